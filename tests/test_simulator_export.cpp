// Simulator exports of a channel's twin (pipeline/simulator_export): for
// every target, its noise equations as its own source runs them
// (docs/twin-exports.md: the per-step update and its random draws) are fed
// the numbers read back from the exported text and simulated; the Haar
// wavelet variance of the simulated record must match the projection's
// theoretical curve within the empirical intervals at nearly every scale,
// and the twin error the file reports must be the one the exported numbers
// give against the twin. The twins are those of a MEMS gyroscope (deg/s,
// MA1+RW+2*GM, one with a vibration line) and accelerometer (g, with QN and
// DR) at 100 Hz.
#include "cubecal/pipeline/simulator_export.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/estimator_config.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {
namespace {

using pipeline::Estimator;
using pipeline::ExportProjection;

constexpr double kRate = 100.0;
constexpr double kDt = 1.0 / kRate;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kG = 9.80665;
constexpr std::size_t kRecord = std::size_t{1} << 22;  // the twin's record: its scales 2 .. 2^21 and their EDF
constexpr std::size_t kSim = std::size_t{1} << 20;     // samples each target's equations are run for

Process wn(double n) { return {ProcessKind::wn, n * n / kDt}; }
Process rw(double k) { return {ProcessKind::rw, k * k * kDt}; }
Process qn(double q) { return {ProcessKind::qn, (q / kDt) * (q / kDt)}; }
Process dr(double r) { return {ProcessKind::dr, r * kDt}; }

// A channel whose analysis carries `twin` as its composite model, with the
// scales and EDF of the wavelet variance of a kRecord-sample record
// (stats/wavelet_variance.hpp: eta3 = max(M / tau, 1), M = N - tau + 1).
pipeline::ChannelAnalysis channel(const std::string& name, const std::string& unit, CompositeModel twin) {
  pipeline::ChannelAnalysis c;
  c.name = name;
  c.unit = *parse_unit(unit);
  pipeline::ModelChannel m;
  m.name = name;
  m.unit = c.unit;
  m.model = model_name(twin);
  for (double tau = 2.0; tau <= static_cast<double>(kRecord / 2); tau *= 2.0) {
    const double M = static_cast<double>(kRecord) - tau + 1.0;
    m.wv.tau.push_back(tau);
    m.wv.nu2.push_back(haar_wavelet_variance(twin, tau));
    m.wv.n.push_back(static_cast<std::size_t>(M));
    m.wv.edf.push_back(std::max(M / tau, 1.0));
  }
  for (const double v : m.wv.nu2) m.wv.interval.push_back({v, v});
  m.fit.model = std::move(twin);
  c.model.composite = std::move(m);
  return c;
}

const pipeline::AnalysisResult& imu_record() {
  static const pipeline::AnalysisResult r = [] {
    pipeline::AnalysisResult a;
    a.file = "synthetic-twins";
    a.samples = kRecord;
    a.rate_hz = kRate;
    a.duration_s = static_cast<double>(kRecord) * kDt;
    const double n = 0.005;  // deg/s/sqrt(Hz): 0.3 deg/sqrt(h)
    a.channels.push_back(
        channel("gx", "deg/s",
                {{ma1_process(n, 0.3, kDt), rw(2e-5), gm_process(2.0, 2e-3, kDt), gm_process(200.0, 1e-3, kDt)}}));
    a.channels.push_back(channel(
        "gy", "deg/s",
        {{ma1_process(1.2 * n, 0.25, kDt), rw(1.5e-5), gm_process(5.0, 1.5e-3, kDt), gm_process(600.0, 8e-4, kDt)}}));
    a.channels.push_back(channel(
        "gz", "deg/s",
        {{ma1_process(0.8 * n, 0.35, kDt), rw(2.5e-5), gm_process(100.0, 1.2e-3, kDt), sin_process(0.03, 12.5, kDt)}}));
    a.channels.push_back(channel("ax", "g", {{wn(1e-4), qn(2e-6), rw(2e-7), gm_process(60.0, 3e-5, kDt)}}));
    a.channels.push_back(channel("ay", "g", {{wn(1.2e-4), rw(1.5e-7), dr(2e-9), gm_process(30.0, 2e-5, kDt)}}));
    a.channels.push_back(channel("az", "g", {{wn(0.9e-4), rw(3e-7), gm_process(300.0, 4e-5, kDt)}}));
    return a;
  }();
  return r;
}

pipeline::EstimatorFile file(Estimator e, const pipeline::AnalysisResult& r = imu_record()) {
  return pipeline::estimator_config(e, r, {"cubecal analyze test --for x", "/imu7", 1.0});
}

// ------------------------------------------------------------ reading back

double number_at(const std::string& text, std::size_t at) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str() + at, &end);
  EXPECT_NE(end, text.c_str() + at) << "no number at " << text.substr(at, 40);
  return v;
}

// The value of <name>...</name> after `from`; `from` moves past it.
double tag(const std::string& text, std::size_t& from, const std::string& name) {
  const std::size_t at = text.find("<" + name + ">", from);
  EXPECT_NE(at, std::string::npos) << name;
  if (at == std::string::npos) return NAN;
  from = at + name.size() + 2;
  return number_at(text, from);
}

// A bracketed list of numbers after `key` (from `from`): "[a b c]",
// "[a, b, c]" or "np.diag([a, 1.0 - b, c])" whose "1.0 - x" and "-(1 - x)"
// items are evaluated.
std::vector<double> list_after(const std::string& text, std::size_t from, const std::string& key) {
  const std::size_t at = text.find(key, from);
  EXPECT_NE(at, std::string::npos) << key;
  if (at == std::string::npos) return {};
  const std::size_t open = text.find('[', at), close = text.find(']', open);
  std::string body = text.substr(open + 1, close - open - 1);
  for (char& ch : body)
    if (ch == ',') ch = ' ';
  std::vector<double> v;
  std::istringstream in(body);
  for (std::string tok; in >> tok;) {
    if (tok == "-(1") {  // "-(1 - x)"
      std::string minus, x;
      in >> minus >> x;
      v.push_back(-(1.0 - std::stod(x.substr(0, x.find(')')))));
    } else if (tok == "1.0" && in.peek() == ' ') {  // "1.0 - x" or a plain 1.0
      const auto pos = in.tellg();
      std::string minus;
      in >> minus;
      if (minus == "-") {
        std::string x;
        in >> x;
        v.push_back(1.0 - std::stod(x));
      } else {
        in.clear();
        in.seekg(pos);
        v.push_back(1.0);
      }
    } else {
      v.push_back(std::stod(tok));
    }
  }
  return v;
}

double scalar_after(const std::string& text, std::size_t from, const std::string& key) {
  const std::size_t at = text.find(key, from);
  EXPECT_NE(at, std::string::npos) << key;
  if (at == std::string::npos) return NAN;
  return number_at(text, text.find_first_of("-0123456789", at + key.size()));
}

// The twin errors the file reports: "gx: twin error 1.2e-01" and
// "gx (matlab-pre-R2023b): twin error ...".
std::map<std::string, double> reported_twin_errors(const std::string& text) {
  std::map<std::string, double> m;
  const std::regex line(R"(([A-Za-z0-9_]+)( \(([^)]*)\))?: twin error ([-+.0-9eE]+))");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), line); it != std::sregex_iterator(); ++it) {
    const std::string key = (*it)[1].str() + ((*it)[3].matched ? "/" + (*it)[3].str() : "");
    m[key] = std::stod((*it)[4].str());
  }
  return m;
}

// ------------------------------------------------------------ checking

struct Sim {
  std::string label;                             // "gazebo gx"
  std::vector<std::string> channels;             // whose twins the exported numbers stand for
  CompositeModel model_si;                       // the projection the exported numbers define, per sample, SI
  std::function<double(std::mt19937_64&)> step;  // one output sample of the target's equations, SI
  std::string twin_key_suffix;                   // "/matlab-pre-R2023b" for the fallback's reported errors
};

const pipeline::ChannelAnalysis& channel_named(const std::string& name) {
  for (const auto& c : imu_record().channels)
    if (c.name == name) return c;
  throw std::logic_error("no channel " + name);
}

struct Figures {
  std::size_t scales = 0, outside = 0;
  double max_rel = 0.0;  // max |nu2_sim / nu2_theory - 1| where the EDF is at least 100
};

// Runs `s` for kSim samples, compares its wavelet variance with the
// exported model's theoretical one, and the twin error the numbers give
// with the reported one (and simulator_projections').
Figures check(const Sim& s, const std::map<std::string, double>& reported,
              const std::vector<ExportProjection>& projections, const std::string& target, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::vector<double> y(kSim);
  for (double& v : y) v = s.step(engine);
  const WaveletVariance w = wavelet_variance(y, 0.99);
  Figures f;
  for (std::size_t j = 0; j < w.size(); ++j) {
    const double theory = haar_wavelet_variance(s.model_si, w.tau[j]);
    ++f.scales;
    if (theory < w.interval[j].lo || theory > w.interval[j].hi) ++f.outside;
    if (w.edf[j] >= 100.0) f.max_rel = std::max(f.max_rel, std::abs(w.nu2[j] / theory - 1.0));
  }
  EXPECT_LE(f.outside, 2u) << s.label << ": the simulated curve leaves the projection's at " << f.outside << " of "
                           << f.scales << " scales";
  for (const std::string& name : s.channels) {
    const auto& c = channel_named(name);
    const double si2 = c.unit.to_si * c.unit.to_si;
    double err = 0.0;
    for (const double tau : c.model.composite->wv.tau) {
      const double twin = haar_wavelet_variance(c.model.composite->fit.model, tau) * si2;
      err = std::max(err, std::abs(std::sqrt(haar_wavelet_variance(s.model_si, tau) / twin) - 1.0));
    }
    const auto it = reported.find(name + s.twin_key_suffix);
    EXPECT_NE(it, reported.end()) << s.label << ": no twin error reported for " << name;
    if (it == reported.end()) continue;
    EXPECT_NEAR(it->second, err, 1e-6 * std::max(1.0, err)) << s.label << " " << name;
    const std::string t = s.twin_key_suffix.empty() ? target : s.twin_key_suffix.substr(1);
    bool found = false;
    for (const auto& p : projections)
      if (p.channel == name && p.target == t) {
        found = true;
        EXPECT_NEAR(p.twin_error, err, 1e-6 * std::max(1.0, err)) << s.label << " " << name;
      }
    EXPECT_TRUE(found) << s.label << " " << name;
    std::printf(
        "  %-28s %-3s twin error %6.2f %%  simulated: %2zu/%2zu scales inside 99 %%, max |sim/theory - 1| "
        "%.3f (EDF >= 100)\n",
        s.label.c_str(), name.c_str(), 100.0 * err, f.scales - f.outside, f.scales, f.max_rel);
  }
  return f;
}

double normal(std::mt19937_64& e, double mean, double sd) { return std::normal_distribution<double>(mean, sd)(e); }

const std::vector<std::string> kGyro{"gx", "gy", "gz"}, kAccel{"ax", "ay", "az"};

// ------------------------------------------------------------ the targets

TEST(SimulatorExport, NamesAndFiles) {
  const std::map<std::string, std::string> files{{"gazebo", "gazebo_imu_noise.sdf"},
                                                 {"rotors", "rotors_imu_plugin.sdf"},
                                                 {"navego", "navego_imu.m"},
                                                 {"matlab", "matlab_imu.m"},
                                                 {"basilisk", "basilisk_imu.py"}};
  for (const auto& [name, f] : files) {
    const auto e = pipeline::parse_estimator(name);
    ASSERT_TRUE(e) << name;
    EXPECT_TRUE(pipeline::is_simulator(*e));
    EXPECT_EQ(pipeline::estimator_name(*e), name);
    EXPECT_EQ(pipeline::estimator_file(*e), f);
    EXPECT_NE(pipeline::estimator_names().find(name), std::string::npos);
  }
  EXPECT_FALSE(pipeline::is_simulator(Estimator::kalibr));
  EXPECT_THROW(pipeline::simulator_projections(Estimator::vins, imu_record()), std::invalid_argument);
}

// gz-sensors GaussianNoiseModel::Load and ApplyImpl, as ImuSensor::Update
// calls them at each update, dt apart.
TEST(SimulatorExport, GazeboSdfReproducesItsProjection) {
  const auto f = file(Estimator::gazebo);
  const auto reported = reported_twin_errors(f.text);
  const auto projections = pipeline::simulator_projections(Estimator::gazebo, imu_record());
  // XML comments may not hold "--": the command line's is written "- -".
  const std::size_t open = f.text.find("<!--"), close = f.text.find("-->", open + 4);
  const std::string header = f.text.substr(open + 4, close - open - 4);
  EXPECT_EQ(header.find("--"), std::string::npos);
  EXPECT_NE(header.find("test - -for x"), std::string::npos);
  std::uint64_t seed = 11;
  for (const bool gyro : {true, false}) {
    std::size_t at = f.text.find(gyro ? "<angular_velocity>" : "<linear_acceleration>");
    ASSERT_NE(at, std::string::npos);
    for (std::size_t i = 0; i < 3; ++i) {
      at = f.text.find(std::string("<") + "xyz"[i] + ">", at);
      const double mean = tag(f.text, at, "mean"), stddev = tag(f.text, at, "stddev");
      const double bias_mean = tag(f.text, at, "bias_mean"), bias_stddev = tag(f.text, at, "bias_stddev");
      const double dyn = tag(f.text, at, "dynamic_bias_stddev"), T = tag(f.text, at, "dynamic_bias_correlation_time");
      const double precision = tag(f.text, at, "precision");
      const std::string name = (gyro ? kGyro : kAccel)[i];
      Sim s;
      s.label = "gazebo " + name;
      s.channels = {name};
      const double phi_d = std::exp(-kDt / T);
      const double sigma_bd = std::sqrt(-dyn * dyn * T / 2.0 * std::expm1(-2.0 * kDt / T));
      s.model_si = {{{ProcessKind::wn, stddev * stddev}, {ProcessKind::gm, sigma_bd * sigma_bd, phi_d}}};
      auto bias = std::make_shared<double>(0.0);
      auto started = std::make_shared<bool>(false);
      s.step = [=](std::mt19937_64& e) {
        if (!*started) {  // Load: the turn-on bias, a random sign
          *bias = bias_stddev > 0.0 ? normal(e, bias_mean, bias_stddev) : bias_mean;
          if (std::uniform_real_distribution<double>(0.0, 1.0)(e) < 0.5) *bias = -*bias;
          *started = true;
        }
        const double white = stddev > 0.0 ? normal(e, mean, stddev) : mean;
        if (dyn > 0.0 && T > 0.0) *bias = phi_d * *bias + normal(e, 0.0, sigma_bd);
        double out = *bias + white;
        if (precision != 0.0) out = std::round(out / precision) * precision;
        return out;
      };
      check(s, reported, projections, "gazebo", seed++);
    }
  }
}

// RotorS GazeboImuPlugin::AddNoise (PX4's addNoise starts the bias from the
// turn-on draw instead of adding it): one value per sensor.
TEST(SimulatorExport, RotorsPluginReproducesItsProjection) {
  const auto f = file(Estimator::rotors);
  const auto reported = reported_twin_errors(f.text);
  const auto projections = pipeline::simulator_projections(Estimator::rotors, imu_record());
  std::uint64_t seed = 21;
  for (const bool gyro : {true, false}) {
    const std::string n = gyro ? "gyroscope" : "accelerometer";
    std::size_t at = f.text.find("<plugin");
    const double nd = tag(f.text, at, n + "NoiseDensity");
    std::size_t w = f.text.find("<plugin");
    const double walk = tag(f.text, w, n + "RandomWalk");
    if (gyro) {
      std::size_t b = f.text.find("<plugin");
      EXPECT_EQ(tag(f.text, b, "gyroscopeBiasRandomWalk"), walk) << "RotorS's name, the same value";
    }
    std::size_t t = f.text.find("<plugin");
    const double T = tag(f.text, t, n + "BiasCorrelationTime");
    std::size_t o = f.text.find("<plugin");
    const double turn_on = tag(f.text, o, n + "TurnOnBiasSigma");
    Sim s;
    s.label = "rotors " + n;
    s.channels = gyro ? kGyro : kAccel;
    const double sigma_d = nd / std::sqrt(kDt);
    const double sigma_bd = std::sqrt(-walk * walk * T / 2.0 * (std::exp(-2.0 * kDt / T) - 1.0));
    const double phi = std::exp(-1.0 / T * kDt);
    s.model_si = {{{ProcessKind::wn, sigma_d * sigma_d}, {ProcessKind::gm, sigma_bd * sigma_bd, phi}}};
    auto bias = std::make_shared<double>(0.0);
    auto on = std::make_shared<double>(NAN);
    s.step = [=](std::mt19937_64& e) {
      if (std::isnan(*on)) *on = turn_on * normal(e, 0.0, 1.0);
      *bias = phi * *bias + sigma_bd * normal(e, 0.0, 1.0);
      return *bias + sigma_d * normal(e, 0.0, 1.0) + *on;
    };
    check(s, reported, projections, "rotors", seed++);
  }
}

// NaveGo's imu_si_errors, then gyro_gen / acc_gen with noise_b_sta,
// noise_b_dyn (Aggarwal) and noise_rrw, per axis.
TEST(SimulatorExport, NavegoProfileReproducesItsProjection) {
  const auto f = file(Estimator::navego);
  const auto reported = reported_twin_errors(f.text);
  const auto projections = pipeline::simulator_projections(Estimator::navego, imu_record());
  const double freq = scalar_after(f.text, 0, "cubecal_imu.freq");
  EXPECT_EQ(freq, kRate);
  const double dt = 1.0 / freq;
  const double D2R = std::numbers::pi / 180.0;
  std::uint64_t seed = 31;
  for (const bool gyro : {true, false}) {
    const auto white_m = list_after(f.text, 0, gyro ? "cubecal_imu.arw " : "cubecal_imu.vrw ");
    const auto walk_m = list_after(f.text, 0, gyro ? "cubecal_imu.arrw" : "cubecal_imu.vrrw");
    const auto sta = list_after(f.text, 0, gyro ? "cubecal_imu.gb_sta" : "cubecal_imu.ab_sta");
    const auto dyn = list_after(f.text, 0, gyro ? "cubecal_imu.gb_dyn" : "cubecal_imu.ab_dyn");
    const auto corr = list_after(f.text, 0, gyro ? "cubecal_imu.gb_corr" : "cubecal_imu.ab_corr");
    ASSERT_EQ(white_m.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      // imu_si_errors.m
      const double rw_si = gyro ? white_m[i] / 60.0 * D2R : white_m[i] / 60.0;
      const double rrw_si = gyro ? walk_m[i] / 60.0 * D2R : walk_m[i] / 60.0;
      const double dyn_si = gyro ? dyn[i] * D2R : dyn[i] * 0.001 * kG;
      const double sta_si = gyro ? sta[i] * D2R : sta[i] * 0.001 * kG;
      const double std_si = rw_si / std::sqrt(dt);
      // noise_b_dyn.m (finite correlation time), noise_rrw.m
      const double beta = dt / corr[i], a1 = std::exp(-beta);
      const double sigma_gm = dyn_si * std::sqrt(1.0 - std::exp(-2.0 * beta));
      const std::string name = (gyro ? kGyro : kAccel)[i];
      Sim s;
      s.label = "navego " + name;
      s.channels = {name};
      s.model_si = {{{ProcessKind::wn, std_si * std_si},
                     {ProcessKind::rw, rrw_si * dt * rrw_si * dt},
                     {ProcessKind::gm, sigma_gm * sigma_gm, a1}}};
      struct State {
        bool started = false;
        double b_sta = 0.0, b_dyn = 0.0, rrw = 0.0;
      };
      auto st = std::make_shared<State>();
      s.step = [=](std::mt19937_64& e) {
        if (!st->started) {  // noise_b_sta: a uniform 10 % about b_sta; b_dyn(1) = b_dyn; rrw(1) = 0
          st->b_sta = sta_si + (-0.1 * sta_si + 0.2 * sta_si * std::uniform_real_distribution<double>(0, 1)(e));
          st->b_dyn = dyn_si;
          st->started = true;
        } else {
          st->b_dyn = a1 * st->b_dyn + sigma_gm * normal(e, 0.0, 1.0);
          st->rrw += rrw_si * dt * normal(e, 0.0, 1.0);
        }
        return std_si * normal(e, 0.0, 1.0) + st->b_sta + st->b_dyn + st->rrw;
      };
      check(s, reported, projections, "navego", seed++);
    }
  }
}

// MATLAB imuSensor at SampleRate Fs, NoiseType "double-sided" (BW = Fs/2):
// white NoiseDensity sqrt(BW) w, random walk r += RandomWalk / sqrt(BW) w,
// bias filter(Numerator, Denominator, BiasInstability w) (transposed direct
// form, as the code Simulink Coder generates for it).
TEST(SimulatorExport, MatlabScriptReproducesItsProjections) {
  const auto f = file(Estimator::matlab);
  const auto reported = reported_twin_errors(f.text);
  const auto projections = pipeline::simulator_projections(Estimator::matlab, imu_record());
  const double Fs = scalar_after(f.text, 0, "\nFs = ");
  EXPECT_EQ(Fs, kRate);
  const double BW = Fs / 2.0;
  const std::size_t branch_new = f.text.find("if isprop(gyroparams, 'BiasInstabilityCoefficients')");
  const std::size_t branch_old = f.text.find("\nelse\n", branch_new);
  ASSERT_NE(branch_new, std::string::npos);
  ASSERT_NE(branch_old, std::string::npos);
  std::uint64_t seed = 41;
  for (const bool with_filter : {true, false}) {
    for (const bool gyro : {true, false}) {
      const std::size_t at =
          f.text.find(gyro ? "gyro = gyroparams(" : "accel = accelparams(", with_filter ? branch_new : branch_old);
      const std::size_t end = f.text.find(");", at);
      const std::string call = f.text.substr(at, end - at + 2);
      const auto nd = list_after(call, 0, "'NoiseDensity'");
      const auto walk = list_after(call, 0, "'RandomWalk'");
      std::vector<double> bi{0.0, 0.0, 0.0};
      double numerator = 1.0;
      std::vector<double> den{1.0, -0.5};  // the default filter, in every release
      if (with_filter) {
        bi = list_after(call, 0, "'BiasInstability'");
        numerator = scalar_after(call, 0, "'Numerator', ");
        den = list_after(call, 0, "'Denominator'");
      } else {
        EXPECT_EQ(call.find("BiasInstability"), std::string::npos) << "no filter before R2023b";
      }
      ASSERT_EQ(den.size(), 2u);
      for (std::size_t i = 0; i < 3; ++i) {
        const std::string name = (gyro ? kGyro : kAccel)[i];
        Sim s;
        s.label = std::string("matlab") + (with_filter ? "" : "-pre-R2023b") + " " + name;
        s.channels = {name};
        s.twin_key_suffix = with_filter ? "" : "/matlab-pre-R2023b";
        const double b = numerator / den[0], a1 = den[1] / den[0];
        const double white = nd[i] * std::sqrt(BW), step = walk[i] / std::sqrt(BW), gain = bi[i];
        s.model_si = {{{ProcessKind::wn, white * white}, {ProcessKind::rw, step * step}}};
        if (with_filter) s.model_si.processes.push_back({ProcessKind::gm, b * b * gain * gain, -a1});
        struct State {
          double z = 0.0, r = 0.0;
        };
        auto st = std::make_shared<State>();
        s.step = [=](std::mt19937_64& e) {
          const double w1 = normal(e, 0.0, 1.0), w2 = normal(e, 0.0, 1.0), w3 = normal(e, 0.0, 1.0);
          const double y = b * (gain * w1) + st->z;  // filter(b, [1 a1], x): y = b x + z; z = -a1 y
          st->z = -a1 * y;
          st->r += step * w3;
          return white * w2 + y + st->r;
        };
        check(s, reported, projections, "matlab", seed++);
      }
    }
  }
}

// Basilisk imuSensor: GaussMarkov::computeNextState, x = A x + P w, no bound.
TEST(SimulatorExport, BasiliskSnippetReproducesItsProjection) {
  const auto f = file(Estimator::basilisk);
  const auto reported = reported_twin_errors(f.text);
  const auto projections = pipeline::simulator_projections(Estimator::basilisk, imu_record());
  EXPECT_EQ(scalar_after(f.text, 0, "IMU_RATE_HZ = "), kRate);
  std::uint64_t seed = 51;
  for (const bool gyro : {true, false}) {
    const auto P = list_after(f.text, 0, gyro ? "imu.PMatrixGyro = " : "imu.PMatrixAccel = ");
    const auto A = list_after(f.text, 0, gyro ? "imu.AMatrixGyro = " : "imu.AMatrixAccel = ");
    ASSERT_EQ(P.size(), 3u);
    ASSERT_EQ(A.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      const std::string name = (gyro ? kGyro : kAccel)[i];
      Sim s;
      s.label = "basilisk " + name;
      s.channels = {name};
      const double p = P[i], a = A[i];
      ASSERT_GE(a, 0.0);
      ASSERT_LE(a, 1.0);
      if (a == 0.0)
        s.model_si = {{{ProcessKind::wn, p * p}}};
      else if (a == 1.0)
        s.model_si = {{{ProcessKind::rw, p * p}}};
      else
        s.model_si = {{{ProcessKind::gm, p * p, a}}};
      auto x = std::make_shared<double>(0.0);
      s.step = [=](std::mt19937_64& e) {
        const double w = normal(e, 0.0, 1.0);  // noise first, then the propagation
        *x = a * *x + p * w;
        return *x;
      };
      check(s, reported, projections, "basilisk", seed++);
    }
  }
}

// ------------------------------------------------------------ the projections

TEST(SimulatorExport, DroppedTermsAreNamed) {
  const auto proj = pipeline::simulator_projections(Estimator::gazebo, imu_record());
  ASSERT_EQ(proj.size(), 6u);
  const auto dropped = [&](const std::string& name, const std::string& what) {
    for (const auto& p : proj)
      if (p.channel == name)
        for (const auto& d : p.dropped)
          if (d.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(dropped("gz", "SIN 12.5 Hz"));
  EXPECT_TRUE(dropped("gx", "MA1's theta = 0.3"));
  EXPECT_TRUE(dropped("ax", "QN"));
  EXPECT_TRUE(dropped("ay", "DR"));
  EXPECT_FALSE(dropped("az", ""));  // WN+RW+GM: the random walk goes to the Gauss-Markov term
  const std::string text = file(Estimator::gazebo).text;
  const std::size_t line = text.find("gz: dropped: ");
  ASSERT_NE(line, std::string::npos);
  EXPECT_NE(text.substr(line, text.find('\n', line) - line).find("SIN 12.5 Hz (A = 0.03 deg/s)"), std::string::npos);
}

// Where the target can carry the whole twin, the projection is the twin:
// the accelerometer az (WN+RW+GM) in NaveGo's shape, and in MATLAB's when it
// is its sensor's only axis (the one filter's phi its own). Beside ax and
// ay (T_c 60 s and 30 s) MATLAB's common phi costs az its own.
TEST(SimulatorExport, AnExpressibleTwinIsReproduced) {
  const auto twin_error = [](Estimator e, const pipeline::AnalysisResult& r, const std::string& target) {
    for (const auto& p : pipeline::simulator_projections(e, r))
      if (p.channel == "az" && p.target == target) return p.twin_error;
    ADD_FAILURE() << target << ": no projection of az";
    return std::numeric_limits<double>::quiet_NaN();
  };
  EXPECT_LT(twin_error(Estimator::navego, imu_record(), "navego"), 0.01);
  pipeline::AnalysisResult alone = imu_record();
  alone.channels.erase(alone.channels.begin() + 3, alone.channels.begin() + 5);  // ax, ay
  EXPECT_LT(twin_error(Estimator::matlab, alone, "matlab"), 0.01);
  EXPECT_GT(twin_error(Estimator::matlab, imu_record(), "matlab"), 0.1);
}

TEST(SimulatorExport, AChannelWithoutItsTwinIsRefused) {
  pipeline::AnalysisResult r = imu_record();
  r.channels[1].model.composite.reset();
  for (const Estimator e :
       {Estimator::gazebo, Estimator::rotors, Estimator::navego, Estimator::matlab, Estimator::basilisk}) {
    try {
      file(e, r);
      ADD_FAILURE() << pipeline::estimator_name(e) << ": no refusal";
    } catch (const UsageError& err) {
      EXPECT_EQ(err.field(), cubecal::Field::estimators);
      const std::string m = err.what();
      EXPECT_NE(m.find("gy"), std::string::npos) << m;
      EXPECT_NE(m.find("twin"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

TEST(SimulatorExport, AGyroscopeAloneLeavesTheAccelerometerOut) {
  pipeline::AnalysisResult r = imu_record();
  r.channels.resize(3);
  for (const Estimator e :
       {Estimator::gazebo, Estimator::rotors, Estimator::navego, Estimator::matlab, Estimator::basilisk}) {
    const auto f = file(e, r);
    EXPECT_EQ(f.missing, "accelerometer") << pipeline::estimator_name(e);
    EXPECT_NE(f.text.find("accelerometer terms absent"), std::string::npos) << pipeline::estimator_name(e);
  }
  EXPECT_EQ(file(Estimator::gazebo, r).text.find("<linear_acceleration>"), std::string::npos);
}

}  // namespace
}  // namespace cubecal
