// Estimator configuration files (pipeline/estimator_config): each format read
// back and its numbers checked against closed forms of the analysis result,
// the simulated truth, the unit conversions of each estimator, --inflate, and
// the rules for missing sensors and terms not identified.
#include "cubecal/pipeline/estimator_config.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "estimator_yaml.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

using test::number;
using test::triple;
using test::yaml_keys;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kG = 9.80665;
constexpr double kRate = 100.0;

std::vector<double> white_plus_walk(std::size_t n, double sigma, double walk, std::uint64_t seed, double bias = 0.0) {
  return test::white_plus_walk(n, 1.0 / kRate, sigma, walk, seed, bias);
}

pipeline::AnalysisResult analyze(std::vector<std::vector<double>> ch, std::vector<std::string> names,
                                 const std::string& units) {
  io::Series s;
  s.file = "memory";
  s.names = std::move(names);
  s.channels = std::move(ch);
  s.rate_hz = kRate;
  s.tau0 = 1.0 / kRate;
  s.segments = {{0, s.channels[0].size()}};
  pipeline::AnalyzeRequest req;
  std::stringstream ss(units);
  for (std::string u; std::getline(ss, u, ',');) req.units.push_back(*parse_unit(u));
  req.grid = parse_tau_grid("log:10");
  return pipeline::run_analyze(s, req);
}

// Three gyro axes (deg/s, white 0.02 deg/s per sample: N = 0.002 deg/s/sqrt(Hz))
// and three accelerometer axes (g, white 0.002 g: N = 2e-4 g/sqrt(Hz)) with
// a bias random walk, z of the accelerometer at 1 g.
const pipeline::AnalysisResult& imu_record() {
  static const pipeline::AnalysisResult r = [] {
    const std::size_t n = 100000;
    return analyze({white_plus_walk(n, 0.02, 0.01, 1), white_plus_walk(n, 0.02, 0.01, 2),
                    white_plus_walk(n, 0.02, 0.01, 3), white_plus_walk(n, 0.002, 0.0005, 4),
                    white_plus_walk(n, 0.002, 0.0005, 5), white_plus_walk(n, 0.002, 0.0005, 6, 1.0)},
                   {"gx", "gy", "gz", "ax", "ay", "az"}, "deg/s,deg/s,deg/s,g,g,g");
  }();
  return r;
}

// The N of every output: the slope read-off, the -1/2 line at tau = 1 s.
const TermEstimate& white_term(const pipeline::ChannelAnalysis& c) { return c.noise.readoffs.N; }

// The closed forms of noise-terms.md §8.2 from the result, per channel in SI.
double white_si(const pipeline::ChannelAnalysis& c) {
  EXPECT_TRUE(c.noise.readoffs.N.valid) << c.name;
  return white_term(c).value * c.unit.to_si;
}
// K only when significant (value > 2 sigma): the fit's, else the read-off's,
// else the bound min sigma(tau) sqrt(3/tau).
double walk_si(const pipeline::ChannelAnalysis& c) {
  const auto sig = [](const TermEstimate& t) { return t.valid && t.value > 2.0 * t.sigma; };
  if (sig(c.noise.fit.K)) return c.noise.fit.K.value * c.unit.to_si;
  if (sig(c.noise.readoffs.K)) return c.noise.readoffs.K.value * c.unit.to_si;
  double b = INFINITY;
  for (const auto& p : c.noise.adev) b = std::min(b, p.dev * std::sqrt(3.0 / p.tau));
  return b * c.unit.to_si;
}

// The simulated model's N as the read-off defines it: its Allan deviation
// sqrt(N^2 / tau + K^2 tau / 3) times sqrt(tau), averaged over the taus N was
// read over with the weights of the read-off (1 / rel^2 of the measured
// intervals).
double model_white_read(const pipeline::ChannelAnalysis& c, double n, double k) {
  const TermEstimate& t = white_term(c);
  double sw = 0.0, swv = 0.0;
  for (const auto& p : c.noise.adev) {
    if (p.tau < t.tau_lo || p.tau > t.tau_hi) continue;
    const double rel = (p.interval.hi - p.interval.lo) / (2.0 * p.dev);
    const double w = 1.0 / (rel * rel);
    sw += w;
    swv += w * std::sqrt(n * n + k * k * p.tau * p.tau / 3.0);
  }
  return swv / sw;
}
// Largest over the channels [first, first + 3).
template <class F>
double largest(const pipeline::AnalysisResult& r, std::size_t first, F f) {
  double m = 0.0;
  for (std::size_t i = first; i < first + 3; ++i) m = std::max(m, f(r.channels[i]));
  return m;
}

pipeline::EstimatorFile file(pipeline::Estimator e, const pipeline::AnalysisResult& r, double inflate = 1.0) {
  return pipeline::estimator_config(e, r, {"cubecal analyze test", "/imu7", inflate});
}

constexpr double kExact = 1e-9;  // the files print 10 significant digits

TEST(EstimatorConfig, KalibrNoiseDensityIsTheSimulatedN) {
  const auto& r = imu_record();
  const auto y = yaml_keys(file(pipeline::Estimator::kalibr, r).text);
  // Truth: N = sigma sqrt(dt), K = walk sqrt(dt); read at tau = 1 s, where
  // the walk carries 8 % (gyro) and 2 % (accelerometer) of the variance, the
  // model gives model_white_read. The largest axis lies within 3 sigma of it.
  const double dt = 1.0 / kRate;
  const double nd = number(y, "gyroscope_noise_density");
  std::size_t axis = 0;
  for (std::size_t i = 0; i < 3; ++i)
    if (white_si(r.channels[i]) > white_si(r.channels[axis])) axis = i;
  const double n_true = model_white_read(r.channels[axis], 0.02 * std::sqrt(dt), 0.01 * std::sqrt(dt)) * kDeg;
  EXPECT_GT(n_true, 0.02 * std::sqrt(dt) * kDeg);
  EXPECT_NEAR(nd, n_true, 3.0 * white_term(r.channels[axis]).sigma * kDeg) << "axis " << r.channels[axis].name;
  std::size_t aaxis = 3;
  for (std::size_t i = 3; i < 6; ++i)
    if (white_si(r.channels[i]) > white_si(r.channels[aaxis])) aaxis = i;
  const double na_true = model_white_read(r.channels[aaxis], 0.002 * std::sqrt(dt), 0.0005 * std::sqrt(dt)) * kG;
  EXPECT_NEAR(number(y, "accelerometer_noise_density"), na_true, 3.0 * white_term(r.channels[aaxis]).sigma * kG);
}

TEST(EstimatorConfig, KalibrKeysAreTheLargestAxisInSi) {
  const auto& r = imu_record();
  const std::string text = file(pipeline::Estimator::kalibr, r).text;
  const auto y = yaml_keys(text);
  EXPECT_NEAR(number(y, "gyroscope_noise_density") / largest(r, 0, white_si), 1.0, kExact);
  EXPECT_NEAR(number(y, "gyroscope_random_walk") / largest(r, 0, walk_si), 1.0, kExact);
  EXPECT_NEAR(number(y, "accelerometer_noise_density") / largest(r, 3, white_si), 1.0, kExact);
  EXPECT_NEAR(number(y, "accelerometer_random_walk") / largest(r, 3, walk_si), 1.0, kExact);
  EXPECT_EQ(number(y, "update_rate"), kRate);
  EXPECT_EQ(y.at("rostopic"), "/imu7");
  // The definitions and units travel with the numbers.
  for (const char* s : {"sigma_w^2 / tau", "sigma_bw^2 tau / 3", "[rad/s/sqrt(Hz)]", "[m/s^3/sqrt(Hz)]",
                        "largest over its axes", "(inflate"})
    EXPECT_NE(text.find(s), std::string::npos) << s;
}

TEST(EstimatorConfig, OpenVinsImuChainHoldsTheKalibrNumbers) {
  const auto& r = imu_record();
  const std::string text = file(pipeline::Estimator::openvins, r).text;
  EXPECT_EQ(text.rfind("%YAML:1.0\n", 0), 0u) << "OpenCV's FileStorage wants the directive first";
  const auto y = yaml_keys(text);
  const auto k = yaml_keys(file(pipeline::Estimator::kalibr, r).text);
  ASSERT_TRUE(y.count("imu0"));
  for (const char* key : {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
                          "accelerometer_random_walk", "update_rate"})
    EXPECT_EQ(number(y, key), number(k, key)) << key;
  EXPECT_EQ(number(y, "time_offset"), 0.0);
  EXPECT_EQ(y.at("rostopic"), "/imu7");
  EXPECT_NE(text.find("  T_i_b:\n    - [1.0, 0.0, 0.0, 0.0]\n"), std::string::npos);
}

TEST(EstimatorConfig, VinsBlockIsContinuousTimeWithMeasuredGravity) {
  const auto& r = imu_record();
  const std::string text = file(pipeline::Estimator::vins, r).text;
  const auto y = yaml_keys(text);
  EXPECT_NEAR(number(y, "gyr_n") / largest(r, 0, white_si), 1.0, kExact);
  EXPECT_NEAR(number(y, "gyr_w") / largest(r, 0, walk_si), 1.0, kExact);
  EXPECT_NEAR(number(y, "acc_n") / largest(r, 3, white_si), 1.0, kExact);
  EXPECT_NEAR(number(y, "acc_w") / largest(r, 3, walk_si), 1.0, kExact);
  double g2 = 0.0;
  for (std::size_t i = 3; i < 6; ++i) g2 += std::pow(r.channels[i].mean * kG, 2);
  EXPECT_NEAR(number(y, "g_norm"), std::sqrt(g2), 1e-7);
  EXPECT_NEAR(number(y, "g_norm"), kG, 1e-3 * kG);
  EXPECT_NE(text.find("continuous-time noise densities"), std::string::npos);
}

TEST(EstimatorConfig, KfGinsUnitsPerAxis) {
  const auto& r = imu_record();
  const std::string text = file(pipeline::Estimator::kf_gins, r).text;
  const auto y = yaml_keys(text);
  ASSERT_TRUE(y.count("imunoise"));
  const auto arw = triple(y, "arw"), vrw = triple(y, "vrw"), gb = triple(y, "gbstd"), ab = triple(y, "abstd");
  double tmin = INFINITY;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& g = r.channels[i];
    const auto& a = r.channels[i + 3];
    // arw [deg/sqrt(h)] = N [deg/s*sqrt(s)] * 60: the display unit analysis.json quotes.
    EXPECT_NEAR(arw[i] / (white_term(g).value * 60.0), 1.0, kExact) << g.name;
    EXPECT_NEAR(arw[i] / display(white_term(g), Term::N, g.unit).value, 1.0, kExact) << g.name;
    // vrw [m/s/sqrt(h)] = N [m/s^2/sqrt(Hz)] * 60.
    EXPECT_NEAR(vrw[i] / (white_term(a).value * kG * 60.0), 1.0, kExact) << a.name;
    // Bias instability (deg/h; mGal = 1e-5 m/s^2), or the bound without a minimum.
    for (const auto* c : {&g, &a}) {
      const auto& ro = c->noise.readoffs;
      // The read-off B, or without a minimum in the record the bound
      // sigma_min / 0.664 at the end where the curve is lowest.
      const double b = ro.B.valid ? ro.B.value : ro.sigma_min / kFlickerFloor;
      const double t = ro.tau_min;
      tmin = std::min(tmin, t);
      if (c == &g) {
        EXPECT_NEAR(gb[i] / (b * 3600.0), 1.0, kExact) << g.name;
      } else {
        EXPECT_NEAR(ab[i] / (b * kG / 1e-5), 1.0, kExact) << a.name;
      }
    }
  }
  EXPECT_NEAR(number(y, "corrtime") / (tmin / 3600.0), 1.0, kExact);
  EXPECT_FALSE(y.count("gsstd")) << "scale-factor terms are not measured: left to the user";
  for (const char* s : {"[deg/sqrt(h)]", "[m/s/sqrt(h)]", "[deg/h]", "[mGal]", "[h]", "Gauss-Markov"})
    EXPECT_NE(text.find(s), std::string::npos) << s;
}

TEST(EstimatorConfig, InflateScalesEveryNoiseTermExactly) {
  const auto& r = imu_record();
  const double K = 2.5;
  const std::vector<std::pair<pipeline::Estimator, std::vector<std::string>>> cases{
      {pipeline::Estimator::kalibr,
       {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
        "accelerometer_random_walk"}},
      {pipeline::Estimator::openvins,
       {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
        "accelerometer_random_walk"}},
      {pipeline::Estimator::vins, {"acc_n", "gyr_n", "acc_w", "gyr_w"}}};
  for (const auto& [e, keys] : cases) {
    const auto one = yaml_keys(file(e, r).text);
    const std::string text = file(e, r, K).text;
    const auto k = yaml_keys(text);
    for (const auto& key : keys) EXPECT_NEAR(number(k, key) / number(one, key), K, K * kExact) << key;
    for (const char* same : {"update_rate", "g_norm", "time_offset"})
      if (one.count(same)) {
        EXPECT_EQ(number(k, same), number(one, same)) << same;
      }
    EXPECT_NE(text.find("measured value x 2.5 (inflate)"), std::string::npos);
  }
  const auto one = yaml_keys(file(pipeline::Estimator::kf_gins, r).text);
  const auto k = yaml_keys(file(pipeline::Estimator::kf_gins, r, K).text);
  for (const char* key : {"arw", "vrw", "gbstd", "abstd"})
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(triple(k, key)[i] / triple(one, key)[i], K, K * kExact) << key;
  EXPECT_EQ(number(k, "corrtime"), number(one, "corrtime"));
}

TEST(EstimatorConfig, InflateBelowOneIsRefused) {
  EXPECT_THROW(file(pipeline::Estimator::kalibr, imu_record(), 0.5), UsageError);
  EXPECT_THROW(file(pipeline::Estimator::kalibr, imu_record(), NAN), UsageError);
}

TEST(EstimatorConfig, GyroOnlyRecordSaysTheAccelerometerTermsAreAbsent) {
  const auto r =
      analyze({white_plus_walk(20000, 0.02, 0.0, 1), white_plus_walk(20000, 0.03, 0.0, 2)}, {"gx", "gy"}, "deg/s");
  for (const auto e : {pipeline::Estimator::kalibr, pipeline::Estimator::openvins, pipeline::Estimator::vins,
                       pipeline::Estimator::kf_gins}) {
    const auto f = file(e, r);
    EXPECT_EQ(f.missing, "accelerometer") << f.name;
    const auto y = yaml_keys(f.text);
    for (const char* key :
         {"accelerometer_noise_density", "accelerometer_random_walk", "acc_n", "acc_w", "vrw", "abstd"})
      EXPECT_FALSE(y.count(key)) << f.name << " " << key;
    EXPECT_NE(f.text.find("accelerometer terms absent: the record has no acceleration (g, m/s^2) channel"),
              std::string::npos)
        << f.text;
    if (e == pipeline::Estimator::vins) {
      EXPECT_NE(f.text.find("g_norm: 9.80665  # [m/s^2] standard gravity"), std::string::npos);
    }
  }
  // KF-GINS takes three values: two axes give the larger on all three.
  const auto y = yaml_keys(file(pipeline::Estimator::kf_gins, r).text);
  const double big = std::max(display(white_term(r.channels[0]), Term::N, r.channels[0].unit).value,
                              display(white_term(r.channels[1]), Term::N, r.channels[1].unit).value);
  for (double v : triple(y, "arw")) EXPECT_NEAR(v / big, 1.0, kExact);
  // The default imu.yaml of `analyze --out` is the Kalibr file.
  EXPECT_EQ(pipeline::kalibr_yaml(r, {"cubecal analyze test", "/imu7"}), file(pipeline::Estimator::kalibr, r).text);
}

TEST(EstimatorConfig, UnidentifiedRandomWalkIsAMarkedUpperBoundNeverZero) {
  // Pure white noise: no +1/2 slope. The walk is the bound min sigma(tau) sqrt(3/tau).
  const auto r = analyze({white_plus_walk(20000, 0.02, 0.0, 9)}, {"gx"}, "deg/s");
  const auto& c = r.channels[0];
  ASSERT_FALSE(c.noise.fit.K.valid || c.noise.readoffs.K.valid) << "the record was meant to show no K";
  const std::string text = file(pipeline::Estimator::kalibr, r).text;
  const auto y = yaml_keys(text);
  const double walk = number(y, "gyroscope_random_walk");
  EXPECT_GT(walk, 0.0);
  EXPECT_NEAR(walk / walk_si(c), 1.0, kExact);
  const auto line = text.substr(text.find("gyroscope_random_walk:"));
  EXPECT_NE(line.substr(0, line.find('\n')).find("UPPER BOUND: no +1/2 slope"), std::string::npos) << line;
  // Without a minimum, KF-GINS gets the bias bound at the last tau, marked too.
  ASSERT_FALSE(c.noise.readoffs.B.valid);
  const std::string kf = file(pipeline::Estimator::kf_gins, r).text;
  const auto gb = kf.substr(kf.find("  gbstd:"));
  EXPECT_NE(gb.substr(0, gb.find('\n')).find("UPPER BOUND"), std::string::npos) << gb;
}

TEST(EstimatorConfig, RandomWalkIsWrittenOnlyWhenSignificant) {
  // A gyro whose fit finds a K with an uncertainty 6.5 x its value (as on
  // the ADIS16405 z axis): not a measurement. The file gets the bound, marked
  // UPPER BOUND with the estimate; at value = 2.01 sigma the fit's K is written.
  auto r = analyze({white_plus_walk(20000, 0.02, 0.0, 9)}, {"gx"}, "deg/s");
  auto& c = r.channels[0];
  c.noise.readoffs.K.valid = false;
  c.noise.fit.K = TermEstimate{true, 1e-3, 6.5e-3, 10.0, 200.0};
  double bound = INFINITY;
  for (const auto& p : c.noise.adev) bound = std::min(bound, p.dev * std::sqrt(3.0 / p.tau));
  std::string text = file(pipeline::Estimator::kalibr, r).text;
  EXPECT_NEAR(number(yaml_keys(text), "gyroscope_random_walk") / (bound * kDeg), 1.0, kExact);
  std::string line = text.substr(text.find("gyroscope_random_walk:"));
  line = line.substr(0, line.find('\n'));
  EXPECT_NE(line.find("UPPER BOUND: K not significant"), std::string::npos) << line;
  EXPECT_NE(line.find("not above 2 sigma"), std::string::npos) << line;
  const auto v = yaml_keys(file(pipeline::Estimator::vins, r).text);
  EXPECT_NEAR(number(v, "gyr_w") / (bound * kDeg), 1.0, kExact);

  c.noise.fit.K.sigma = 1e-3 / 2.01;
  text = file(pipeline::Estimator::kalibr, r).text;
  EXPECT_NEAR(number(yaml_keys(text), "gyroscope_random_walk") / (1e-3 * kDeg), 1.0, kExact);
  line = text.substr(text.find("gyroscope_random_walk:"));
  line = line.substr(0, line.find('\n'));
  EXPECT_NE(line.find("five-term fit, significant (> 2 sigma)"), std::string::npos) << line;
}

TEST(EstimatorConfig, NoiseDensityIsTheNReadAtOneSecond) {
  // The N of the estimator files is the read-off, whatever the fit says.
  auto r = analyze({white_plus_walk(20000, 0.02, 0.0, 9)}, {"gx"}, "deg/s");
  auto& c = r.channels[0];
  c.noise.fit.N = TermEstimate{true, 2.0 * c.noise.readoffs.N.value, 1e-6, 0.01, 100.0};
  const auto y = yaml_keys(file(pipeline::Estimator::kalibr, r).text);
  EXPECT_NEAR(number(y, "gyroscope_noise_density") / (c.noise.readoffs.N.value * kDeg), 1.0, kExact);
}

TEST(EstimatorConfig, NoImuChannelOrConstantRecordIsAnError) {
  const auto mag = analyze({white_plus_walk(20000, 3.0, 0.0, 1)}, {"mx"}, "mGauss");
  EXPECT_THROW(file(pipeline::Estimator::kalibr, mag), UsageError);
  EXPECT_EQ(pipeline::kalibr_yaml(mag, {"cmd", "/imu0"}), "");  // the default imu.yaml is simply left out
  const auto flat = analyze({std::vector<double>(20000, 0.5)}, {"gx"}, "deg/s");
  try {
    file(pipeline::Estimator::vins, flat);
    ADD_FAILURE() << "a constant record gave noise parameters";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("channel gx"), std::string::npos) << e.what();
  }
}

TEST(EstimatorConfig, NamesAndFiles) {
  for (const char* n : {"kalibr", "openvins", "vins", "kf-gins"}) {
    const auto e = pipeline::parse_estimator(n);
    ASSERT_TRUE(e) << n;
    EXPECT_EQ(pipeline::estimator_name(*e), n);
  }
  EXPECT_FALSE(pipeline::parse_estimator("okvis"));
  EXPECT_EQ(pipeline::estimator_file(pipeline::Estimator::kalibr), "imu.yaml");
  EXPECT_EQ(pipeline::estimator_file(pipeline::Estimator::openvins), "kalibr_imu_chain.yaml");
}

}  // namespace
}  // namespace cubecal
