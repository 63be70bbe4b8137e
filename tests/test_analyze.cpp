// Static characterization: temperature regression, drift, covariance, the
// analyze pipeline on records with known parameters, its JSON and Kalibr
// output, and the six real ADIS16405 runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "cubecal/noise/covariance.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

// White noise (sigma per sample) + bias random walk (increment walk*dt per
// step), the paper's eq. 1-2 without quantization.
using cubecal::test::white_plus_walk;

TEST(Temperature, ExactPolynomialFromNoiseFreeData) {
  // docs/formulas/drift-covariance-temperature.md §3.5: b(T) = 0.01 + 2e-4 (T-25) - 3e-6 (T-25)^2 over -20..60 degC.
  std::vector<double> T, y;
  for (int i = 0; i <= 800; ++i) {
    const double t = -20.0 + 0.1 * i;
    T.push_back(t);
    y.push_back(0.01 + 2e-4 * (t - 25) - 3e-6 * (t - 25) * (t - 25));
  }
  const auto f = fit_temperature(y, T, 2);
  // Back to powers of (T - 25): c1 + 2 c2 (t_ref - 25) = 2e-4 etc.
  const double d = f.t_ref - 25.0;
  EXPECT_NEAR(f.coeff[2], -3e-6, 1e-15);
  EXPECT_NEAR(f.coeff[1] - 2 * f.coeff[2] * d, 2e-4, 1e-14);
  EXPECT_NEAR(f.coeff[0] - f.coeff[1] * d + f.coeff[2] * d * d, 0.01, 1e-13);
  EXPECT_NEAR(f.r2, 1.0, 1e-12);
}

TEST(Temperature, CoefficientWithinUncertaintyOverSeeds) {
  // The paper's magnetometer: 0.7 mGauss/degC under a daily +-5 degC swing,
  // white 3 mGauss and a bias random walk of 0.0034 mGauss/s: the residuals
  // are strongly correlated, and the reported sigma must still cover.
  const double dt = 1.0;
  const std::size_t n = 3 * 86400;
  int inside = 0;
  const int seeds = 20;
  for (int s = 1; s <= seeds; ++s) {
    auto y = white_plus_walk(n, dt, 3.0, 0.0034, 100 + s, 210.0);
    std::vector<double> T(n);
    for (std::size_t i = 0; i < n; ++i) {
      T[i] = 25.0 + 5.0 * std::sin(2 * std::numbers::pi * static_cast<double>(i) * dt / 86400.0 + s);
      y[i] += 0.7 * (T[i] - 25.0);
    }
    const auto f = fit_temperature(y, T, 1);
    inside += std::abs(f.coeff[1] - 0.7) < 2.0 * f.coeff_sigma[1];
  }
  std::printf("  temperature coefficient within 2 sigma: %d of %d seeds\n", inside, seeds);
  // Nominal 95 %; batch means leave some slack. Binomial(20, 0.95): >= 16 at
  // more than 99.6 % probability.
  EXPECT_GE(inside, 16) << inside << " of " << seeds;
}

TEST(Temperature, ConstantTemperatureIsAnError) {
  std::vector<double> y(100, 1.0), T(100, 20.0);
  EXPECT_THROW(fit_temperature(y, T, 1), std::invalid_argument);
}

TEST(Drift, RampGivesCentredWindowMeans) {
  // y = r t: the moving average at the window centre is r t_c; minus the mean.
  const double r = 0.002, dt = 0.5;
  std::vector<double> y(1000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = r * static_cast<double>(i) * dt;
  const auto d = bias_drift(y, dt, 100, 10);
  ASSERT_FALSE(d.t.empty());
  const double mean_t = 0.5 * 999 * dt;
  for (std::size_t k = 0; k < d.t.size(); ++k) EXPECT_NEAR(d.drift[k], r * (d.t[k] - mean_t), 1e-12);
  EXPECT_EQ(d.t.size(), 91u);  // windows starting at 0, 10, ..., 900
}

TEST(Covariance, KnownMatrixWithinSampling) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  const std::size_t n = 200000;
  std::vector<double> a(n), b(n);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = g(rng);
    b[i] = 0.5 * a[i] + g(rng);
  }
  const auto c = covariance_matrix({a, b});
  // Standard error of a sample covariance ~ sqrt((s_aa s_bb + s_ab^2)/n) < 0.003 here.
  EXPECT_NEAR(c[0][0], 1.0, 0.015);
  EXPECT_NEAR(c[0][1], 0.5, 0.015);
  EXPECT_NEAR(c[1][1], 1.25, 0.015);
  EXPECT_EQ(c[0][1], c[1][0]);
  const auto first = covariance_matrix({a, b}, 13000);  // the paper's first 13000 samples
  EXPECT_NEAR(first[0][1], 0.5, 0.05);
}

io::Series series_of(std::vector<std::vector<double>> ch, std::vector<std::string> names, double rate) {
  io::Series s;
  s.file = "memory";
  s.names = std::move(names);
  s.channels = std::move(ch);
  s.rate_hz = rate;
  s.tau0 = 1.0 / rate;
  s.segments = {{0, s.channels[0].size()}};
  return s;
}

TEST(Analyze, RecoversNoiseTermsOverSeeds) {
  // White sigma_n and random walk sigma_mu at 10 Hz, 12 h: N = sigma_n sqrt(dt);
  // B is the minimum of the model's exact Allan deviation / 0.664.
  const double dt = 0.1, sn = 13.0e-3, smu = 0.66e-3;
  const RandomWalkModel truth{sn, smu, dt, 0.0};
  double min_var = 1e300;
  for (std::size_t m = 1; m < 100000; ++m) min_var = std::min(min_var, avar(truth, m));
  const double B = std::sqrt(min_var) / kFlickerFloor;
  const double N = sn * std::sqrt(dt);
  int n_in = 0, b_in = 0, sigma_n_in = 0;
  const int seeds = 8;
  for (int s = 1; s <= seeds; ++s) {
    auto y = white_plus_walk(12 * 36000, dt, sn, smu, 40 + s);
    pipeline::AnalyzeRequest req;
    req.units = {*parse_unit("deg/s")};
    req.grid = parse_tau_grid("log:20");
    const auto r = pipeline::run_analyze(series_of({y}, {"g"}, 10.0), req);
    const auto& c = r.channels[0];
    n_in += std::abs(c.noise.readoffs.N.value - N) < 3 * c.noise.readoffs.N.sigma;
    b_in += std::abs(c.noise.readoffs.B.value - B) < 3 * c.noise.readoffs.B.sigma;
    ASSERT_TRUE(c.model.ok) << c.model.error;
    sigma_n_in += std::abs(c.model.random_walk.sigma_n / sn - 1.0) < 0.02;
  }
  std::printf("  inside 3 sigma: N %d, B %d of %d seeds; sigma_n within 2 %%: %d\n", n_in, b_in, seeds, sigma_n_in);
  EXPECT_GE(n_in, seeds - 1) << "N inside 3 sigma in " << n_in << " of " << seeds;
  EXPECT_GE(b_in, seeds - 1) << "B inside 3 sigma in " << b_in << " of " << seeds;
  EXPECT_GE(sigma_n_in, seeds - 1);
}

TEST(Analyze, JsonKeysAndKalibrYaml) {
  auto gx = white_plus_walk(200000, 0.01, 0.02, 0.01, 1, 0.3);
  auto ax = white_plus_walk(200000, 0.01, 0.002, 0.0005, 2, 1.0);
  std::vector<double> temp(gx.size());
  for (std::size_t i = 0; i < temp.size(); ++i) temp[i] = 20.0 + 1e-4 * static_cast<double>(i);
  auto s = series_of({gx, ax}, {"gx", "ax"}, 100.0);
  s.extra_names = {"temp"};
  s.extra = {temp};
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s"), *parse_unit("g")};
  req.grid = parse_tau_grid("log:10");
  req.temp_index = 0;
  const auto r = pipeline::run_analyze(s, req);
  const auto j = nlohmann::json::parse(pipeline::analysis_json(r, {"cubecal analyze test", "/imu0"}));
  for (const char* k : {"file", "samples", "rate_hz", "duration_s"}) EXPECT_TRUE(j["input"].contains(k)) << k;
  const auto& c = j["channels"][0];
  for (const char* k : {"name", "unit", "kind", "mean", "adev", "noise", "model", "temperature"})
    EXPECT_TRUE(c.contains(k)) << k;
  for (const char* k : {"tau", "dev", "lo", "hi", "n"}) EXPECT_TRUE(c["adev"].contains(k)) << k;
  for (const char* k : {"arw", "bias_instability", "time_constant_s", "rate_random_walk", "quantization",
                        "rate_ramp", "fit"})
    EXPECT_TRUE(c["noise"].contains(k)) << k;
  for (const char* k : {"value", "unit", "sigma"}) EXPECT_TRUE(c["noise"]["arw"].contains(k)) << k;
  EXPECT_EQ(c["noise"]["arw"]["unit"], "deg/sqrt(h)");
  EXPECT_EQ(c["noise"]["bias_instability"]["unit"], "deg/h");
  EXPECT_EQ(c["kind"], "rate");
  for (const char* k : {"sigma_n", "sigma_mu", "unit", "gauss_markov"}) EXPECT_TRUE(c["model"].contains(k)) << k;
  for (const char* k : {"offset", "coeff", "unit", "r2"}) EXPECT_TRUE(c["temperature"].contains(k)) << k;
  EXPECT_TRUE(j["covariance"].contains("matrix"));
  EXPECT_EQ(j["covariance"]["matrix"].size(), 2u);
  EXPECT_EQ(j["channels"][1]["noise"]["arw"]["unit"], "g*sqrt(h)");

  // Kalibr: noise density = N in rad/s/sqrt(Hz) (white sigma * sqrt(dt)).
  const std::string y = pipeline::kalibr_yaml(r, {"cmd", "/imu0"});
  const auto pos = y.find("gyroscope_noise_density: ");
  ASSERT_NE(pos, std::string::npos) << y;
  const double nd = std::stod(y.substr(pos + 25));
  EXPECT_NEAR(nd / (0.02 * std::sqrt(0.01) * std::numbers::pi / 180.0), 1.0, 0.03);
  EXPECT_NE(y.find("accelerometer_random_walk: "), std::string::npos);
  EXPECT_NE(y.find("update_rate: 100"), std::string::npos);
  EXPECT_NE(y.find("rostopic: /imu0"), std::string::npos);
}

TEST(Analyze, TemperatureCompensationLowersTheLongTauCurve) {
  // A daily temperature swing through 0.7 mGauss/degC raises the Allan curve
  // at long tau; compensated, the bias instability drops back.
  const double dt = 1.0;
  const std::size_t n = 3 * 86400;
  auto y = white_plus_walk(n, dt, 3.0, 0.0034, 9, 210.0);
  std::vector<double> T(n);
  for (std::size_t i = 0; i < n; ++i) {
    T[i] = 25.0 + 5.0 * std::sin(2 * std::numbers::pi * static_cast<double>(i) * dt / 86400.0);
    y[i] += 0.7 * (T[i] - 25.0);
  }
  auto s = series_of({y}, {"mx"}, 1.0);
  s.extra_names = {"temp"};
  s.extra = {T};
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("mGauss")};
  req.grid = parse_tau_grid("log:10");
  req.temp_index = 0;
  const auto r = pipeline::run_analyze(s, req);
  const auto& c = r.channels[0];
  ASSERT_TRUE(c.temperature);
  EXPECT_NEAR(c.temperature->fit.coeff[1], 0.7, 3 * c.temperature->fit.coeff_sigma[1]);
  EXPECT_LT(c.temperature->compensated.readoffs.B.value, 0.8 * c.noise.readoffs.B.value);
}

TEST(Analyze, AdisRunsAnalyzedWithoutError) {
  // The six real ADIS16405 static runs (100 Hz, 2.78 h): every channel gets
  // noise terms; the gyro ARW agrees between runs and with the datasheet's
  // 2 deg/sqrt(h) to within the spread of real parts.
  std::vector<double> arw;
  for (int run = 1; run <= 6; ++run) {
    io::SeriesOptions so;
    const auto s = io::read_series(std::string(CUBECAL_SHARED_DATA) + "/imu/adis16405/run" + std::to_string(run) +
                                       ".csv.gz",
                                   so);
    ASSERT_EQ(s.samples(), 1000000u);
    pipeline::AnalyzeRequest req;
    for (int k = 0; k < 3; ++k) req.units.push_back(*parse_unit("deg/s"));
    for (int k = 0; k < 3; ++k) req.units.push_back(*parse_unit("g"));
    req.grid = parse_tau_grid("log:10");
    const auto r = pipeline::run_analyze(s, req);
    ASSERT_EQ(r.channels.size(), 6u);
    for (int k = 0; k < 3; ++k) {
      const auto N = display(r.channels[k].noise.readoffs.N, Term::N, r.channels[k].unit);
      ASSERT_TRUE(r.channels[k].noise.readoffs.N.valid);
      arw.push_back(N.value);
    }
    for (const auto& c : r.channels) EXPECT_TRUE(std::isfinite(c.mean));
  }
  for (double v : arw) {
    EXPECT_GT(v, 1.5);
    EXPECT_LT(v, 3.0);
  }
}

}  // namespace
}  // namespace cubecal
