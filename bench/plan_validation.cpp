// The record plan validated by Monte Carlo (issue 35, item 2;
// docs/planning.md). For each sensor model: the plan (plan_duration for
// targets chosen per model, and plan_precision at a fixed length such as the
// paper's 72 h), then K seeded records of that length from the project's
// simulator (TriadSimulator), each analysed as `cubecal analyze` analyses a
// record: the OADEV curve with intervals (run_dev with analyze's request:
// log:10, ci, conservative_short), read_off_noise_terms, fit_noise_terms and
// reported_terms, the numbers analyze states. The first record of every run
// is also put through pipeline::run_analyze itself, and the program stops if
// a number differs. Per term it prints a Markdown row:
//
//   plan       the plan's precision (relative half-width at the ci; 1 sigma at 0.683)
//   spread     over the records that resolve the term, in the plan's own
//              statistic (docs/formulas/planning.md §0, §3), times z_ci: N, K
//              sd / mean; B half the central 68.3 % interval over the median;
//              T half the central 68.3 % interval of ln T, each record's T
//              uniform over its tau's cell; with its Monte Carlo standard
//              error (sd: from the fourth moment; intervals: 400 bootstrap
//              resamples)
//   MC sd      sd / mean (T: sd of ln T), for comparison
//   stated     the mean over those records of the uncertainty analyze
//              states, relative: sigma / value (T: T_rel_sigma), with its
//              standard error
//   ratios     spread / plan and stated / plan, "yes" when within 15 %
//   unresolved the share of records in which analyze does not report the
//              term (B, T: no minimum within the record; K: not significant,
//              an upper bound; N: no -1/2 region)
//
//   cubecal_plan_validation [--records K] [--seed S] [--only NAME] [--threads T]
//                           [--adis FILE] [--ci C] [--plan-only] [--paper]
//
// K (default 200) is the number of records of a run (a case may cap it; the
// table's records column states it). The three axes of a simulated triad carry the
// same axis model on streams of their own, so one simulation gives three
// independent records. Record r of a run is axis r % 3 of the triad seeded
// S + r / 3. --only runs the cases whose name contains NAME. --adis is the
// ADIS16405 record the ADIS models are fitted to (default
// ../shared/data/imu/adis16405/run1.csv.gz beside the source tree).
// --plan-only prints the plans without simulating; --paper the plan of the
// paper's 72 h for every axis of both presets and the length B:10 % needs.
#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/record_plan.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/sim/model_allan_variance.hpp"
#include "cubecal/sim/power_law_noise.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/sim/simulator.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/io/series.hpp"
#include "../tests/plan_statistics.hpp"

#ifndef CUBECAL_SHARED_DATA
#define CUBECAL_SHARED_DATA "../shared/data"
#endif

namespace {

using namespace cubecal;

constexpr double kWithin = 0.15;  // the bound on spread / plan - 1 and stated / plan - 1
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Options {
  std::size_t records = 200;
  std::uint64_t seed = 1;
  std::string only;
  int threads = 2;
  double ci = 0.683;
  std::string adis = std::string(CUBECAL_SHARED_DATA) + "/imu/adis16405/run1.csv.gz";
  bool plan_only = false;  // print the plans only, simulate nothing
  bool paper = false;      // print the paper's 72 h plan for every preset axis
};

// One sensor model and what is planned for it.
struct Case {
  std::string name;       // e.g. "sport-gyro x"
  AxisModel axis;         // the axis simulated (on all three axes of the triad)
  TriadModel triad;       // its triad (quantizer, unit); axes replaced by `axis`
  double rate_hz = 10.0;  // sampling rate
  std::vector<PlanTarget> targets;
  std::vector<double> fixed_s;  // lengths planned with plan_precision (the paper's 72 h)
  std::size_t max_records = 0;  // cap on K for this case's runs (0: none)
  double max_samples = 4e7;     // longest record simulated (samples); longer plans are listed, not run
};

// One record's reported terms, as analyze states them.
struct RecordTerms {
  double value[4] = {0, 0, 0, 0};   // N, B, K, T
  double stated[4] = {0, 0, 0, 0};  // relative 1 sigma at the ci: sigma / value (T: T_rel_sigma, in ln tau)
  bool resolved[4] = {false, false, false, false};
  double t_cell[2] = {0, 0};  // ln tau of T's cell on the record's grid (half-way to the neighbouring taus)
};

constexpr PlanTerm kTerms[4] = {PlanTerm::N, PlanTerm::B, PlanTerm::K, PlanTerm::T};
int slot_of(PlanTerm t) {
  for (int i = 0; i < 4; ++i)
    if (kTerms[i] == t) return i;
  throw std::invalid_argument("term not validated");
}

// analyze's request for the Allan curve (src/pipeline/detail/analysis_parts.cpp, oadev_request).
pipeline::DevRequest oadev_request(double ci) {
  pipeline::DevRequest d;
  d.stat = Stat::oadev;
  d.type = DataType::freq;
  d.grid = TauGrid{TauGrid::Kind::log, 10, {}};
  d.options.ci = ci;
  d.options.conservative_short = true;
  d.threads = 1;
  return d;
}

// The cell of the point at tau T on the curve: half-way in ln tau to its neighbours (docs/formulas/planning.md §3).
void t_cell(const AllanCurve& c, double T, double cell[2]) {
  const auto it = std::find(c.tau.begin(), c.tau.end(), T);
  if (it == c.tau.end()) return;
  const auto i = static_cast<std::size_t>(it - c.tau.begin());
  const double l = std::log(T);
  cell[0] = i > 0 ? 0.5 * (l + std::log(c.tau[i - 1])) : l;
  cell[1] = i + 1 < c.size() ? 0.5 * (l + std::log(c.tau[i + 1])) : l;
}

// The terms of a record as analyze reports them (reported_terms.hpp): N, B,
// K with their sigmas when not an upper bound; T and T_rel_sigma when the
// curve has a minimum inside.
RecordTerms terms_of(const ReportedTerms& rep, const AllanCurve& curve) {
  RecordTerms t;
  const auto put = [&](int i, const ReportedTerm& r) {
    t.resolved[i] = !r.bound() && r.estimate.valid && r.value() > 0.0;
    t.value[i] = r.value();
    t.stated[i] = r.value() > 0.0 ? r.estimate.sigma / r.value() : 0.0;
  };
  put(0, rep.N);
  put(1, rep.B);
  put(2, rep.K);
  t.resolved[3] = !rep.no_minimum && rep.T > 0.0;
  t.value[3] = rep.T;
  t.stated[3] = rep.T_rel_sigma;
  if (t.resolved[3]) t_cell(curve, rep.T, t.t_cell);
  return t;
}

RecordTerms terms_of_curve(const std::vector<StabilityPoint>& points) {
  const AllanCurve curve = to_allan_curve(points);
  const SlopeReadOffs ro = read_off_noise_terms(curve);
  const NoiseFit fit = fit_noise_terms(curve);
  return terms_of(reported_terms(ro, fit, curve), curve);
}

io::Series series_of(std::vector<std::vector<double>> channels, double rate_hz) {
  io::Series s;
  s.file = "<simulated>";
  s.rate_hz = rate_hz;
  s.tau0 = 1.0 / rate_hz;
  s.names = {"a0", "a1", "a2"};
  s.channels = std::move(channels);
  s.segments = {IndexRange{0, s.channels[0].size()}};
  return s;
}

io::Series simulate_triad(const Case& c, std::size_t n, std::uint64_t seed) {
  TriadModel m = c.triad;
  m.axes = {c.axis, c.axis, c.axis};
  TriadSimulator sim(m, 1.0 / c.rate_hz, seed, n);
  std::vector<double> out(3 * n);
  sim.run(n, {}, {}, out);
  std::vector<std::vector<double>> ch(3, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t a = 0; a < 3; ++a) ch[a][i] = out[3 * i + a];
  return series_of(std::move(ch), c.rate_hz);
}

// The three records of one simulation, as the harness reads them.
std::vector<RecordTerms> analyse_triad(const io::Series& s, double ci) {
  const pipeline::DevResult dev = pipeline::run_dev(s, oadev_request(ci));
  std::vector<RecordTerms> out;
  for (const auto& ch : dev.channels) out.push_back(terms_of_curve(ch.points));
  return out;
}

bool same(const RecordTerms& a, const RecordTerms& b) {
  for (int i = 0; i < 4; ++i)
    if (a.resolved[i] != b.resolved[i] || a.value[i] != b.value[i] || a.stated[i] != b.stated[i]) return false;
  return true;
}

// The same records through pipeline::run_analyze (no composite model): the harness must state analyze's numbers.
void check_against_analyze(const io::Series& s, double ci, const std::vector<RecordTerms>& mine) {
  pipeline::AnalyzeRequest req;
  req.units = {Unit{}};
  req.grid = TauGrid{TauGrid::Kind::log, 10, {}};
  req.ci = ci;
  req.composite = std::nullopt;
  req.threads = 1;
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, req);
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const pipeline::NoiseAnalysis& n = r.channels[c].noise;
    const AllanCurve curve = to_allan_curve(n.adev);
    const RecordTerms t = terms_of(reported_terms(n.readoffs, n.fit, curve), curve);
    if (!same(t, mine[c])) throw std::runtime_error("the harness's terms differ from run_analyze's");
  }
}

}  // namespace

namespace {

// A Monte Carlo statistic and its standard error.
struct Estimate {
  double v = kNaN;
  double se = kNaN;
};

using plan_statistics::b_half_width;
using plan_statistics::Moments;
using plan_statistics::moments;
using plan_statistics::t_half_width;

// sd / mean, the mean's error added in quadrature (delta method); `log`: the sd of ln v.
Estimate sd_spread(const std::vector<double>& v, bool log) {
  if (v.size() < 3) return {};
  if (log) {
    std::vector<double> l;
    for (double x : v) l.push_back(std::log(x));
    const Moments m = moments(l);
    return {m.sd, m.sd_se};
  }
  const Moments m = moments(v);
  const double r = m.sd / m.mean;
  return {r, m.sd > 0.0 ? r * std::hypot(m.sd_se / m.sd, 1.0 / std::sqrt(m.n)) : 0.0};
}

// The mean and its standard error sd / sqrt(n).
Estimate mean_of(const std::vector<double>& v) {
  if (v.size() < 3) return {};
  const Moments m = moments(v);
  return {m.mean, m.sd / std::sqrt(m.n)};
}

// A statistic of the records and its bootstrap standard error.
template <class T, class F>
Estimate bootstrapped(const std::vector<T>& v, F statistic) {
  if (v.size() < 3) return {};
  return {statistic(v), plan_statistics::bootstrap_se(v, statistic)};
}

// The records of one run (one model, one length), in record order.
std::vector<RecordTerms> run_records(const Case& c, std::size_t n, std::size_t records, const Options& o) {
  const std::size_t sims = (records + 2) / 3;
  std::vector<std::vector<RecordTerms>> per(sims);
  std::string failure;
#pragma omp parallel for schedule(dynamic, 1) num_threads(o.threads)
  for (std::size_t k = 0; k < sims; ++k) {
    try {
      const io::Series s = simulate_triad(c, n, o.seed + k);
      per[k] = analyse_triad(s, o.ci);
      if (k == 0) check_against_analyze(s, o.ci, per[k]);
    } catch (const std::exception& e) {
#pragma omp critical
      failure = e.what();
    }
  }
  if (!failure.empty()) throw std::runtime_error(c.name + ": " + failure);
  std::vector<RecordTerms> out;
  for (const auto& p : per)
    for (const auto& t : p)
      if (out.size() < records) out.push_back(t);
  return out;
}

std::string pct(double x, int digits = 1) {
  if (!std::isfinite(x)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, "%.*f %%", digits, 100.0 * x);
  return b;
}

std::string num(double x, const char* fmt = "%.3g") {
  if (!std::isfinite(x)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, fmt, x);
  return b;
}

std::string length_text(double s) {
  char b[48];
  if (s >= 86400.0)
    std::snprintf(b, sizeof b, "%.3g d", s / 86400.0);
  else if (s >= 3600.0)
    std::snprintf(b, sizeof b, "%.3g h", s / 3600.0);
  else if (s >= 60.0)
    std::snprintf(b, sizeof b, "%.3g min", s / 60.0);
  else
    std::snprintf(b, sizeof b, "%.3g s", s);
  return b;
}

std::string ratio_cell(double r, double se) {
  if (!std::isfinite(r)) return "—";
  char b[64];
  std::snprintf(b, sizeof b, "%.2f ± %.2f %s", r, se, std::abs(r - 1.0) <= kWithin ? "yes" : "**NO**");
  return b;
}

// z of a two-sided normal interval of probability ci (bisection on erf).
double z_of(double ci) {
  double lo = 0.0, hi = 10.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erf(mid / std::sqrt(2.0)) < ci ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The spread over the records as the plan states the term's precision
// (docs/formulas/planning.md §0, §3), at 1 sigma: N, K sd / mean; B half
// the central 68.3 % interval over the median; T half the central 68.3 %
// interval of ln T, each T uniform over its tau's cell.
Estimate plan_spread(PlanTerm term, const std::vector<RecordTerms>& recs) {
  const int i = slot_of(term);
  std::vector<double> v;
  std::vector<std::array<double, 2>> cells;
  for (const auto& r : recs) {
    if (!r.resolved[i]) continue;
    v.push_back(r.value[i]);
    cells.push_back({r.t_cell[0], r.t_cell[1]});
  }
  if (term == PlanTerm::B) return bootstrapped(v, b_half_width);
  if (term == PlanTerm::T) return bootstrapped(cells, t_half_width);
  return sd_spread(v, false);
}

// One row of the table: the plan of one term at one length against the records.
void print_row(const Case& c, const std::string& why, double length_s, const TermPrecision& plan,
               const std::vector<RecordTerms>& recs, double z) {
  const int i = slot_of(plan.term);
  std::vector<double> values, stated;
  for (const auto& r : recs) {
    if (!r.resolved[i]) continue;
    values.push_back(r.value[i]);
    stated.push_back(r.stated[i]);
  }
  Estimate spread = plan_spread(plan.term, recs);
  spread = {z * spread.v, z * spread.se};
  const Estimate sd = sd_spread(values, plan.term == PlanTerm::T);
  const Estimate st = mean_of(stated);
  const double unresolved = 1.0 - static_cast<double>(values.size()) / static_cast<double>(recs.size());
  const double p = plan.precision;
  std::printf("| %s | %s | %s | %zu | %s | %s | %s | %s | %s ± %s | %s | %s | %s ± %s | %s | %s |\n", c.name.c_str(),
              why.c_str(), length_text(length_s).c_str(), recs.size(), std::string(to_string(plan.term)).c_str(),
              num(plan.value).c_str(), num(mean_of(values).v).c_str(), pct(p).c_str(), pct(spread.v).c_str(),
              pct(spread.se).c_str(), ratio_cell(spread.v / p, spread.se / p).c_str(), pct(z * sd.v).c_str(),
              pct(st.v).c_str(), pct(st.se).c_str(), ratio_cell(st.v / p, st.se / p).c_str(),
              pct(unresolved, 0).c_str());
  std::fflush(stdout);
}

void print_header() {
  std::printf(
      "| model | planned for | length | records | term | plan value | MC mean | plan precision | MC spread | spread / "
      "plan "
      "| MC sd | stated | stated / plan | unresolved |\n");
  std::printf("|---|---|---|---:|---|---:|---:|---:|---:|---|---:|---:|---|---:|\n");
}

}  // namespace

namespace {

TriadModel with_axis(const Case& c) {
  TriadModel m = c.triad;
  m.axes = {c.axis, c.axis, c.axis};
  return m;
}

std::string target_text(const PlanTarget& t) {
  return std::string(to_string(t.term)) + ":" + num(100.0 * t.precision, "%g") + " %";
}

// A row for a plan that is not simulated: why not.
void print_unrun(const Case& c, const std::string& why, const std::string& length, PlanTerm term,
                 const std::string& reason) {
  std::printf("| %s | %s | %s | 0 | %s | — | — | — | — | %s | — | — | — | — |\n", c.name.c_str(), why.c_str(),
              length.c_str(), std::string(to_string(term)).c_str(), reason.c_str());
  std::fflush(stdout);
}

std::size_t records_of(const Case& c, const Options& o) {
  return c.max_records > 0 ? std::min(o.records, c.max_records) : o.records;
}

// Each target's planned length: simulated, and its term compared there.
void run_targets(const Case& c, const PlanModel& model, const PlanOptions& po, const Options& o) {
  for (const TargetPlan& tp : plan_duration(model, c.targets, po)) {
    const std::string why = target_text(tp.target);
    if (tp.at.reason != PlanReason::none || !std::isfinite(tp.duration_s)) {
      print_unrun(c, why, "—", tp.target.term, "not planned: " + tp.at.why);
      continue;
    }
    const auto n = static_cast<std::size_t>(std::llround(tp.duration_s * c.rate_hz));
    if (static_cast<double>(n) > c.max_samples) {
      print_unrun(c, why, length_text(tp.duration_s), tp.target.term, "planned; not simulated (too long here)");
      continue;
    }
    const double length = static_cast<double>(n) / c.rate_hz;
    const PlanTerm term[1] = {tp.target.term};
    const TermPrecision plan = plan_precision(model, length, term, po).front();
    print_row(c, why, length, plan, run_records(c, n, records_of(c, o), o), z_of(o.ci));
  }
}

// The fixed lengths: every term compared.
void run_fixed(const Case& c, const PlanModel& model, const PlanOptions& po, const Options& o) {
  for (const double length_s : c.fixed_s) {
    const auto n = static_cast<std::size_t>(std::llround(length_s * c.rate_hz));
    const double length = static_cast<double>(n) / c.rate_hz;
    const std::vector<TermPrecision> plans = plan_precision(model, length, kTerms, po);
    const std::vector<RecordTerms> recs = run_records(c, n, records_of(c, o), o);
    for (const TermPrecision& p : plans) {
      if (p.reason != PlanReason::none) {
        print_unrun(c, "at " + length_text(length), length_text(length), p.term, "not planned: " + p.why);
        continue;
      }
      print_row(c, "at " + length_text(length), length, p, recs, z_of(o.ci));
    }
  }
}

void run_case(const Case& c, const Options& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const PlanModel model = plan_model(with_axis(c), 0, 1.0 / c.rate_hz);
  PlanOptions po;
  po.ci = o.ci;
  run_targets(c, model, po, o);
  run_fixed(c, model, po, o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr, "%s: %.0f s\n", c.name.c_str(), s);
}

}  // namespace

namespace {

std::vector<PlanTarget> targets(const char* spec) {
  return *spec ? parse_plan_targets(spec) : std::vector<PlanTarget>{};
}

// The paper's sensors at their 10 Hz (sim/presets.hpp): axis `a` of the preset.
Case preset_case(const std::string& name, std::size_t a, const char* spec) {
  Case c;
  c.triad = preset(name);
  c.name = name + " " + c.triad.axis_names[a];
  c.axis = c.triad.axes[a];
  c.rate_hz = kPresetRateHz;
  c.targets = targets(spec);
  c.fixed_s = {72.0 * 3600.0};
  return c;
}

// The ADIS16405 record analysed as `cubecal analyze FILE` analyses it (its gyro columns, log:10, the twin).
pipeline::AnalysisResult adis_analysis(const Options& o) {
  io::SeriesOptions so;
  so.table.columns = {"gyro_x_dps", "gyro_y_dps", "gyro_z_dps"};
  so.keep_time = false;
  const io::Series s = io::read_series(o.adis, so);
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s")};
  req.grid = TauGrid{TauGrid::Kind::log, 10, {}};
  req.ci = o.ci;
  req.threads = static_cast<unsigned>(o.threads);
  return pipeline::run_analyze(s, req);
}

// Channel `a` of the ADIS16405 gyro: its twin (the composite model) or the paper's random-walk model, at 100 Hz.
Case adis_case(const pipeline::AnalysisResult& r, std::size_t a, bool twin, const char* spec) {
  Case c;
  c.rate_hz = r.rate_hz;
  const std::vector<TriadModel> m = twin ? pipeline::models_from_composite(r, "adis16405", c.rate_hz)
                                         : pipeline::models_from_analysis(r, "adis16405", false, c.rate_hz);
  c.triad = m.at(0);
  c.axis = c.triad.axes.at(a);
  c.axis.fixed_bias = 0.0;
  c.name = std::string("ADIS16405 ") + r.channels.at(a).name + (twin ? " twin" : " random walk");
  c.fixed_s = {r.duration_s};  // the record's own length (1,000,000 samples)
  if (twin && r.channels[a].model.composite) c.name += " (" + r.channels[a].model.composite->model + ")";
  c.targets = targets(spec);
  return c;
}

// White noise, flicker floor and rate random walk at 10 Hz (IEEE 952's three middle terms; unit u):
// N 0.01 u sqrt(s), B 0.002 u, K 1e-4 u / sqrt(s). (At 100 Hz the flicker
// generator makes this case take ten minutes of the table's twenty.)
Case flicker_case(const char* spec) {
  Case c;
  c.name = "WN+flicker+RW 10 Hz";
  c.rate_hz = 10.0;
  c.triad.name = "wn-flicker-rw";
  c.triad.unit = "u";
  c.axis.white_sigma = 0.01 * std::sqrt(c.rate_hz);
  c.axis.bias = BiasProcess::random_walk;
  c.axis.bias_sigma = 1e-4 * std::sqrt(c.rate_hz);
  c.axis.power_law = {flicker_term(0.002)};
  c.targets = targets(spec);
  return c;
}

std::vector<Case> cases(const Options& o) {
  std::vector<Case> cs;
  cs.push_back(preset_case("sport-gyro", 0, "N:1%,B:10%,K:20%,T:30%"));
  cs.push_back(preset_case("sport-gyro", 1, "N:1%,B:10%,K:20%,T:30%"));
  cs.push_back(preset_case("sport-mag", 0, "N:1%,B:10%,K:20%,T:30%"));
  cs.push_back(flicker_case("N:1%,B:10%,K:20%,T:30%"));
  // The same gyro axis with a rounding quantizer: the plan takes any
  // quantizer as white noise of 1 / (12 lsb^2); truncation toward zero (the
  // preset's, the paper's eq. 3) has a dead zone of +-1 LSB that the
  // random-walk bias crosses (docs/planning.md).
  Case rounded = preset_case("sport-gyro", 0, "");
  rounded.name += ", rounding quantizer";
  rounded.triad.quantizer = Quantizer::round;
  cs.push_back(rounded);
  bool adis = o.only.empty() || std::string("ADIS16405").find(o.only) != std::string::npos;
  if (adis) {
    const pipeline::AnalysisResult r = adis_analysis(o);
    cs.push_back(adis_case(r, 1, true, "N:1%,B:10%,K:20%,T:30%"));
    cs.push_back(adis_case(r, 1, false, "N:1%,B:10%,K:20%,T:30%"));
  }
  return cs;
}

void print_plan_only(const Case& c, const Options& o) {
  const PlanModel model = plan_model(with_axis(c), 0, 1.0 / c.rate_hz);
  PlanOptions po;
  po.ci = o.ci;
  for (const TargetPlan& tp : plan_duration(model, c.targets, po))
    std::printf("%s  %s  duration %s (%.0f s)  value %.4g  %s\n", c.name.c_str(), target_text(tp.target).c_str(),
                length_text(tp.duration_s).c_str(), tp.duration_s, tp.at.value, tp.at.why.c_str());
  for (const double L : c.fixed_s)
    for (const TermPrecision& p : plan_precision(model, L, kTerms, po))
      std::printf("%s  at %s  %s  precision %s  value %.4g  tau %.3g-%.3g  %s\n", c.name.c_str(),
                  length_text(L).c_str(), std::string(to_string(p.term)).c_str(), pct(p.precision).c_str(), p.value,
                  p.tau_lo, p.tau_hi, p.why.c_str());
}

// A planned term in the unit people quote it in (units.hpp; T in s), with its precision.
std::string quoted(const TermPrecision& p, const Unit& unit) {
  if (p.reason != PlanReason::none) return std::string(to_string(p.reason));
  if (p.term == PlanTerm::T) return num(p.value, "%.3g") + " s ± " + pct(p.precision);
  TermEstimate e;
  e.valid = true;
  e.value = p.value;
  const Term t = p.term == PlanTerm::N ? Term::N : p.term == PlanTerm::B ? Term::B : Term::K;
  const Quantity q = display(e, t, unit);
  return num(q.value, "%.3g") + " " + q.unit + " ± " + pct(p.precision);
}

// --paper: the plan of the paper's 72 h for every axis of both presets, and the length B:10 % needs.
void print_paper(const Options& o) {
  PlanOptions po;
  po.ci = o.ci;
  const PlanTarget b10[1] = {{PlanTerm::B, 0.10}};
  std::printf("| sensor | axis | N | B | K | T | B:10 %% needs |\n|---|---|---:|---:|---:|---:|---:|\n");
  for (const std::string name : {"sport-gyro", "sport-mag"}) {
    const TriadModel m = preset(name);
    for (std::size_t a = 0; a < 3; ++a) {
      const PlanModel model = plan_model(m, a, 1.0 / kPresetRateHz);
      std::printf("| %s | %s |", name.c_str(), m.axis_names[a].c_str());
      for (const TermPrecision& p : plan_precision(model, 72.0 * 3600.0, kTerms, po))
        std::printf(" %s |", quoted(p, *parse_unit(m.unit)).c_str());
      const TargetPlan t = plan_duration(model, b10, po).front();
      std::printf(" %s |\n", std::isfinite(t.duration_s) ? length_text(t.duration_s).c_str()
                                                         : std::string(to_string(t.at.reason)).c_str());
    }
  }
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--records")
      o.records = std::stoul(value());
    else if (a == "--seed")
      o.seed = std::stoull(value());
    else if (a == "--only")
      o.only = value();
    else if (a == "--threads")
      o.threads = std::stoi(value());
    else if (a == "--ci")
      o.ci = std::stod(value());
    else if (a == "--adis")
      o.adis = value();
    else if (a == "--plan-only")
      o.plan_only = true;
    else if (a == "--paper")
      o.paper = true;
    else
      throw std::invalid_argument(
          "unknown option " + a +
          " (--records K, --seed S, --only NAME, --threads T, --ci C, --adis FILE, --plan-only, --paper)");
  }
  if (o.records < 3) throw std::invalid_argument("--records: at least 3");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse_options(argc, argv);
    if (o.paper) {
      print_paper(o);
      return 0;
    }
    const std::vector<Case> cs = cases(o);
    if (!o.plan_only) print_header();
    for (const Case& c : cs) {
      if (!o.only.empty() && c.name.find(o.only) == std::string::npos) continue;
      if (o.plan_only)
        print_plan_only(c, o);
      else
        run_case(c, o);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cubecal_plan_validation: %s\n", e.what());
    return 1;
  }
}
