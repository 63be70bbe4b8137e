// Static characterization: temperature regression, drift, covariance, the
// analyze pipeline on records with known parameters, its JSON and Kalibr
// output, the six real ADIS16405 runs, and the spectral view (analyze --psd:
// run_psd of the record, its terms beside the Allan fit, its JSON).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "cubecal/error.hpp"
#include "cubecal/noise/covariance.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/pipeline/spectral_analysis.hpp"
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
  EXPECT_THROW(fit_temperature(y, T, 1), cubecal::CalibrationError);
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
  EXPECT_NEAR(c(0, 0), 1.0, 0.015);
  EXPECT_NEAR(c(0, 1), 0.5, 0.015);
  EXPECT_NEAR(c(1, 1), 1.25, 0.015);
  EXPECT_EQ(c(0, 1), c(1, 0));
  const auto first = covariance_matrix({a, b}, 13000);  // the paper's first 13000 samples
  EXPECT_NEAR(first(0, 1), 0.5, 0.05);
}

// The sums walked side by side in blocks are each the one add chain of its
// own terms in sample order: every entry is the two-pass definition's, to
// the bit, for channel counts on both sides of a group of sums and lengths
// on both sides of a block (a lane given another pair's operands, or a
// block edge dropping or repeating a sample, fails it).
TEST(Covariance, EqualsThePassPerSumDefinitionToTheBit) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(3.0, 2.0);
  for (const std::size_t k : {1u, 3u, 6u, 9u})
    for (const std::size_t n : {2u, 511u, 512u, 1537u, 40000u}) {
      std::vector<std::vector<double>> ch(k, std::vector<double>(n + 5));
      for (auto& c : ch)
        for (double& v : c) v = g(rng) * static_cast<double>(1 + rng() % 1000);
      std::vector<std::span<const double>> spans(ch.begin(), ch.end());
      for (const std::size_t count : {std::size_t{0}, n}) {
        const std::size_t used = count > 0 ? count : n + 5;
        std::vector<double> mean(k, 0.0);
        for (std::size_t a = 0; a < k; ++a) {
          for (std::size_t i = 0; i < used; ++i) mean[a] += ch[a][i];
          mean[a] /= static_cast<double>(used);
        }
        const auto got = covariance_matrix(spans, count);
        for (std::size_t a = 0; a < k; ++a)
          for (std::size_t b = a; b < k; ++b) {
            double s = 0.0;
            for (std::size_t i = 0; i < used; ++i) s += (ch[a][i] - mean[a]) * (ch[b][i] - mean[b]);
            const double want = s / static_cast<double>(used - 1);
            EXPECT_EQ(got(a, b), want) << k << " channels, " << used << " samples, " << a << "," << b;
            EXPECT_EQ(got(b, a), want);
          }
      }
    }
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
  for (const char* k :
       {"arw", "bias_instability", "time_constant_s", "rate_random_walk", "quantization", "rate_ramp", "fit"})
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
    const auto s =
        io::read_series(std::string(CUBECAL_SHARED_DATA) + "/imu/adis16405/run" + std::to_string(run) + ".csv.gz", so);
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

// ---------------------------------------------------------------------------
// The spectral view (AnalyzeRequest::psd)

TEST(SpectralView, DifferenceInCombinedSigmas) {
  // (spectrum - allan) / sqrt(s_s^2 + s_a^2) where both found the term;
  // nothing where either did not; Q left out when the spectrum has none.
  NoiseFit allan;
  allan.N = {true, 1.0, 0.1, 0.5, 2.0};
  allan.B = {true, 2.0, 0.3, 0.0, 0.0};
  allan.K = {false, 0.0, 0.0, 0.0, 0.0};
  pipeline::SpectralAnalysis s;
  const auto term = [](Term t, int alpha, TermEstimate e) {
    pipeline::PsdAllanTerm a;
    a.term = t;
    a.alpha = alpha;
    a.estimate = e;
    return a;
  };
  s.allan_terms = {term(Term::K, -2, {true, 3.0, 0.4, 0.0, 0.0}), term(Term::B, -1, {false, 0.0, 0.0, 0.0, 0.0}),
                   term(Term::N, 0, {true, 1.5, 0.2, 0.0, 0.0})};
  const auto v = pipeline::compare_views(allan, s);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].term, Term::N);
  EXPECT_EQ(v[1].term, Term::B);
  EXPECT_EQ(v[2].term, Term::K);
  ASSERT_TRUE(v[0].difference_sigmas.has_value());
  EXPECT_NEAR(*v[0].difference_sigmas, 0.5 / std::sqrt(0.05), 1e-15);
  EXPECT_EQ(v[0].allan.value, 1.0);
  EXPECT_EQ(v[0].spectrum.value, 1.5);
  EXPECT_FALSE(v[1].difference_sigmas.has_value());                                   // not in the spectrum
  EXPECT_FALSE(v[2].difference_sigmas.has_value());                                   // not in the Allan fit
  EXPECT_TRUE(pipeline::compare_views(allan, pipeline::SpectralAnalysis{}).empty());  // no fit: nothing
}

// Every field of two spectral views, exactly.
void expect_same_spectral(const pipeline::SpectralAnalysis& a, const pipeline::SpectralAnalysis& b) {
  const Psd &p = a.spectrum, &q = b.spectrum;
  EXPECT_EQ(p.rate_hz, q.rate_hz);
  EXPECT_EQ(p.window, q.window);
  EXPECT_EQ(p.detrend, q.detrend);
  EXPECT_EQ(p.segment_length, q.segment_length);
  EXPECT_EQ(p.overlap, q.overlap);
  EXPECT_EQ(p.segments, q.segments);
  EXPECT_EQ(p.samples_used, q.samples_used);
  EXPECT_EQ(p.enbw_hz, q.enbw_hz);
  EXPECT_EQ(p.bins_per_decade, q.bins_per_decade);
  EXPECT_EQ(p.frequency, q.frequency);
  EXPECT_EQ(p.density, q.density);
  EXPECT_EQ(p.edf, q.edf);
  EXPECT_EQ(p.first_bin, q.first_bin);
  EXPECT_EQ(p.bins, q.bins);
  EXPECT_EQ(p.bin_covariance, q.bin_covariance);
  const PowerLawFit &f = a.fit, &g = b.fit;
  EXPECT_EQ(f.f_lo, g.f_lo);
  EXPECT_EQ(f.f_hi, g.f_hi);
  EXPECT_EQ(f.bands, g.bands);
  EXPECT_EQ(f.chi2, g.chi2);
  EXPECT_EQ(f.dof, g.dof);
  EXPECT_EQ(f.scale, g.scale);
  EXPECT_EQ(f.covariance, g.covariance);
  ASSERT_EQ(f.terms.size(), g.terms.size());
  for (std::size_t k = 0; k < f.terms.size(); ++k) {
    EXPECT_EQ(f.terms[k].alpha, g.terms[k].alpha);
    EXPECT_EQ(f.terms[k].h, g.terms[k].h);
    EXPECT_EQ(f.terms[k].sigma, g.terms[k].sigma);
    EXPECT_EQ(f.terms[k].valid, g.terms[k].valid);
    EXPECT_EQ(f.terms[k].f_lo, g.terms[k].f_lo);
    EXPECT_EQ(f.terms[k].f_hi, g.terms[k].f_hi);
  }
  ASSERT_EQ(a.allan_terms.size(), b.allan_terms.size());
  for (std::size_t k = 0; k < a.allan_terms.size(); ++k) {
    const auto &x = a.allan_terms[k], &y = b.allan_terms[k];
    EXPECT_EQ(x.term, y.term);
    EXPECT_EQ(x.alpha, y.alpha);
    EXPECT_EQ(x.estimate.valid, y.estimate.valid);
    EXPECT_EQ(x.estimate.value, y.estimate.value);
    EXPECT_EQ(x.estimate.sigma, y.estimate.sigma);
    EXPECT_EQ(x.display.value, y.display.value);
    EXPECT_EQ(x.display.sigma, y.display.sigma);
    EXPECT_EQ(x.display.unit, y.display.unit);
  }
  EXPECT_EQ(a.fit_error, b.fit_error);
  EXPECT_EQ(a.overlap, b.overlap);
  EXPECT_EQ(a.pieces, b.pieces);
  EXPECT_EQ(a.pieces_used, b.pieces_used);
}

// Two deg/s channels at 10 Hz, white noise plus a walk, cut at a gap.
io::Series split_record() {
  const std::size_t n = std::size_t{1} << 17;
  io::Series s =
      series_of({white_plus_walk(n, 0.1, 0.014, 0.0035, 31, 0.2), white_plus_walk(n, 0.1, 0.013, 0.00066, 32, -1.5)},
                {"gx", "gy"}, 10.0);
  s.segments = {{0, 50000}, {50000, n}};
  s.gaps = io::GapPolicy::split;
  return s;
}

pipeline::AnalyzeRequest psd_request() {
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s")};
  req.grid = parse_tau_grid("log:10");
  req.psd = true;
  return req;
}

TEST(SpectralView, IsRunPsdOfTheRecordAtTwentyBandsPerDecadeWithItsGaps) {
  const io::Series s = split_record();
  const auto r = pipeline::run_analyze(s, psd_request());
  pipeline::PsdRequest preq;
  preq.bins_per_decade = 20;
  preq.units = {*parse_unit("deg/s")};
  const pipeline::PsdResult p = pipeline::run_psd(s, preq);
  ASSERT_EQ(r.channels.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c) {
    ASSERT_TRUE(r.channels[c].spectral.has_value());
    const pipeline::SpectralAnalysis& v = *r.channels[c].spectral;
    pipeline::SpectralAnalysis want;
    want.spectrum = p.channels[c].spectrum;
    want.spectrum.bin_covariance.clear();  // not kept
    want.fit = p.channels[c].fit;
    want.allan_terms = p.channels[c].allan_terms;
    want.fit_error = p.channels[c].fit_error;
    want.overlap = p.overlap;
    want.pieces = p.pieces;
    want.pieces_used = p.pieces_used;
    expect_same_spectral(v, want);
    // The pieces at the gap: segments of 8192 samples (the longest piece's
    // 81072 / 8 rounded down to a power of two), none across the gap.
    EXPECT_EQ(v.pieces, 2u);
    EXPECT_EQ(v.pieces_used, 2u);
    EXPECT_EQ(v.spectrum.segment_length, 8192u);
    EXPECT_EQ(v.spectrum.bins_per_decade, 20u);
    EXPECT_TRUE(v.fit_error.empty());
    EXPECT_FALSE(v.allan_terms.empty());
  }
  // Without the request: no spectral view.
  pipeline::AnalyzeRequest plain = psd_request();
  plain.psd = false;
  for (const auto& c : pipeline::run_analyze(s, plain).channels) EXPECT_FALSE(c.spectral.has_value());
}

TEST(SpectralView, ShortRecordKeepsItsSpectrumAndSaysWhyNotFitted) {
  // 300 samples: segments of 32, raw bins from 10 up to Nyquist (bin 16)
  // make fewer log bands than the four coefficients need.
  const io::Series s = series_of({white_plus_walk(300, 0.1, 0.014, 0.0, 33)}, {"gx"}, 10.0);
  const auto r = pipeline::run_analyze(s, psd_request());
  ASSERT_TRUE(r.channels[0].spectral.has_value());
  const auto& v = *r.channels[0].spectral;
  EXPECT_FALSE(v.fit_error.empty());
  EXPECT_TRUE(v.fit.terms.empty());
  EXPECT_TRUE(v.allan_terms.empty());
  EXPECT_GT(v.spectrum.size(), 0u);
  EXPECT_TRUE(pipeline::compare_views(r.channels[0].noise.fit, v).empty());
  // And through analysis.json.
  pipeline::AnalysisDocument d;
  d.result = r;
  const auto back = pipeline::parse_analysis_json(pipeline::to_json(d).dump(1), "analysis.json");
  ASSERT_TRUE(back.result.channels[0].spectral.has_value());
  expect_same_spectral(*back.result.channels[0].spectral, v);
}

TEST(SpectralView, AnalysisJsonRoundTripAndFilesWithoutIt) {
  const io::Series s = split_record();
  const auto r = pipeline::run_analyze(s, psd_request());
  pipeline::AnalysisDocument d;
  d.result = r;
  d.command = "cubecal analyze --psd";
  const nlohmann::json j = pipeline::to_json(d);
  const auto back = pipeline::parse_analysis_json(j.dump(1), "analysis.json");
  ASSERT_EQ(back.result.channels.size(), r.channels.size());
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    ASSERT_TRUE(back.result.channels[c].spectral.has_value());
    expect_same_spectral(*back.result.channels[c].spectral, *r.channels[c].spectral);
  }
  // Written again: the same spectral part. Its derived terms too, but for
  // the Allan fit beside them, which analysis.json keeps in display units
  // (read back divided by the unit's factor: equal to rounding).
  const nlohmann::json again = pipeline::to_json(back);
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    nlohmann::json x = again.at("channels")[c].at("spectral"), y = j.at("channels")[c].at("spectral");
    const nlohmann::json xt = x.at("terms"), yt = y.at("terms");
    x.erase("terms");
    y.erase("terms");
    EXPECT_EQ(x, y) << c;
    ASSERT_EQ(xt.size(), yt.size());
    for (std::size_t k = 0; k < xt.size(); ++k) {
      EXPECT_EQ(xt[k].at("value"), yt[k].at("value"));
      EXPECT_EQ(xt[k].at("sigma"), yt[k].at("sigma"));
      EXPECT_EQ(xt[k].at("term"), yt[k].at("term"));
      EXPECT_EQ(xt[k].at("difference_sigmas").is_null(), yt[k].at("difference_sigmas").is_null());
      if (!yt[k].at("difference_sigmas").is_null()) {
        EXPECT_NEAR(xt[k].at("difference_sigmas").get<double>(), yt[k].at("difference_sigmas").get<double>(), 1e-12);
      }
      if (!yt[k].at("allan_fit").at("value").is_null()) {
        EXPECT_NEAR(xt[k].at("allan_fit").at("value").get<double>() / yt[k].at("allan_fit").at("value").get<double>(),
                    1.0, 1e-14);
      }
    }
  }
  // The terms beside the Allan fit, in display units, as compare_views has them.
  const auto& terms = j.at("channels")[0].at("spectral").at("terms");
  const auto views = pipeline::compare_views(r.channels[0].noise.fit, *r.channels[0].spectral);
  ASSERT_EQ(terms.size(), views.size());
  for (std::size_t k = 0; k < views.size(); ++k) {
    const Quantity q = display(views[k].spectrum, views[k].term, r.channels[0].unit);
    if (views[k].spectrum.valid) {
      EXPECT_EQ(terms[k].at("value").get<double>(), q.value);
    } else {
      EXPECT_TRUE(terms[k].at("value").is_null());
    }
    EXPECT_EQ(terms[k].at("unit"), q.unit);
    if (views[k].difference_sigmas) {
      EXPECT_EQ(terms[k].at("difference_sigmas").get<double>(), *views[k].difference_sigmas);
    } else {
      EXPECT_TRUE(terms[k].at("difference_sigmas").is_null());
    }
  }
  // A file without "spectral" (before analyze --psd, or without it) loads
  // with no spectral view and everything else as before.
  nlohmann::json old = j;
  for (auto& c : old.at("channels")) c.erase("spectral");
  const auto plain = pipeline::parse_analysis_json(old.dump(), "analysis.json");
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    EXPECT_FALSE(plain.result.channels[c].spectral.has_value());
    EXPECT_EQ(plain.result.channels[c].noise.fit.N.value, back.result.channels[c].noise.fit.N.value);
  }
  // A damaged spectral part is one UsageError naming its place.
  nlohmann::json bad = j;
  bad.at("channels")[1].at("spectral").at("spectrum").at("bins").erase(0);
  try {
    (void)pipeline::parse_analysis_json(bad.dump(), "analysis.json");
    ADD_FAILURE() << "no error";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("channels[1].spectral.spectrum"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cubecal
