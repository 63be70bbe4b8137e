// The temperature coefficients estimated jointly with a random-walk bias
// (noise/temperature_random_walk.hpp; docs/formulas/drift-covariance-temperature.md §4):
// the Kalman-filter GLS against a dense GLS with the n x n covariance, its
// reductions (no walk: least squares), its errors, the iteration, and the
// Monte Carlo of docs/validation.md over 50 seeds of 72 h records like the
// demo's.
#include <gtest/gtest.h>
#include <malloc.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <thread>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/noise/temperature_random_walk.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/sim/simulator.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "reason_of.hpp"

namespace cubecal {
namespace {

struct Record {
  std::vector<double> y, temp;
};

// n samples of c0 + c1 d + c2 d^2 + random walk (step sqrt(q), from 0) +
// white (sqrt(r)), d = T - 25, T a slow swing with a little noise.
Record small_record(std::size_t n, double r, double q, std::uint64_t seed, std::size_t gap_at = 0,
                    double gap_steps = 0.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Record rec;
  double s = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (gap_at != 0 && k == gap_at) s += std::sqrt(q * gap_steps) * g(rng);
    const double t = 25.0 + 5.0 * std::sin(2.0 * M_PI * static_cast<double>(k) / static_cast<double>(n)) + 0.1 * g(rng);
    const double d = t - 25.0;
    rec.temp.push_back(t);
    rec.y.push_back(3.0 + 0.7 * d - 0.02 * d * d + s + std::sqrt(r) * g(rng));
    s += std::sqrt(q) * g(rng);
  }
  return rec;
}

// Dense GLS: Sigma_ij = r delta_ij + q steps(min(i, j)), steps(k) the walk's
// steps before sample k (k, plus the gap's for k >= gap_at).
struct DenseGls {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov;
};
DenseGls dense_gls(const Record& rec, std::size_t order, double r, double q, std::size_t gap_at, double gap_steps) {
  const auto n = static_cast<Eigen::Index>(rec.y.size());
  const auto p = static_cast<Eigen::Index>(order + 1);
  double tref = 0.0;
  for (double t : rec.temp) tref += t;
  tref /= static_cast<double>(n);
  Eigen::MatrixXd sigma(n, n), x(n, p);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    y(i) = rec.y[static_cast<std::size_t>(i)];
    double pw = 1.0;
    for (Eigen::Index j = 0; j < p; ++j, pw *= rec.temp[static_cast<std::size_t>(i)] - tref) x(i, j) = pw;
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto m = static_cast<std::size_t>(std::min(i, j));
      const double steps = static_cast<double>(m) + (gap_at != 0 && m >= gap_at ? gap_steps : 0.0);
      sigma(i, j) = q * steps + (i == j ? r : 0.0);
    }
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(sigma);
  const Eigen::MatrixXd sx = llt.solve(x);
  const Eigen::MatrixXd info = x.transpose() * sx;
  DenseGls d;
  d.cov = info.inverse();
  d.beta = d.cov * (sx.transpose() * y);
  return d;
}

TEST(TemperatureRandomWalk, KalmanGlsEqualsDenseGls) {
  const double r = 0.25, q = 4e-4;
  for (const std::size_t gap : {std::size_t{0}, std::size_t{170}}) {
    const Record rec = small_record(400, r, q, 11 + gap, gap, 250.0);
    const RandomWalkModel noise{std::sqrt(r), std::sqrt(q) / 0.5, 0.5, 0.0};  // sigma_mu dt = sqrt(q)
    std::vector<BiasGap> gaps;
    if (gap != 0) gaps.push_back({gap, 250.0});
    const TemperatureFit f = fit_temperature_gls(rec.y, rec.temp, 2, noise, gaps);
    const DenseGls d = dense_gls(rec, 2, r, q, gap, 250.0);
    const std::string w = gap != 0 ? "with a gap" : "no gap";
    ASSERT_EQ(f.coeff.size(), 3u);
    for (std::size_t j = 1; j < 3; ++j) {
      const auto J = static_cast<Eigen::Index>(j);
      EXPECT_NEAR(f.coeff[j], d.beta(J), 1e-9 * std::sqrt(d.cov(J, J)) + 1e-12) << w << " c" << j;
      for (std::size_t k = 1; k < 3; ++k)
        EXPECT_NEAR(f.cov(j, k), d.cov(J, static_cast<Eigen::Index>(k)), 1e-9 * d.cov(J, J)) << w << " cov" << j << k;
      EXPECT_NEAR(f.coeff_sigma[j], std::sqrt(d.cov(J, J)), 1e-9 * std::sqrt(d.cov(J, J))) << w;
    }
    // c_0: the record's mean of y less the fitted temperature part.
    double c0 = 0.0;
    for (std::size_t k = 0; k < rec.y.size(); ++k) {
      const double dd = rec.temp[k] - f.t_ref;
      c0 += rec.y[k] - f.coeff[1] * dd - f.coeff[2] * dd * dd;
    }
    EXPECT_NEAR(f.coeff[0], c0 / static_cast<double>(rec.y.size()), 1e-9) << w;
  }
}

TEST(TemperatureRandomWalk, WithoutTheWalkItIsLeastSquares) {
  const Record rec = small_record(2000, 0.25, 0.0, 5);
  const TemperatureFit ols = fit_temperature(rec.y, rec.temp, 2);
  const TemperatureFit gls = fit_temperature_gls(rec.y, rec.temp, 2, RandomWalkModel{0.5, 0.0, 0.1, 0.0});
  ASSERT_EQ(gls.coeff.size(), ols.coeff.size());
  for (std::size_t j = 0; j < ols.coeff.size(); ++j) EXPECT_NEAR(gls.coeff[j], ols.coeff[j], 1e-9) << j;
  EXPECT_NEAR(gls.residual_rms, ols.residual_rms, 1e-12);
  EXPECT_NEAR(gls.r2, ols.r2, 1e-12);
  EXPECT_EQ(gls.t_ref, ols.t_ref);
}

TEST(TemperatureRandomWalk, ExactPolynomialFromNoiseFreeData) {
  // docs/formulas/drift-covariance-temperature.md §3.5, with a noise model.
  std::vector<double> t, y;
  for (int i = 0; i <= 800; ++i) {
    const double T = -20.0 + 0.1 * i;
    t.push_back(T);
    y.push_back(0.01 + 2e-4 * (T - 25.0) - 3e-6 * (T - 25.0) * (T - 25.0));
  }
  const TemperatureFit f = fit_temperature_gls(y, t, 2, RandomWalkModel{1e-3, 1e-4, 1.0, 0.0});
  const double d = f.t_ref - 25.0;  // the same polynomial about t_ref
  EXPECT_NEAR(f.coeff[1], 2e-4 - 6e-6 * d, 1e-12);
  EXPECT_NEAR(f.coeff[2], -3e-6, 1e-13);
  EXPECT_NEAR(f.coeff[0], 0.01 + 2e-4 * d - 3e-6 * d * d, 1e-12);
}

TEST(TemperatureRandomWalk, BadInputIsACalibrationError) {
  const Record rec = small_record(100, 0.25, 1e-4, 3);
  EXPECT_EQ(test::reason_of([&] {
              fit_temperature_gls(rec.y, rec.temp, 1, RandomWalkModel{0.0, 0.01, 0.1, 0.0});
            }),
            "bad_option")
      << "no white noise";
  EXPECT_EQ(test::reason_of([&] {
              fit_temperature_gls(rec.y, rec.temp, 1, RandomWalkModel{1.0, NAN, 0.1, 0.0});
            }),
            "bad_option");
  EXPECT_EQ(test::reason_of([&] {
              fit_temperature_gls(rec.y, rec.temp, 1, RandomWalkModel{1.0, 0.01, 0.0, 0.0});
            }),
            "bad_option")
      << "no sample period";
  const std::vector<double> flat(rec.y.size(), 20.0);
  EXPECT_EQ(test::reason_of([&] {
              fit_temperature_gls(rec.y, flat, 1, RandomWalkModel{1.0, 0.01, 0.1, 0.0});
            }),
            "degenerate");
  EXPECT_EQ(test::reason_of([&] {
              fit_temperature_gls(rec.y, rec.temp, 6, RandomWalkModel{1.0, 0.01, 0.1, 0.0});
            }),
            "bad_option");
}

TEST(TemperatureRandomWalk, IterationStopsWhenTheCoefficientsStandStill) {
  const Record rec = small_record(3000, 0.25, 1e-4, 9);
  std::size_t calls = 0;
  const auto model = [&](std::span<const double> comp) {
    ++calls;
    EXPECT_EQ(comp.size(), rec.y.size());
    return RandomWalkModel{0.5, 0.1, 0.1, 0.0};  // sigma_mu dt = 0.01 = sqrt(q)
  };
  const TemperatureRandomWalkFit f = fit_temperature_random_walk(rec.y, rec.temp, 1, model);
  // The model does not change: the second GLS repeats the first.
  EXPECT_TRUE(f.converged);
  EXPECT_EQ(f.iterations, 2u);
  EXPECT_EQ(calls, 2u);
  const TemperatureFit direct = fit_temperature_gls(rec.y, rec.temp, 1, RandomWalkModel{0.5, 0.1, 0.1, 0.0});
  EXPECT_EQ(f.fit.coeff, direct.coeff);
  EXPECT_EQ(f.ols.coeff, fit_temperature(rec.y, rec.temp, 1).coeff);
  EXPECT_EQ(f.noise.sigma_mu, 0.1);
  // A model that cannot be fitted stops it with its error.
  const auto none = [](std::span<const double>) -> RandomWalkModel {
    throw CalibrationError(CalibrationReason::degenerate, "no minimum");
  };
  EXPECT_EQ(test::reason_of([&] { fit_temperature_random_walk(rec.y, rec.temp, 1, none); }), "degenerate");
  // Started from the caller's OLS fit: the same iteration, bit for bit; an
  // OLS fit of another order is refused.
  const TemperatureFit ols = fit_temperature(rec.y, rec.temp, 1);
  const TemperatureRandomWalkFit g = fit_temperature_random_walk(rec.y, rec.temp, 1, ols, model);
  EXPECT_EQ(g.fit.coeff, f.fit.coeff);
  EXPECT_EQ(g.fit.cov, f.fit.cov);
  EXPECT_EQ(g.ols.coeff, f.ols.coeff);
  EXPECT_EQ(g.iterations, f.iterations);
  EXPECT_THROW(fit_temperature_random_walk(rec.y, rec.temp, 2, ols, model), std::invalid_argument);
}

// The Monte Carlo of docs/validation.md ("Temperature coefficient with the
// random-walk bias"): 50 seeds of the demo's magnetometer (the sport-mag
// preset: sigma_n 3.0/4.9/2.96 mGauss, sigma_mu 0.0034/0.0042/0.0036
// mGauss/s, 0.7 mGauss/degC, 1.30 LSB/mGauss truncation) for 72 h at 10 Hz
// under the demo's 25 +- 5 degC daily swing: 150 axis records of 2.592 M
// samples. The noise model of each iteration is the paper's random-walk
// model fitted to the OADEV (octave grid, intervals as analyze) of the
// compensated record. Asserted: the coefficient's RMS error within 1.2x of
// the GLS sigma with the true noise model, the stated sigma covering the
// truth in 60-76 % of the records, the fitted sigma_mu within 10 % of the
// truth on average; and the joint estimate beating least squares.
TEST(TemperatureRandomWalk, MonteCarloOfTheDemoRecord) {
  const auto start = std::chrono::steady_clock::now();
  // Each record allocates a few buffers of its length (20 MB); glibc would
  // map and unmap them, and faulting the pages in again costs more than the
  // estimator. Keeping freed memory in the heap leaves only the arithmetic.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
  constexpr int kSeeds = 50;
  constexpr double kRate = 10.0, kDt = 1.0 / kRate, kLsb = 1.30, kCoeff = 0.7;
  const std::size_t n = static_cast<std::size_t>(72.0 * 3600.0 * kRate);
  const TriadModel mag = preset("sport-mag");
  TemperatureProfile profile;
  profile.kind = TemperatureProfile::Kind::sinusoid;
  profile.mean = 25.0;
  profile.amplitude = 5.0;
  std::vector<double> temp(n);
  for (std::size_t k = 0; k < n; ++k) temp[k] = profile.at(k, kDt);

  // Octave taus keep the test within ~30 s; CUBECAL_MC_TAUS=log:10 runs it on
  // analyze's default grid (docs/validation.md gives both).
  const char* taus = std::getenv("CUBECAL_MC_TAUS");
  const TauGrid grid = parse_tau_grid(taus != nullptr && *taus != '\0' ? taus : "octave");
  const auto noise_model = [&](std::span<const double> comp) {
    const StabilityRecord rec(comp, DataType::freq, kDt, Stat::oadev);
    const std::vector<std::size_t> ms = averaging_factors(grid, rec.max_m(), kDt);
    return fit_random_walk_model(to_allan_curve(rec.evaluate(ms, StabilityOptions{})), kDt, kLsb);
  };

  struct Outcome {
    double err = 0.0, sigma = 0.0, ols_err = 0.0, ols_sigma = 0.0, sigma_mu = 0.0;
    bool converged = false;
  };
  std::vector<Outcome> out(3 * kSeeds);
  std::vector<double> theory(3);  // GLS sigma of c1 with the true noise model (data-independent)
  std::atomic<int> next{1};
  const auto worker = [&] {
    std::vector<double> xyz(3 * n), y(n);
    for (int seed = next++; seed <= kSeeds; seed = next++) {
      TriadSimulator sim(mag, kDt, static_cast<std::uint64_t>(seed));
      sim.run(n, {}, temp, xyz);
      for (std::size_t a = 0; a < 3; ++a) {
        for (std::size_t k = 0; k < n; ++k) y[k] = xyz[3 * k + a];
        const TemperatureRandomWalkFit f = fit_temperature_random_walk(y, temp, 1, noise_model);
        Outcome& o = out[3 * static_cast<std::size_t>(seed - 1) + a];
        o.err = f.fit.coeff[1] - kCoeff;
        o.sigma = f.fit.coeff_sigma[1];
        o.ols_err = f.ols.coeff[1] - kCoeff;
        o.ols_sigma = f.ols.coeff_sigma[1];
        o.sigma_mu = f.noise.sigma_mu / mag.axes[a].bias_sigma;
        o.converged = f.converged;
        if (seed == 1) {
          const RandomWalkModel truth{mag.axes[a].white_sigma, mag.axes[a].bias_sigma, kDt, kLsb};
          theory[a] = fit_temperature_gls(y, temp, 1, truth).coeff_sigma[1];
        }
      }
    }
  };
  std::vector<std::thread> pool;
  const unsigned threads = std::max(2u, std::min(4u, std::thread::hardware_concurrency()));
  for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();

  double z2 = 0.0, ols_z2 = 0.0, mu_sum = 0.0, mu_sq = 0.0, mu_min = 1e9, mu_max = 0.0;
  int covered = 0, ols_covered = 0, converged = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Outcome& o = out[i];
    const double th = theory[i % 3];
    z2 += (o.err / th) * (o.err / th);
    ols_z2 += (o.ols_err / th) * (o.ols_err / th);
    covered += std::abs(o.err) <= o.sigma;
    ols_covered += std::abs(o.ols_err) <= o.ols_sigma;
    converged += o.converged;
    mu_sum += o.sigma_mu;
    mu_sq += o.sigma_mu * o.sigma_mu;
    mu_min = std::min(mu_min, o.sigma_mu);
    mu_max = std::max(mu_max, o.sigma_mu);
  }
  const auto m = static_cast<double>(out.size());
  const double rms_ratio = std::sqrt(z2 / m), ols_ratio = std::sqrt(ols_z2 / m);
  const double coverage = covered / m, ols_coverage = ols_covered / m;
  const double mu_mean = mu_sum / m, mu_sd = std::sqrt(std::max(0.0, mu_sq / m - mu_mean * mu_mean));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("  %d seeds x 3 axes = %zu records of 72 h at 10 Hz, noise model on %s taus (%.1f s, %u threads)\n",
              kSeeds, out.size(), taus != nullptr && *taus != '\0' ? taus : "octave", secs, threads);
  std::printf("  GLS sigma of c1 with the true noise model: %.4f %.4f %.4f mGauss/degC (x, y, z)\n", theory[0],
              theory[1], theory[2]);
  std::printf(
      "  joint:  RMS error / theoretical sigma %.3f; stated sigma covers the truth in %.1f %%; converged %d/%zu\n",
      rms_ratio, 100.0 * coverage, converged, out.size());
  std::printf("  OLS:    RMS error / theoretical sigma %.3f; sandwich sigma covers the truth in %.1f %%\n", ols_ratio,
              100.0 * ols_coverage);
  std::printf("  sigma_mu (compensated) / truth: mean %.3f, sd %.3f, range %.3f-%.3f\n", mu_mean, mu_sd, mu_min,
              mu_max);
  EXPECT_LE(rms_ratio, 1.2);
  EXPECT_GE(rms_ratio, 1.0 / 1.2);
  EXPECT_GE(coverage, 0.60);
  EXPECT_LE(coverage, 0.76);
  EXPECT_NEAR(mu_mean, 1.0, 0.10);
  EXPECT_EQ(converged, static_cast<int>(out.size()));
  EXPECT_GT(ols_ratio, 1.3 * rms_ratio) << "the joint estimate scatters less than least squares";
}

}  // namespace
}  // namespace cubecal
