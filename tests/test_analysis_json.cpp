// The JSON form of the analysis results beside their types: to_json then
// from_json gives back every field of a real analysis (a simulated gyro and
// magnetometer with a temperature swing, plus a white-noise channel whose
// models cannot be fitted), a document without a required key is a
// UsageError naming it, and the faces that read an earlier run's files
// (simulate --model, cubecal report DIR) work from the typed result.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cubecal/error.hpp"
#include "cubecal/io/csv_writer.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/report/report.hpp"
#include "cubecal/sim/presets.hpp"

namespace cubecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Two hours of the paper's gyro and magnetometer at 10 Hz under a 25 +- 5 degC
// swing, and a channel of white noise (no minimum in its Allan curve).
io::Series simulated_series() {
  pipeline::SimulateRequest sim;
  sim.triads = {preset("sport-gyro"), preset("sport-mag")};
  sim.rate_hz = 10.0;
  sim.duration_s = 2 * 3600.0;
  sim.seed = 7;
  sim.temperature.kind = TemperatureProfile::Kind::sinusoid;
  sim.temperature.mean = 25.0;
  sim.temperature.amplitude = 5.0;
  sim.temperature.period_s = 3600.0;
  pipeline::SimulatedRecord rec = pipeline::simulate(sim);
  io::Series s;
  s.file = "sim/record.csv";
  s.rate_hz = rec.rate_hz;
  s.tau0 = 1.0 / rec.rate_hz;
  const std::size_t n = rec.channels[0].size();
  for (std::size_t c = 0; c < rec.names.size(); ++c) {
    if (rec.names[c] == "temp") {
      s.extra_names.push_back("temp");
      s.extra.push_back(rec.channels[c]);
    } else {
      s.names.push_back(rec.names[c]);
      s.channels.push_back(rec.channels[c]);
    }
  }
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> w(n);
  for (double& v : w) v = 5.0 + 0.1 * g(rng);
  s.names.push_back("white");
  s.channels.push_back(std::move(w));
  s.segments = {{0, n}};
  s.gaps = io::GapPolicy::split;
  return s;
}

const pipeline::AnalysisResult& analysis() {
  static const pipeline::AnalysisResult r = [] {
    const io::Series s = simulated_series();
    pipeline::AnalyzeRequest req;
    for (int k = 0; k < 3; ++k) req.units.push_back(*parse_unit("deg/s"));
    for (int k = 0; k < 3; ++k) req.units.push_back(*parse_unit("mGauss"));
    req.units.push_back(*parse_unit("counts"));
    req.grid = parse_tau_grid("log:10");
    req.ci = 0.95;
    req.temp_index = 0;
    req.temp_order = 2;
    req.max_samples = 30000;
    req.lsb = {145.6, 145.6, 145.6, 1.3, 1.3, 1.3, 0.0};
    return pipeline::run_analyze(s, req);
  }();
  return r;
}

pipeline::AnalysisResult round_trip(const pipeline::AnalysisResult& r) {
  const json j = pipeline::to_json(r);
  // Through text, as analysis.json is.
  return pipeline::analysis_result_from_json(json::parse(j.dump(1)), "analysis.json");
}

void expect_points(const std::vector<StabilityPoint>& a, const std::vector<StabilityPoint>& b,
                   const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].m, b[i].m) << what << " " << i;
    EXPECT_EQ(a[i].tau, b[i].tau) << what << " " << i;
    EXPECT_EQ(a[i].dev, b[i].dev) << what << " " << i;
    EXPECT_EQ(a[i].n, b[i].n) << what << " " << i;
    EXPECT_EQ(a[i].interval.lo, b[i].interval.lo) << what << " " << i;
    EXPECT_EQ(a[i].interval.hi, b[i].interval.hi) << what << " " << i;
    EXPECT_EQ(a[i].edf, b[i].edf) << what << " " << i;
    EXPECT_EQ(a[i].alpha, b[i].alpha) << what << " " << i;
  }
}

// Terms are stored in display units: equal to the last bits of the conversion.
void expect_term(const TermEstimate& a, const TermEstimate& b, const std::string& what) {
  EXPECT_EQ(a.valid, b.valid) << what;
  if (!a.valid) return;
  EXPECT_DOUBLE_EQ(a.value, b.value) << what;
  EXPECT_DOUBLE_EQ(a.sigma, b.sigma) << what;
  EXPECT_EQ(a.tau_lo, b.tau_lo) << what;
  EXPECT_EQ(a.tau_hi, b.tau_hi) << what;
}

void expect_noise(const pipeline::NoiseAnalysis& a, const pipeline::NoiseAnalysis& b, const std::string& what) {
  expect_points(a.adev, b.adev, what + " adev");
  const SlopeReadOffs &x = a.readoffs, &y = b.readoffs;
  expect_term(x.Q, y.Q, what + " read-off Q");
  expect_term(x.N, y.N, what + " read-off N");
  expect_term(x.B, y.B, what + " read-off B");
  expect_term(x.K, y.K, what + " read-off K");
  expect_term(x.R, y.R, what + " read-off R");
  EXPECT_EQ(x.tau_min, y.tau_min) << what;
  EXPECT_EQ(x.tau_min_lo, y.tau_min_lo) << what;
  EXPECT_EQ(x.tau_min_hi, y.tau_min_hi) << what;
  EXPECT_EQ(x.sigma_min, y.sigma_min) << what;
  const NoiseFit &f = a.fit, &g = b.fit;
  expect_term(f.Q, g.Q, what + " fit Q");
  expect_term(f.N, g.N, what + " fit N");
  expect_term(f.B, g.B, what + " fit B");
  expect_term(f.K, g.K, what + " fit K");
  expect_term(f.R, g.R, what + " fit R");
  EXPECT_EQ(f.c, g.c) << what;
  EXPECT_EQ(f.c_sigma, g.c_sigma) << what;
  EXPECT_EQ(f.chi2, g.chi2) << what;
  EXPECT_EQ(f.dof, g.dof) << what;
  EXPECT_EQ(f.rms_rel_residual, g.rms_rel_residual) << what;
}

void expect_temperature_fit(const TemperatureFit& t, const TemperatureFit& u, const std::string& w) {
  EXPECT_EQ(u.t_ref, t.t_ref) << w;
  EXPECT_EQ(u.coeff, t.coeff) << w;
  EXPECT_EQ(u.coeff_sigma, t.coeff_sigma) << w;
  EXPECT_EQ(u.cov, t.cov) << w;
  EXPECT_EQ(u.residual_rms, t.residual_rms) << w;
  EXPECT_EQ(u.r2, t.r2) << w;
  EXPECT_EQ(u.order, t.order) << w;
}

// A model (the record's or the compensated series') as written and read back.
void expect_model(const pipeline::ModelAnalysis& m, const pipeline::ModelAnalysis& n, const std::string& w) {
  EXPECT_EQ(n.ok, m.ok) << w;
  EXPECT_EQ(n.error, m.error) << w;
  EXPECT_EQ(n.samples, m.samples) << w;
  expect_points(m.adev, n.adev, w + " model adev");
  EXPECT_EQ(n.random_walk.lsb, m.random_walk.lsb) << w;
  EXPECT_DOUBLE_EQ(n.random_walk.dt, m.random_walk.dt) << w;
  if (m.ok) {
    EXPECT_EQ(n.random_walk.sigma_n, m.random_walk.sigma_n) << w;
    EXPECT_EQ(n.random_walk.sigma_mu, m.random_walk.sigma_mu) << w;
    EXPECT_EQ(n.random_walk_residual.rms_log, m.random_walk_residual.rms_log) << w;
    EXPECT_EQ(n.random_walk_residual.chi2, m.random_walk_residual.chi2) << w;
  }
  EXPECT_EQ(n.gm_ok, m.gm_ok) << w;
  EXPECT_EQ(n.gm_error, m.gm_error) << w;
  EXPECT_EQ(n.gauss_markov.lsb, m.gauss_markov.lsb) << w;
  if (m.gm_ok) {
    EXPECT_EQ(n.gauss_markov.sigma_n, m.gauss_markov.sigma_n) << w;
    EXPECT_EQ(n.gauss_markov.sigma_b, m.gauss_markov.sigma_b) << w;
    EXPECT_EQ(n.gauss_markov.tau_c, m.gauss_markov.tau_c) << w;
    EXPECT_DOUBLE_EQ(n.gauss_markov.dt, m.gauss_markov.dt) << w;
    EXPECT_EQ(n.gauss_markov_residual.rms_log, m.gauss_markov_residual.rms_log) << w;
    EXPECT_EQ(n.gauss_markov_residual.chi2, m.gauss_markov_residual.chi2) << w;
  }
}

TEST(AnalysisJson, RoundTripKeepsEveryField) {
  const pipeline::AnalysisResult& a = analysis();
  // The analysis has what the round trip must cover.
  ASSERT_EQ(a.channels.size(), 7u);
  ASSERT_TRUE(a.channels[0].model.ok);
  ASSERT_FALSE(a.channels[6].model.ok) << "white noise: no minimum, no random-walk model";
  ASSERT_FALSE(a.channels[6].noise.readoffs.B.valid);
  ASSERT_TRUE(a.channels[3].temperature.has_value());
  ASSERT_NE(a.channels[0].model.samples, a.samples) << "model fitted on the first samples";

  const pipeline::AnalysisResult b = round_trip(a);
  EXPECT_EQ(b.file, a.file);
  EXPECT_EQ(b.samples, a.samples);
  EXPECT_EQ(b.rate_hz, a.rate_hz);
  EXPECT_EQ(b.duration_s, a.duration_s);
  EXPECT_EQ(b.segments, a.segments);
  EXPECT_EQ(b.gaps, io::GapPolicy::split);
  EXPECT_EQ(b.ci, 0.95);
  EXPECT_EQ(b.temp_name, "temp");
  EXPECT_EQ(b.cov_names, a.cov_names);
  EXPECT_EQ(b.covariance, a.covariance);
  EXPECT_EQ(b.cov_samples, a.cov_samples);
  ASSERT_EQ(b.channels.size(), a.channels.size());
  for (std::size_t c = 0; c < a.channels.size(); ++c) {
    const auto &x = a.channels[c], &y = b.channels[c];
    const std::string w = "channel " + x.name;
    EXPECT_EQ(y.name, x.name);
    EXPECT_EQ(y.unit.name, x.unit.name) << w;
    EXPECT_EQ(y.unit.kind, x.unit.kind) << w;
    EXPECT_EQ(y.unit.to_si, x.unit.to_si) << w;
    EXPECT_EQ(y.mean, x.mean) << w;
    EXPECT_EQ(y.stddev, x.stddev) << w;
    expect_noise(x.noise, y.noise, w);
    expect_model(x.model, y.model, w);
    EXPECT_EQ(y.drift.window, x.drift.window) << w;
    EXPECT_EQ(y.drift.mean, x.drift.mean) << w;
    EXPECT_TRUE(y.drift.t.empty()) << "drift series live in drift.csv";
    ASSERT_EQ(y.temperature.has_value(), x.temperature.has_value()) << w;
    if (x.temperature) {
      const auto &t = *x.temperature, &u = *y.temperature;
      expect_temperature_fit(t.fit, u.fit, w + " temperature");
      expect_temperature_fit(t.ols, u.ols, w + " temperature OLS");
      EXPECT_EQ(u.joint, t.joint) << w;
      EXPECT_EQ(u.joint_error, t.joint_error) << w;
      EXPECT_EQ(u.noise.sigma_n, t.noise.sigma_n) << w;
      EXPECT_EQ(u.noise.sigma_mu, t.noise.sigma_mu) << w;
      EXPECT_EQ(u.noise.lsb, t.noise.lsb) << w;
      EXPECT_EQ(u.iterations, t.iterations) << w;
      EXPECT_EQ(u.converged, t.converged) << w;
      expect_noise(t.compensated, u.compensated, w + " compensated");
      expect_model(t.compensated_model, u.compensated_model, w + " compensated model");
    }
  }
}

TEST(AnalysisJson, MissingKeyIsAUsageErrorNamingIt) {
  json j = pipeline::to_json(analysis());
  j["channels"][1]["noise"].erase("fit");
  try {
    (void)pipeline::analysis_result_from_json(j, "analysis.json");
    FAIL() << "no error";
  } catch (const UsageError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("analysis.json: channels[1].noise: no key 'fit'"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line";
  }
  json k = pipeline::to_json(analysis());
  k["channels"][0]["adev"]["tau"] = "many";
  EXPECT_THROW((void)pipeline::analysis_result_from_json(k, "analysis.json"), UsageError);
  try {
    (void)pipeline::parse_analysis_json("{\"input\": {}}", "dir/analysis.json");
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("dir/analysis.json: no 'input' and 'channels'"), std::string::npos)
        << e.what();
  }
  try {
    (void)pipeline::parse_analysis_json("{ truncated", "x.json");
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("x.json: not an analysis.json written by cubecal analyze"), std::string::npos)
        << e.what();
  }
}

// Found by fuzz_analysis_json in CI: an alpha of -1e308 was cast to int
// (undefined behaviour).
TEST(AnalysisJson, NoiseExponentOutOfRangeIsAUsageError) {
  for (const double bad : {-1e308, 1e308, 2.5, 3.0, -5.0}) {
    json j = pipeline::to_json(analysis());
    j["channels"][0]["adev"]["alpha"][0] = bad;
    try {
      (void)pipeline::analysis_result_from_json(j, "analysis.json");
      ADD_FAILURE() << "alpha " << bad << " accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("channels[0].adev.alpha[0]: not a whole number from -4 to 2"),
                std::string::npos)
          << e.what();
    }
  }
  json w = pipeline::to_json(analysis());
  w["channels"][0]["drift"]["window_s"] = -1e300;
  EXPECT_THROW((void)pipeline::analysis_result_from_json(w, "analysis.json"), UsageError);
  json ok = pipeline::to_json(analysis());
  ok["channels"][0]["adev"]["alpha"][0] = -4;
  EXPECT_EQ(pipeline::analysis_result_from_json(ok, "analysis.json").channels[0].noise.adev[0].alpha, -4);
}

TEST(AnalysisJson, KeysAddedLaterTakeTheirDefaults) {
  json j = pipeline::to_json(analysis());
  j.erase("ci");
  j["input"].erase("gaps");
  for (auto& c : j["channels"]) {
    EXPECT_TRUE(c["noise"].contains("bias_instability_choice"));
    c["noise"].erase("curve_minimum");
    c["noise"].erase("bias_instability_choice");
    c["noise"].erase("accelerometer");
    c["model"].erase("adev");
  }
  const auto r = pipeline::analysis_result_from_json(j, "analysis.json");
  EXPECT_EQ(r.ci, 0.683);
  EXPECT_EQ(r.gaps, io::GapPolicy::error);
  EXPECT_EQ(r.channels[0].noise.readoffs.tau_min, analysis().channels[0].noise.readoffs.tau_min)
      << "from time_constant_s when the curve has a minimum";
  expect_points(r.channels[0].model.adev, analysis().channels[0].noise.adev, "model curve: the record's");
}

TEST(AnalysisJson, OneNKSignificanceAndNoMinimumAreWritten) {
  const auto& r = analysis();
  json j = pipeline::to_json(r);
  EXPECT_EQ(j.at("format_version"), 2);
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const auto& ch = r.channels[c];
    SCOPED_TRACE(ch.name);
    const json& n = j["channels"][c]["noise"];
    // One N: the read-off, in noise.arw, noise.reported and the densities.
    ASSERT_TRUE(ch.noise.readoffs.N.valid);
    EXPECT_EQ(n["arw"]["value"], n["reported"]["white_noise"]["value"]);
    EXPECT_EQ(n["reported"]["white_noise"]["source"], "read-off");
    EXPECT_EQ(n["arw"]["read_at_tau_s"], 1.0);
    const double n_unit = ch.noise.readoffs.N.value;  // data unit * sqrt(s) = unit/sqrt(Hz)
    EXPECT_NEAR(n["densities"]["white"]["value"].get<double>() / n_unit, 1.0, 1e-12);
    // K: significant only when value > 2 sigma, else an upper bound.
    const json& k = n["reported"]["rate_random_walk"];
    const TermEstimate& fk = ch.noise.fit.K;
    const TermEstimate& rk = ch.noise.readoffs.K;
    const bool sig = (fk.valid && fk.value > 2.0 * fk.sigma) || (rk.valid && rk.value > 2.0 * rk.sigma);
    EXPECT_EQ(k["significant"], sig);
    EXPECT_EQ(k["upper_bound"], !sig);
    EXPECT_EQ(n["rate_random_walk"]["significant"], rk.valid && rk.value > 2.0 * rk.sigma);
    EXPECT_EQ(n["fit"]["rate_random_walk"]["significant"], fk.valid && fk.value > 2.0 * fk.sigma);
    // B: "no minimum within the record" exactly when the curve is lowest at an end.
    const auto& adev = ch.noise.adev;
    std::size_t imin = 0;
    for (std::size_t i = 0; i < adev.size(); ++i)
      if (adev[i].dev < adev[imin].dev) imin = i;
    const bool none = imin == 0 || imin + 1 == adev.size();
    EXPECT_EQ(n["bias_instability"]["no_minimum_within_record"], none);
    EXPECT_EQ(n["reported"]["bias_instability"]["no_minimum_within_record"], none);
    EXPECT_EQ(n["reported"]["bias_instability"]["upper_bound"], none);
  }
  // The white channel has no minimum and no significant K.
  const json& w = j["channels"][r.channels.size() - 1]["noise"];
  EXPECT_TRUE(w["bias_instability"]["no_minimum_within_record"].get<bool>());
  EXPECT_FALSE(w["reported"]["rate_random_walk"]["significant"].get<bool>());
}

TEST(AnalysisJson, FileBeforeVersionTwoReadsNAgainFromItsCurve) {
  const auto& r = analysis();
  json j = pipeline::to_json(r);
  j.erase("format_version");
  // An old file's N: the tangent to the whole -1/2 region, lower than at 1 s.
  for (auto& ch : j["channels"]) ch["noise"]["arw"]["value"] = ch["noise"]["arw"]["value"].get<double>() * 0.93;
  pipeline::AnalysisResult back = pipeline::analysis_result_from_json(j, "analysis.json");
  for (std::size_t c = 0; c < r.channels.size(); ++c)
    EXPECT_NEAR(back.channels[c].noise.readoffs.N.value, r.channels[c].noise.readoffs.N.value,
                1e-9 * r.channels[c].noise.readoffs.N.value)
        << r.channels[c].name;
  // A version 2 file is taken as written.
  j["format_version"] = 2;
  back = pipeline::analysis_result_from_json(j, "analysis.json");
  EXPECT_NEAR(back.channels[0].noise.readoffs.N.value, 0.93 * r.channels[0].noise.readoffs.N.value,
              1e-9 * r.channels[0].noise.readoffs.N.value);
}

TEST(AnalysisJson, TemperatureJointFitOlsAndCompensatedModels) {
  const pipeline::AnalysisResult& a = analysis();
  // The gyro x axis (a random walk that shows within 2 h): jointly with its
  // random-walk bias; the white channel, whose curve has no minimum: least
  // squares, with the reason.
  const auto& gx = *a.channels[0].temperature;
  EXPECT_TRUE(gx.joint) << gx.joint_error;
  EXPECT_GT(gx.noise.sigma_mu, 0.0);
  EXPECT_GE(gx.iterations, 1u);
  EXPECT_NE(gx.fit.coeff, gx.ols.coeff);
  EXPECT_TRUE(gx.compensated_model.ok) << gx.compensated_model.error;
  EXPECT_EQ(gx.compensated_model.samples, a.channels[0].model.samples) << "fitted as the record's model";
  const auto& white = *a.channels[6].temperature;
  EXPECT_FALSE(white.joint);
  EXPECT_NE(white.joint_error.find("no random-walk model"), std::string::npos) << white.joint_error;
  EXPECT_EQ(white.fit.coeff, white.ols.coeff);
  const json j = pipeline::to_json(a);
  const json& t = j["channels"][0]["temperature"];
  EXPECT_EQ(t["method"], "random_walk_gls");
  EXPECT_EQ(t["noise_model"]["sigma_mu"], gx.noise.sigma_mu);
  EXPECT_EQ(t["ols"]["coeff"][0], gx.ols.coeff[1]);
  EXPECT_EQ(t["compensated_model"]["sigma_mu"], gx.compensated_model.random_walk.sigma_mu);
  EXPECT_EQ(j["channels"][6]["temperature"]["method"], "ols");
  EXPECT_TRUE(j["channels"][6]["temperature"].contains("joint_error"));
}

TEST(AnalysisJson, TemperatureOfAnEarlierVersionLoads) {
  // analysis.json of a cubecal that fitted by least squares only and
  // reported no compensated model.
  json j = pipeline::to_json(analysis());
  for (auto& c : j["channels"]) {
    if (!c.contains("temperature")) continue;
    for (const char* k : {"method", "method_text", "noise_model", "joint_error", "ols", "compensated_model"})
      c["temperature"].erase(k);
  }
  const auto r = pipeline::analysis_result_from_json(j, "analysis.json");
  const auto& t = *r.channels[0].temperature;
  EXPECT_FALSE(t.joint);
  EXPECT_EQ(t.ols.coeff, t.fit.coeff);
  EXPECT_EQ(t.fit.coeff, analysis().channels[0].temperature->fit.coeff);
  EXPECT_FALSE(t.compensated_model.ok);
  EXPECT_FALSE(t.compensated_model.gm_ok);
  EXPECT_NE(t.compensated_model.error.find("not in this analysis.json"), std::string::npos);
  json bad = pipeline::to_json(analysis());
  bad["channels"][0]["temperature"]["method"] = "kalman";
  EXPECT_THROW((void)pipeline::analysis_result_from_json(bad, "analysis.json"), UsageError);
}

TEST(AnalysisJson, DocumentKeepsTheCommandAndDriftCounts) {
  const std::string text = pipeline::analysis_json(analysis(), {"cubecal analyze sim/record.csv --ci 0.95", "/imu0"});
  const auto d = pipeline::parse_analysis_json(text, "analysis.json");
  EXPECT_EQ(d.command, "cubecal analyze sim/record.csv --ci 0.95");
  ASSERT_EQ(d.drift_points.size(), 7u);
  EXPECT_EQ(d.drift_points[0], analysis().channels[0].drift.t.size());
  EXPECT_GT(d.drift_points[0], 0u);
}

TEST(AnalysisJson, DriftCsvReadBackThroughTheTableReader) {
  char tmpl[] = "/tmp/cubecal-test-drift-XXXXXX";
  ASSERT_NE(::mkdtemp(tmpl), nullptr);
  const fs::path dir = tmpl;
  std::ofstream(dir / "drift.csv") << pipeline::drift_csv(analysis());
  pipeline::AnalysisResult r = round_trip(analysis());
  std::vector<std::size_t> points;
  for (const auto& c : analysis().channels) points.push_back(c.drift.t.size());
  ASSERT_TRUE(pipeline::read_drift_csv((dir / "drift.csv").string(), points, r));
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const auto &x = analysis().channels[c].drift, &y = r.channels[c].drift;
    ASSERT_EQ(y.t.size(), x.t.size());
    for (std::size_t i = 0; i < x.t.size(); ++i) {
      EXPECT_EQ(y.t[i], io::csv_round(x.t[i]));
      EXPECT_EQ(y.drift[i], io::csv_round(x.drift[i]));
    }
  }
  points[0] += 1;
  pipeline::AnalysisResult s = round_trip(analysis());
  EXPECT_FALSE(pipeline::read_drift_csv((dir / "drift.csv").string(), points, s)) << "counts do not match";
  EXPECT_TRUE(s.channels[0].drift.t.empty());
  fs::remove_all(dir);
}

TEST(AnalysisJson, SimulateModelsFromTheTypedResult) {
  const pipeline::AnalysisResult r = round_trip(analysis());
  pipeline::AnalysisResult sensors = r;
  sensors.channels.pop_back();  // the white-noise channel has no random-walk model
  const auto m = pipeline::models_from_analysis(sensors, "a.json", false);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].unit, "deg/s");
  EXPECT_EQ(m[1].axis_names[2], "mz");
  // With a temperature analysis: the model of the compensated series (the
  // twin simulates the temperature term itself), where it was fitted.
  const auto& gy = analysis().channels[1];
  ASSERT_TRUE(gy.temperature->compensated_model.ok);
  EXPECT_NE(gy.temperature->compensated_model.random_walk.sigma_mu, gy.model.random_walk.sigma_mu);
  EXPECT_EQ(m[0].axes[1].white_sigma, gy.temperature->compensated_model.random_walk.sigma_n);
  EXPECT_EQ(m[0].axes[1].bias_sigma, gy.temperature->compensated_model.random_walk.sigma_mu);
  const auto& mx = analysis().channels[3];
  ASSERT_FALSE(mx.temperature->compensated_model.ok) << "2 h: no minimum in the compensated curve";
  EXPECT_EQ(m[1].axes[0].bias_sigma, mx.model.random_walk.sigma_mu) << "the record's model then";
  EXPECT_EQ(m[0].lsb, 145.6);
  EXPECT_EQ(m[1].axes[0].temp_coeff, analysis().channels[3].temperature->fit.coeff[1]);
  EXPECT_EQ(m[1].axes[0].fixed_bias, analysis().channels[3].temperature->fit.coeff[0]);
  try {
    (void)pipeline::models_from_analysis(r, "a.json", false);
    FAIL() << "no error for a channel without a model";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::bias);
    EXPECT_NE(std::string(e.what()).find("a.json: channel white has no fitted random-walk model ("), std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)pipeline::models_from_analysis(pipeline::AnalysisResult{}, "a.json", false), UsageError);
}

TEST(AnalysisJson, DevResultRoundTrip) {
  const io::Series s = simulated_series();
  pipeline::DevRequest req;
  req.grid = parse_tau_grid("octave");
  req.options.ci = 0.9;
  req.options.edf = EdfMethod::simple;
  const pipeline::DevResult a = pipeline::run_dev(s, req);
  const pipeline::DevResult b = pipeline::dev_result_from_json(json::parse(pipeline::to_json(a).dump()), "dev result");
  EXPECT_EQ(b.stat, a.stat);
  EXPECT_EQ(b.type, a.type);
  EXPECT_EQ(b.rate_hz, a.rate_hz);
  EXPECT_EQ(b.samples, a.samples);
  EXPECT_EQ(b.segments, a.segments);
  EXPECT_EQ(b.file, "sim/record.csv");
  EXPECT_EQ(b.options.ci, 0.9);
  EXPECT_EQ(b.options.edf, EdfMethod::simple);
  EXPECT_TRUE(b.options.intervals);
  ASSERT_EQ(b.channels.size(), a.channels.size());
  for (std::size_t c = 0; c < a.channels.size(); ++c) {
    EXPECT_EQ(b.channels[c].name, a.channels[c].name);
    expect_points(a.channels[c].points, b.channels[c].points, a.channels[c].name);
  }
  pipeline::DevResult no_ci = a;
  no_ci.options.intervals = false;
  const json j = pipeline::to_json(no_ci);
  EXPECT_TRUE(j["ci"].is_null());
  EXPECT_FALSE(j["columns"][0].contains("lo"));
  EXPECT_FALSE(pipeline::dev_result_from_json(j, "dev result").options.intervals);
}

void expect_tau_list(const TauListOutcome& a, const TauListOutcome& b, const std::string& what) {
  ASSERT_EQ(b.excluded.size(), a.excluded.size()) << what;
  for (std::size_t i = 0; i < a.excluded.size(); ++i) {
    EXPECT_EQ(b.excluded[i].tau, a.excluded[i].tau) << what;
    EXPECT_EQ(b.excluded[i].m, a.excluded[i].m) << what;
    EXPECT_EQ(b.excluded[i].needs, a.excluded[i].needs) << what;
    EXPECT_EQ(b.excluded[i].has, a.excluded[i].has) << what;
    EXPECT_EQ(b.excluded[i].reason, a.excluded[i].reason) << what;
  }
  ASSERT_EQ(b.merged.size(), a.merged.size()) << what;
  for (std::size_t i = 0; i < a.merged.size(); ++i) {
    EXPECT_EQ(b.merged[i].tau, a.merged[i].tau) << what;
    EXPECT_EQ(b.merged[i].kept_tau, a.merged[i].kept_tau) << what;
    EXPECT_EQ(b.merged[i].m, a.merged[i].m) << what;
  }
}

// Listed taus left out or merged travel with the result: `dev --format json`
// and analysis.json carry them, and a result read back has them.
TEST(AnalysisJson, ExcludedAndMergedTausRoundTrip) {
  const io::Series s = simulated_series();
  pipeline::DevRequest req;
  req.grid = parse_tau_grid("1,1.04,1e6,1e300");
  const pipeline::DevResult a = pipeline::run_dev(s, req);
  ASSERT_EQ(a.tau_list.excluded.size(), 2u);
  ASSERT_EQ(a.tau_list.merged.size(), 1u);
  const json j = pipeline::to_json(a);
  EXPECT_EQ(j["excluded_taus"][0]["af"], 10000000) << "a whole number";
  EXPECT_EQ(j["excluded_taus"][0]["reason"], a.tau_list.excluded[0].reason);
  EXPECT_EQ(j["merged_taus"][0]["merged_with_tau_s"], 1.0);
  expect_tau_list(a.tau_list, pipeline::dev_result_from_json(json::parse(j.dump()), "dev result").tau_list, "dev");

  pipeline::AnalysisResult r = analysis();
  r.tau_list = a.tau_list;
  r.model_excluded_taus = {a.tau_list.excluded[0]};
  const json k = pipeline::to_json(r);
  ASSERT_TRUE(k.contains("model_excluded_taus"));
  const pipeline::AnalysisResult b = round_trip(r);
  expect_tau_list(r.tau_list, b.tau_list, "analysis");
  expect_tau_list({r.model_excluded_taus, {}}, {b.model_excluded_taus, {}}, "analysis model");

  json old = pipeline::to_json(analysis());  // written before the keys existed
  for (const char* key : {"excluded_taus", "merged_taus", "model_excluded_taus"}) old.erase(key);
  const auto c = pipeline::analysis_result_from_json(old, "analysis.json");
  EXPECT_TRUE(c.tau_list.empty());
  EXPECT_TRUE(c.model_excluded_taus.empty());
}

TEST(AnalysisJson, ReportFromMemoryAndFromTheFilesOfAnEarlierRun) {
  char tmpl[] = "/tmp/cubecal-test-areport-XXXXXX";
  ASSERT_NE(::mkdtemp(tmpl), nullptr);
  const fs::path dir = tmpl;
  report::ReportOptions o;
  o.require_plots = false;
  o.gnuplot = (dir / "no-gnuplot").string();  // the page alone: the plots are another test's
  // The command holds no --ci: the confidence comes from the result.
  const std::string cmd = "cubecal analyze sim/record.csv --out " + dir.string();
  report::write_report(analysis(), {cmd, {}}, (dir / "mem").string(), o);
  const auto slurp = [](const fs::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  const std::string mem = slurp(dir / "mem" / "report.html");
  EXPECT_NE(mem.find("<th>confidence of the intervals</th><td>95 %</td>"), std::string::npos);
  EXPECT_NE(mem.find("[plot drift_rate not rendered]"), std::string::npos) << "drift series from memory";
  EXPECT_NE(mem.find("[plot allan_other not rendered]"), std::string::npos);

  fs::create_directories(dir / "files");
  std::ofstream(dir / "files" / "analysis.json") << pipeline::analysis_json(analysis(), {cmd, "/imu0"});
  std::ofstream(dir / "files" / "drift.csv") << pipeline::drift_csv(analysis());
  report::write_report((dir / "files").string(), o);
  const std::string files = slurp(dir / "files" / "report.html");
  EXPECT_NE(files.find("<th>confidence of the intervals</th><td>95 %</td>"), std::string::npos);
  EXPECT_NE(files.find("[plot drift_rate not rendered]"), std::string::npos) << "drift series from drift.csv";
  EXPECT_NE(files.find(cmd), std::string::npos);

  fs::remove(dir / "files" / "drift.csv");
  o.force = true;
  report::write_report((dir / "files").string(), o);
  const std::string no_drift = slurp(dir / "files" / "report.html");
  EXPECT_EQ(no_drift.find("[plot drift_rate not rendered]"), std::string::npos);
  EXPECT_NE(no_drift.find("No drift.csv in the directory: no drift plots."), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cubecal
