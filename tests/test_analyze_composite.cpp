// analyze --composite and simulate --bias composite (issue 16, "use
// everywhere"): on a record of the paper's gyro the composite model fits the
// Allan curve at the white-noise arm and at the bias-instability minimum,
// where the paper's eq. (3) model cannot fit both; a fit written to
// analysis.json, simulated at another rate and fitted again gives its
// physical quantities back within their bootstrap spread; analysis.json
// with the composite model reads back identically; simulate takes the
// model from analysis.json and from `cubecal model`'s JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/analyze_stream.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/report/analysis_report.hpp"
#include "cubecal/sim/composite_noise.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/sim/simulator.hpp"

namespace cubecal {
namespace {

constexpr double kPaperRate = 10.0;

// The paper's gyro, x axis (docs/paper.md §3.1): the SPORT gyro's white
// noise sigma_n = 13.9e-3 deg/s and quantizer (145.6 LSB/(deg/s),
// truncation), with what its model misses: a Gauss-Markov process
// (sigma_b 5.4e-3 deg/s, T_c 1.3 s) and a slower bias random walk (sigma_mu
// 1.46e-3 deg/s^2). Their Allan curve passes through the paper's measured
// N = 0.3218 deg/sqrt(h) at 1 s and has its minimum B = 12.68 deg/h near
// T = 34.2 s (to within 4 %), while its short-tau white arm is the paper's
// model row, N = 0.2683 deg/sqrt(h): the model tangent to that arm with the
// same minimum is the paper's eq. (3) fit.
TriadModel paper_gyro(double rate_hz) {
  TriadModel m = preset("sport-gyro");
  m.axis_names = {"gx", "", ""};
  AxisModel& x = m.axes[0];
  x.turn_on_sigma = 0.0;
  x.bias_sigma = 1.46e-3;
  x.composite.processes = {gm_process(1.3, 5.4e-3, 1.0 / kPresetRateHz)};
  return pipeline::model_at_rate(m, kPresetRateHz, rate_hz);
}

io::Series series_of(const pipeline::SimulatedRecord& rec, std::size_t channels) {
  io::Series s;
  s.file = "paper-gyro";
  s.rate_hz = rec.rate_hz;
  s.tau0 = 1.0 / rec.rate_hz;
  for (std::size_t c = 0; c < channels; ++c) {
    s.names.push_back(rec.names[c]);
    s.channels.push_back(rec.channels[c]);
  }
  s.segments = {{0, s.channels[0].size()}};
  return s;
}

io::Series record(const std::vector<TriadModel>& triads, double rate_hz, double hours, std::uint64_t seed) {
  pipeline::SimulateRequest req;
  req.triads = triads;
  req.rate_hz = rate_hz;
  req.duration_s = hours * 3600.0;
  req.seed = seed;
  req.temperature_column = false;
  const pipeline::SimulatedRecord rec = pipeline::simulate(req);
  std::size_t axes = 0;
  for (const auto& t : triads)
    for (const auto& a : t.axis_names) axes += a.empty() ? 0 : 1;
  return series_of(rec, axes);
}

pipeline::AnalyzeRequest composite_request(const std::string& model, std::size_t bootstrap, double ci) {
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s")};
  req.grid = parse_tau_grid("log:10");
  req.ci = ci;
  pipeline::ModelRequest m;
  m.model = model;
  m.bootstrap = bootstrap;
  req.composite = m;
  req.composite_required = true;  // a model asked for: refused where it cannot be made
  return req;
}

// Whether a model's Allan deviation at the curve's point lies in its interval.
bool inside(double model_dev, const StabilityPoint& p) {
  return model_dev >= p.interval.lo && model_dev <= p.interval.hi;
}

TEST(AnalyzeComposite, PaperGyroFitsTheWhiteArmAndTheMinimumWhereEquationThreeCannot) {
  // 72 h at 10 Hz, as the paper's static test; the curve at 95 %.
  const io::Series s = record({paper_gyro(kPaperRate)}, kPaperRate, 72.0, 16);
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, composite_request("WN+GM+RW", 0, 0.95));
  const pipeline::ChannelAnalysis& c = r.channels[0];
  ASSERT_TRUE(c.model.ok) << c.model.error;
  ASSERT_TRUE(c.model.composite);
  const std::vector<StabilityPoint>& curve = c.noise.adev;
  const double dt = 1.0 / kPaperRate;
  const auto factor = [&](const StabilityPoint& p) { return static_cast<std::size_t>(std::llround(p.tau / dt)); };
  const auto composite_dev = [&](const StabilityPoint& p) {
    return std::sqrt(avar(c.model.composite->fit.model, factor(p)));
  };
  const auto paper_dev = [&](const StabilityPoint& p) { return std::sqrt(avar(c.model.random_walk, factor(p))); };

  // The record is the paper's gyro: its curve at 1 s is the paper's measured
  // N (sigma(1 s) 60 in deg/sqrt(h)), its minimum the measured B.
  const auto at_1s =
      std::find_if(curve.begin(), curve.end(), [](const auto& p) { return std::abs(p.tau - 1.0) < 1e-9; });
  ASSERT_NE(at_1s, curve.end());
  const Quantity B = display(c.noise.readoffs.B, Term::B, c.unit);
  std::printf(
      "  record: sigma(1 s) 60 = %.4f deg/sqrt(h), B %.3f %s, T %.3g s (the paper: 0.3218, 12.68, 34.2); "
      "N read on the white arm %.4f\n",
      at_1s->dev * 60.0, B.value, B.unit.c_str(), c.noise.readoffs.tau_min,
      display(c.noise.readoffs.N, Term::N, c.unit).value);
  EXPECT_NEAR(at_1s->dev * 60.0 / 0.3218, 1.0, 0.05);
  EXPECT_NEAR(B.value / 12.6832, 1.0, 0.10);

  // The white arm: the points N is read over (within 2x of 1 s); the minimum: the curve's lowest point.
  std::vector<std::size_t> arm;
  for (std::size_t i = 0; i < curve.size(); ++i)
    if (curve[i].tau >= 0.5 && curve[i].tau <= 2.0) arm.push_back(i);
  ASSERT_GE(arm.size(), 3u);
  const auto lowest =
      std::min_element(curve.begin(), curve.end(), [](const auto& a, const auto& b) { return a.dev < b.dev; });
  const std::size_t imin = static_cast<std::size_t>(lowest - curve.begin());
  ASSERT_GT(imin, arm.back());
  ASSERT_LT(imin + 1, curve.size());

  std::size_t composite_arm = 0, paper_arm = 0;
  for (const std::size_t i : arm) {
    composite_arm += inside(composite_dev(curve[i]), curve[i]);
    paper_arm += inside(paper_dev(curve[i]), curve[i]);
  }
  const StabilityPoint& m = curve[imin];
  std::printf("  tau 1 s: measured %.5g [%.5g, %.5g], composite %.5g, eq. (3) %.5g deg/s\n",
              curve[arm[arm.size() / 2]].dev, curve[arm[arm.size() / 2]].interval.lo,
              curve[arm[arm.size() / 2]].interval.hi, composite_dev(curve[arm[arm.size() / 2]]),
              paper_dev(curve[arm[arm.size() / 2]]));
  std::printf("  minimum at %.4g s: measured %.5g [%.5g, %.5g], composite %.5g, eq. (3) %.5g deg/s\n", m.tau, m.dev,
              m.interval.lo, m.interval.hi, composite_dev(m), paper_dev(m));
  std::printf(
      "  white arm: composite inside at %zu of %zu points, eq. (3) at %zu; model %s, residual %.4f vs "
      "eq. (3) %.4f\n",
      composite_arm, arm.size(), paper_arm, c.model.composite->model.c_str(), c.model.composite_residual.rms_log,
      c.model.random_walk_residual.rms_log);
  // The composite model: inside the measured intervals over the whole white arm and at the minimum.
  EXPECT_EQ(composite_arm, arm.size());
  EXPECT_TRUE(inside(composite_dev(m), m));
  // Eq. (3), tangent to the arm with the same minimum value: below the arm
  // where N is read, and its V too sharp at the minimum's tau.
  EXPECT_EQ(paper_arm, 0u);
  EXPECT_FALSE(inside(paper_dev(m), m));
  EXPECT_LT(c.model.composite_residual.rms_log, c.model.random_walk_residual.rms_log);
}

double quantity(const pipeline::ModelChannel& c, ProcessKind kind, const std::string& name, bool sd = false) {
  for (const auto& t : c.terms)
    if (t.kind == kind)
      for (const auto& q : t.quantities)
        if (q.name == name) return sd ? q.sd : q.value;
  ADD_FAILURE() << "no " << name;
  return NAN;
}

TEST(AnalyzeComposite, SimulatedAtAnotherRateTheFitComesBackWithinItsSpread) {
  // Fit at 10 Hz (12 h, bootstrap 40), through analysis.json, simulated at
  // 40 Hz by simulate's composite path and fitted again (bootstrap 40): each
  // of N, sigma_b, T_c, K within 3 combined bootstrap sigmas.
  const io::Series s = record({paper_gyro(kPaperRate)}, kPaperRate, 12.0, 3);
  const pipeline::AnalysisResult first = pipeline::run_analyze(s, composite_request("WN+GM+RW", 40, 0.683));
  const std::string text = pipeline::analysis_json(first, {"cubecal analyze test", "/imu0"});
  const pipeline::AnalysisDocument doc = pipeline::parse_analysis_json(text, "analysis.json");
  const double rate = 40.0;
  const std::vector<TriadModel> twins = pipeline::models_from_composite(doc.result, "analysis.json", rate);
  ASSERT_EQ(twins.size(), 1u);
  EXPECT_EQ(twins[0].axis_names[0], "gx");
  EXPECT_EQ(twins[0].axes[0].white_sigma, 0.0);
  EXPECT_EQ(twins[0].lsb, 0.0);
  EXPECT_DOUBLE_EQ(twins[0].axes[0].fixed_bias, first.channels[0].mean);
  const io::Series again = record(twins, rate, 12.0, 4);
  EXPECT_EQ(again.samples(), static_cast<std::size_t>(12 * 3600 * rate));
  const pipeline::AnalysisResult second = pipeline::run_analyze(again, composite_request("WN+GM+RW", 40, 0.683));
  const pipeline::ModelChannel& a = *first.channels[0].model.composite;
  const pipeline::ModelChannel& b = *second.channels[0].model.composite;
  ASSERT_GE(a.replicates, 30u);
  ASSERT_GE(b.replicates, 30u);
  const struct {
    ProcessKind kind;
    const char* name;
  } quantities[] = {
      {ProcessKind::wn, "N"}, {ProcessKind::gm, "sigma_b"}, {ProcessKind::gm, "T_c"}, {ProcessKind::rw, "K"}};
  for (const auto& q : quantities) {
    const double x = quantity(a, q.kind, q.name), y = quantity(b, q.kind, q.name);
    const double spread = std::hypot(quantity(a, q.kind, q.name, true), quantity(b, q.kind, q.name, true));
    std::printf("  %-8s 10 Hz %.5g, 40 Hz %.5g: %+.2f combined sigmas\n", q.name, x, y, (y - x) / spread);
    EXPECT_GT(spread, 0.0);
    EXPECT_LT(std::abs(y - x), 3.0 * spread) << q.name;
  }
}

TEST(AnalyzeComposite, AnalysisJsonReadsBackIdentically) {
  const io::Series s = record({paper_gyro(kPaperRate)}, kPaperRate, 1.0, 5);
  pipeline::AnalyzeRequest req = composite_request("WN+RW, WN+GM+RW", 4, 0.9);
  req.composite->selection_replicates = 4;
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, req);
  ASSERT_TRUE(r.composite);
  const pipeline::ModelChannel& c = *r.channels[0].model.composite;
  EXPECT_EQ(c.candidates.size(), 2u);
  EXPECT_EQ(r.composite->selection_replicates, 4u);
  EXPECT_EQ(r.composite->bootstrap, 4u);
  // The drift series live in drift.csv, not in analysis.json.
  pipeline::AnalysisResult written = r;
  for (auto& ch : written.channels) {
    ch.drift.t.clear();
    ch.drift.drift.clear();
  }
  const nlohmann::json j = pipeline::to_json(written);
  const pipeline::AnalysisResult back = pipeline::analysis_result_from_json(j, "analysis.json");
  EXPECT_EQ(pipeline::to_json(back), j);
  ASSERT_TRUE(back.channels[0].model.composite);
  const pipeline::ModelChannel& d = *back.channels[0].model.composite;
  EXPECT_EQ(d.model, c.model);
  EXPECT_EQ(model_name(d.fit.model), model_name(c.fit.model));
  for (std::size_t p = 0; p < c.fit.model.processes.size(); ++p) {
    EXPECT_EQ(d.fit.model.processes[p].value, c.fit.model.processes[p].value);
    EXPECT_EQ(d.fit.model.processes[p].phi, c.fit.model.processes[p].phi);
  }
  EXPECT_EQ(back.channels[0].model.composite_residual.rms_log, r.channels[0].model.composite_residual.rms_log);
  // The intervals are the analysis's: at its ci.
  EXPECT_LT(c.wv.interval[0].lo, c.wv.nu2[0]);
  // adev.csv: the composite model's column, its AVAR 2 nu2(2m) at each tau.
  const std::string csv = pipeline::adev_csv(r);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "channel,tau,n,dev,lo,hi,edf,alpha,fit_dev,model_dev,gauss_markov_dev,composite_dev");
  // Without --composite neither key nor column.
  pipeline::AnalyzeRequest plain = req;
  plain.composite.reset();
  const pipeline::AnalysisResult p = pipeline::run_analyze(s, plain);
  const nlohmann::json pj = pipeline::to_json(p);
  EXPECT_FALSE(pj.contains("composite"));
  EXPECT_FALSE(pj["channels"][0]["model"].contains("composite"));
  EXPECT_EQ(pipeline::adev_csv(p).find("composite"), std::string::npos);
}

TEST(AnalyzeComposite, ReportDrawsEachTermAndTheirSumOverTheMeasuredCurve) {
  const io::Series s = record({paper_gyro(kPaperRate)}, kPaperRate, 2.0, 7);
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, composite_request("WN+GM+RW", 0, 0.683));
  const report::CommandReport page = report::analysis_report(r, {"cubecal analyze test", ""}, "out");
  const report::ReportSection* section = nullptr;
  for (const auto& sec : page.sections)
    if (sec.id == "composite") section = &sec;
  ASSERT_NE(section, nullptr);
  const report::ReportBlock* block = nullptr;
  for (const auto& b : section->blocks)
    if (b.table) block = &b;
  ASSERT_NE(block, nullptr);
  // The table: one row per quantity, N, sigma_b, T_c, K, each with its asymptotic sigma.
  const pipeline::ModelChannel& c = *r.channels[0].model.composite;
  ASSERT_EQ(block->table->rows.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NE(block->table->rows[i][3], "—") << block->table->rows[i][1];
  EXPECT_EQ(block->table->rows[0][1], "N");
  EXPECT_EQ(block->table->rows[3][1], "K");
  // The figure: the measured curve with intervals, the fitted scales, one
  // line per term and the model, whose variance is the terms' sum.
  ASSERT_EQ(block->figures.size(), 1u);
  const report::Plot& plot = block->figures[0].plot;
  EXPECT_EQ(plot.name, "composite_gx");
  ASSERT_EQ(plot.series.size(), 2 + c.terms.size() + 1);
  EXPECT_EQ(plot.series[0].mark, report::Mark::errorlines);
  EXPECT_EQ(plot.series[0].x.size(), r.channels[0].noise.adev.size());
  EXPECT_EQ(plot.series[1].x.size(), c.wv.size());
  const report::PlotSeries& total = plot.series.back();
  for (std::size_t i = 0; i < total.x.size(); ++i) {
    double sum = 0.0;
    for (std::size_t t = 0; t < c.terms.size(); ++t) {
      const report::PlotSeries& term = plot.series[2 + t];
      const auto at = std::find(term.x.begin(), term.x.end(), total.x[i]);
      if (at != term.x.end()) sum += std::pow(term.y[static_cast<std::size_t>(at - term.x.begin())], 2);
    }
    EXPECT_NEAR(std::sqrt(sum) / total.y[i], 1.0, 1e-12) << total.x[i];
  }
  // And the Allan figure of the group carries the model beside the other two.
  bool in_allan = false;
  for (const auto& sec : page.sections)
    for (const auto& b : sec.blocks)
      for (const auto& f : b.figures)
        if (f.plot.name.rfind("allan_", 0) == 0)
          for (const auto& ser : f.plot.series) in_allan = in_allan || ser.id == "gx composite model";
  EXPECT_TRUE(in_allan);
}

TEST(AnalyzeComposite, RefusedWhereItCannotBeMade) {
  pipeline::AnalyzeRequest req = composite_request("WN+RW", 0, 0.683);
  try {
    pipeline::check_analyze_streamable(req, true);
    FAIL() << "a streamed analysis took the composite model";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::composite);
  }
  // A record cut at gaps, with no head to fit on.
  io::Series s = record({paper_gyro(kPaperRate)}, kPaperRate, 0.5, 6);
  s.segments = {{0, 9000}, {9000, s.samples()}};
  EXPECT_THROW((void)pipeline::run_analyze(s, req), UsageError);
  req.composite->model = "WN+XY";
  EXPECT_THROW((void)pipeline::run_analyze(s, req), UsageError);

  // The default twin is not required: the same record is analysed without
  // it, and the result says why; a stream is let through and says so too.
  pipeline::AnalyzeRequest lenient;
  lenient.units = req.units;
  ASSERT_TRUE(lenient.composite && pipeline::is_twin(lenient.composite->model) && !lenient.composite_required);
  EXPECT_NO_THROW(pipeline::check_analyze_streamable(lenient, true));
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, lenient);
  EXPECT_FALSE(r.composite);
  EXPECT_FALSE(r.channels[0].model.composite);
  EXPECT_NE(r.composite_skipped.find("pieces at gaps"), std::string::npos) << r.composite_skipped;
  // Too short for any model (2 wavelet-variance scales): skipped, said why.
  io::Series tiny = record({paper_gyro(kPaperRate)}, kPaperRate, 0.5, 6);
  for (auto& y : tiny.channels) y.resize(10);
  if (!tiny.time.empty()) tiny.time.resize(10);
  tiny.segments = {{0, 10}};
  const pipeline::AnalysisResult t = pipeline::run_analyze(tiny, lenient);
  EXPECT_FALSE(t.channels[0].model.composite);
  EXPECT_FALSE(t.composite_skipped.empty());
}

TEST(CompositeNoise, AtAnyPeriodKeepsThePhysicalQuantities) {
  CompositeModel m = parse_composite_model("WN+QN+RW+DR+GM");
  const double dt = 0.1, to = 0.004;
  m.processes[0].value = 2.0e-4;
  m.processes[1].value = 3.0e-6;
  m.processes[2].value = 1.0e-9;
  m.processes[3].value = -2.0e-7;
  m.processes[4] = gm_process(30.0, 1.0e-3, dt);
  const CompositeModel n = composite_at_period(m, dt, to);
  // N^2 = sigma2 dt, Q = sqrt(Q2) dt, K^2 = gamma2 / dt, R = omega / dt.
  EXPECT_NEAR(n.processes[0].value * to, m.processes[0].value * dt, 1e-15);
  EXPECT_NEAR(std::sqrt(n.processes[1].value) * to, std::sqrt(m.processes[1].value) * dt, 1e-15);
  EXPECT_NEAR(n.processes[2].value / to, m.processes[2].value / dt, 1e-15);
  EXPECT_NEAR(n.processes[3].value / to, m.processes[3].value / dt, 1e-15);
  const GaussMarkovTerm g = gauss_markov_term(n.processes[4], to);
  EXPECT_NEAR(g.tau_c, 30.0, 1e-9);
  EXPECT_NEAR(g.sigma_b, 1.0e-3, 1e-15);
  // The Allan variance at the same tau is the same at both rates where the
  // discrete forms agree with the continuous ones (tau >> both periods).
  const double tau = 100.0;
  const double a = avar(m, static_cast<std::size_t>(tau / dt)), b = avar(n, static_cast<std::size_t>(tau / to));
  EXPECT_NEAR(b / a, 1.0, 2e-3);
  EXPECT_THROW((void)composite_at_period(m, 0.0, to), std::invalid_argument);
}

TEST(CompositeNoise, BlocksGiveTheSameSamplesAndTheExactAllanVariance) {
  CompositeModel m = parse_composite_model("WN+QN+RW+GM");
  m.processes[0].value = 1.0;
  m.processes[1].value = 0.5;
  m.processes[2].value = 1e-4;
  m.processes[3] = gm_process(50.0, 2.0, 1.0);
  const std::size_t n = 1 << 20;
  std::vector<double> whole(n, 0.0), pieces(n, 0.0);
  CompositeNoise(m, 9).add_next(whole);
  CompositeNoise g(m, 9);
  for (std::size_t k = 0; k < n;) {
    const std::size_t len = std::min<std::size_t>(n - k, 1 + (k * 7919) % 70001);
    g.add_next(std::span<double>(pieces.data() + k, len));
    k += len;
  }
  EXPECT_EQ(whole, pieces);
  // Seeded records against the exact Allan variance at m = 8: the mean over
  // 40 seeds within 3 standard errors.
  const std::size_t af = 8, len = 1 << 16;
  std::vector<double> v;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::vector<double> y(len, 0.0);
    CompositeNoise(m, seed).add_next(y);
    double sum = 0.0;
    std::size_t terms = 0;
    for (std::size_t i = 0; i + 2 * af <= len; ++i) {
      double d = 0.0;
      for (std::size_t j = 0; j < af; ++j) d += y[i + af + j] - y[i + j];
      d /= static_cast<double>(af);
      sum += 0.5 * d * d;
      ++terms;
    }
    v.push_back(sum / static_cast<double>(terms));
  }
  double mean = 0.0, var = 0.0;
  for (double x : v) mean += x / static_cast<double>(v.size());
  for (double x : v) var += (x - mean) * (x - mean) / static_cast<double>(v.size() - 1);
  EXPECT_LT(std::abs(mean - avar(m, af)), 3.0 * std::sqrt(var / static_cast<double>(v.size())))
      << mean << " vs " << avar(m, af);
}

class CompositeCli : public test::TempDirTest {};

// A composite model the GMWM cannot fit is said as such, with the file and
// a hint (it used to be relabelled as a missing sample).
TEST_F(CompositeCli, NoCandidateThatFitsIsACalibrationError) {
  using test::run_cubecal;
  const std::string rec = (dir_ / "short.csv").string();
  ASSERT_EQ(run_cubecal("simulate --preset sport-gyro --rate 10 --duration 200s --seed 3 --out " + rec).code, 0);
  // 10 and 11 parameters, 9 scales: no candidate gives a fit.
  const test::CliRun r =
      run_cubecal("analyze " + rec + " --columns gx --unit deg/s --composite WN+4*GM+RW,WN+QN+4*GM+RW");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cubecal: error: " + rec + ": GMWM: no candidate model gave a fit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(give --composite a model with fewer terms)\n"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("missing sample"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("needs every sample"), std::string::npos) << r.err;
}

TEST_F(CompositeCli, SimulateTakesTheModelOfAnalyzeAndOfModel) {
  using test::run_cubecal;
  const std::string rec = path("gyro.csv"), out = path("a");
  ASSERT_EQ(run_cubecal("simulate --preset sport-gyro --rate 10 --duration 2h --seed 3 --out " + rec).code, 0);
  test::CliRun r = run_cubecal("analyze " + rec + " --columns gx,gy --unit deg/s --composite WN+RW --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("composite WN+RW"), std::string::npos) << r.out;
  // From analysis.json: the composite model at another rate.
  r = run_cubecal("simulate --model " + out +
                  "/analysis.json --bias composite --rate 25 --duration 60s --seed 2 "
                  "--temp const:20 --out " +
                  path("twin.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream twin(path("twin.csv"));
  std::string header, line;
  std::getline(twin, header);
  EXPECT_EQ(header, "t,gx,gy,temp");
  std::size_t rows = 0;
  while (std::getline(twin, line)) ++rows;
  EXPECT_EQ(rows, 1500u);
  // From `cubecal model --format json`: composite without --bias, at the fit's rate.
  r = run_cubecal("model " + rec + " --columns gx --unit deg/s --model WN+RW --format json --out " + path("m.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cubecal("simulate --model " + path("m.json") + " --duration 30s --out " + path("m.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("300 samples at 10 Hz"), std::string::npos) << r.err;
  // Refusals: one line each.
  EXPECT_TRUE(test::one_error_line(
      run_cubecal("simulate --model " + path("m.json") + " --bias random-walk --duration 30s --out " + path("x.csv"))));
  ASSERT_EQ(run_cubecal("analyze " + rec + " --columns gx --unit deg/s --composite none --out " + path("plain")).code,
            0);
  EXPECT_TRUE(test::one_error_line(run_cubecal(
      "simulate --model " + path("plain") + "/analysis.json --bias composite --duration 30s --out " + path("y.csv"))));
  // Without --bias an analysis without a twin gives the paper's model, said so.
  r = run_cubecal("simulate --model " + path("plain") + "/analysis.json --duration 30s --out " + path("z.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("holds no twin"), std::string::npos) << r.err;
  EXPECT_TRUE(test::one_error_line(run_cubecal("analyze " + rec + " --columns gx --unit deg/s --composite --stream")));
  EXPECT_TRUE(test::one_error_line(run_cubecal("analyze " + rec + " --columns gx --unit deg/s --composite WN+XY")));
}

// The twin end to end: analyze fits it by default and writes it with its
// twin error, --twin-check and the simulator exports; the report and
// simulate read it back from analysis.json; simulate takes it by default,
// the paper's model on request.
TEST_F(CompositeCli, TheTwinByDefaultFromAnalyzeToSimulateAndTheSimulators) {
  using test::run_cubecal;
  const std::string rec = path("imu.csv"), out = path("t");
  ASSERT_EQ(run_cubecal("simulate --preset sport-gyro --rate 10 --duration 3h --seed 5 --out " + rec).code, 0);
  test::CliRun r = run_cubecal("analyze " + rec +
                               " --columns gx,gy,gz --unit deg/s --twin-check 2 --for gazebo,navego "
                               "--out " +
                               out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("twin: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("twin check 2 twins"), std::string::npos) << r.out;
  std::ifstream in(out + "/analysis.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["composite"]["model"], "twin");
  for (const auto& ch : j["channels"]) {
    const auto& c = ch["model"]["composite"];
    // The paper's gyro is white noise and a random walk: so is its twin,
    // inside the intervals, within a few percent of the curve to 10 s.
    EXPECT_EQ(c["model"], "WN+RW") << ch["name"];
    EXPECT_TRUE(c["fidelity"]["faithful"].get<bool>());
    EXPECT_LT(c["twin_error"]["max_error_10s"].get<double>(), 0.05);
    EXPECT_GE(c["twin_error"]["taus"].get<std::size_t>(), 30u);  // the log:10 curve of 3 h at 10 Hz
  }
  ASSERT_EQ(j["twin_check"]["channels"].size(), 3u);
  for (const auto& t : j["twin_check"]["channels"]) EXPECT_LT(t["max_error_10s"].get<double>(), 0.1) << t["name"];
  ASSERT_EQ(j["estimator_files"]["simulator_projections"].size(), 6u);  // 2 targets x 3 axes
  for (const auto& p : j["estimator_files"]["simulator_projections"]) {
    // The error to 10 s is over fewer scales than that to 100 s, and that one than every scale's.
    EXPECT_LE(p["twin_error_10s"].get<double>(), p["twin_error_100s"].get<double>());
    EXPECT_LE(p["twin_error_100s"].get<double>(), p["twin_error"].get<double>());
    // NaveGo holds white noise and a random walk, the whole of these twins.
    if (p["target"] == "navego") {
      EXPECT_LT(p["twin_error"].get<double>(), 0.01) << p["channel"];
    }
  }
  for (const char* f : {"/gazebo_imu_noise.sdf", "/navego_imu.m"}) EXPECT_TRUE(std::ifstream(out + f).good()) << f;
  // Read back: the report of the directory, and the twin simulated by default.
  r = run_cubecal("report " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::ifstream(out + "/report.html").good());
  r = run_cubecal("simulate --model " + out + "/analysis.json --duration 2h --seed 9 --out " + path("twin.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("holds no twin"), std::string::npos) << r.err;
  r = run_cubecal("analyze " + path("twin.csv") + " --columns gx,gy,gz --unit deg/s --composite none --out " +
                  path("u"));
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream again(path("u") + "/analysis.json");
  const nlohmann::json k = nlohmann::json::parse(again);
  // The twin's record has the record's white level (N within 3 %).
  for (std::size_t c = 0; c < 3; ++c) {
    const double n0 = j["channels"][c]["model"]["sigma_n"].get<double>();
    const double n1 = k["channels"][c]["model"]["sigma_n"].get<double>();
    EXPECT_NEAR(n1 / n0, 1.0, 0.03) << c;
  }
  // A simulator export without a twin is refused before the work.
  EXPECT_TRUE(test::one_error_line(
      run_cubecal("analyze " + rec + " --columns gx --unit deg/s --composite none --for gazebo --out " + path("v"))));
}

// With a temperature: the record's twin refitted to the compensated series
// is written and read back, and simulate adds the temperature term to it
// once: the twin's record gives the coefficient back.
TEST_F(CompositeCli, TheTwinWithATemperatureSimulatesItsCoefficientOnce) {
  using test::run_cubecal;
  const std::string rec = path("mag.csv"), out = path("m");
  ASSERT_EQ(
      run_cubecal("simulate --preset sport-mag --rate 10 --duration 24h --temp sine:25,5,21600 --seed 4 --out " + rec)
          .code,
      0);
  test::CliRun r = run_cubecal("analyze " + rec + " --columns mx --unit mGauss --temp-col temp --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(out + "/analysis.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const auto& t = j["channels"][0]["temperature"];
  ASSERT_TRUE(t["compensated_model"].contains("composite")) << t["compensated_model"].dump();
  const double coeff = t["coeff"][0].get<double>();
  EXPECT_NEAR(coeff, 0.7, 0.05);
  r = run_cubecal("simulate --model " + out + "/analysis.json --duration 24h --temp sine:25,5,21600 --seed 8 --out " +
                  path("twin.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run_cubecal("analyze " + path("twin.csv") + " --columns mx --unit mGauss --temp-col temp --out " + path("n"));
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream again(path("n") + "/analysis.json");
  const nlohmann::json k = nlohmann::json::parse(again);
  const auto& t2 = k["channels"][0]["temperature"];
  EXPECT_NEAR(t2["coeff"][0].get<double>(), coeff, 3.0 * t2["coeff_sigma"][0].get<double>() + 0.02);
  // And the compensated curves agree at every tau to 1000 s: the twin of the
  // record itself (which carries the temperature's swing as noise) under
  // the temperature term would stand far above from minutes on.
  const auto& a0 = t["compensated"]["adev"];
  const auto& a1 = t2["compensated"]["adev"];
  ASSERT_EQ(a0["tau"].size(), a1["tau"].size());
  for (std::size_t i = 0; i < a0["tau"].size(); ++i) {
    if (a0["tau"][i].get<double>() > 1000.0) break;
    EXPECT_NEAR(a1["dev"][i].get<double>() / a0["dev"][i].get<double>(), 1.0, 0.25) << a0["tau"][i];
  }
}

}  // namespace
}  // namespace cubecal
