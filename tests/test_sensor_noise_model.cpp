// The paper's sensor noise model (random-walk bias) and the Gauss-Markov
// alternative: exact discrete Allan variances against published values and
// closed forms, the paper's adjustment (fit), and a seeded Monte Carlo of the
// paper's own model row (docs/paper.md §3).
#include "cubecal/noise/sensor_noise_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/error.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "reason_of.hpp"

namespace {

using cubecal::AllanCurve;
using cubecal::GaussMarkovModel;
using cubecal::RandomWalkModel;

constexpr std::size_t kPaperSamples = 42000;  // section 2: "reduced to 42000"
constexpr double kPaperDt = 0.1;              // 10 Hz
constexpr double kGyroLsb = 145.6;            // LSB/(deg/s), eq. 3

// The paper's adjusted gyro model (docs/paper.md §3.1; sigma_mu y = 0.87e-3).
constexpr std::array<double, 3> kSigmaN{13.9e-3, 14.5e-3, 13.0e-3};
constexpr std::array<double, 3> kSigmaMu{3.50e-3, 0.87e-3, 0.66e-3};
constexpr std::array<double, 3> kFixedBias{182.3e-3, 1509.3e-3, -1501.5e-3};
// The paper's model row: N deg/sqrt(h), B deg/h, T s.
constexpr std::array<double, 3> kPaperN{0.2683, 0.2723, 0.2469};
constexpr std::array<double, 3> kPaperB{12.649, 6.853, 5.3007};
constexpr std::array<double, 3> kPaperT{7.4, 34.9, 39.2};

// NIST SP 1065 overlapping-AVAR EDF for white FM, N phase points.
double edf_white_fm(double m, double n_phase) {
  const double n = n_phase;
  return (3.0 * (n - 1.0) / (2.0 * m) - 2.0 * (n - 2.0) / n) * 4.0 * m * m / (4.0 * m * m + 5.0);
}

std::vector<std::size_t> log_grid(std::size_t max_m, unsigned per_decade = 20) {
  auto g = cubecal::parse_tau_grid("log:" + std::to_string(per_decade));
  return cubecal::averaging_factors(g, max_m, kPaperDt);
}

// An Allan curve that is the model's exact AVAR on the factors ms.
template <class Model>
AllanCurve exact_curve(const Model& model, const std::vector<std::size_t>& ms, double n_samples) {
  AllanCurve c;
  for (std::size_t m : ms) {
    const double dev = std::sqrt(cubecal::avar(model, m));
    const double edf = edf_white_fm(static_cast<double>(m), n_samples + 1.0);
    c.tau.push_back(static_cast<double>(m) * model.dt);
    c.dev.push_back(dev);
    c.interval.push_back({dev * (1.0 - 1.0 / std::sqrt(2.0 * edf)), dev * (1.0 + 1.0 / std::sqrt(2.0 * edf))});
    c.edf.push_back(edf);
  }
  return c;
}

// Continuous Gauss-Markov AVAR over sigma^2 (IEEE 952 Annex C), x = tau/T.
double gm_continuous(double x) { return 2.0 / x * (1.0 - (3.0 - 4.0 * std::exp(-x) + std::exp(-2.0 * x)) / (2.0 * x)); }

// Quantile with linear interpolation between order statistics (numpy default).
double quantile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(pos));
  if (i + 1 >= v.size()) return v.back();
  const double f = pos - static_cast<double>(i);
  return v[i] + f * (v[i + 1] - v[i]);
}

// The paper's gyro model, eq. 1-3: w_k = beta + b_k + sigma_n n_k,
// b_{k+1} = b_k + sigma_mu dt n'_k, then int(w * lsb) / lsb (truncation toward
// zero) when lsb > 0.
std::vector<double> simulate_paper_gyro(std::size_t n, double sigma_n, double sigma_mu, double dt, double beta,
                                        double lsb, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> y(n);
  double b = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double w = beta + b + sigma_n * gauss(rng);
    y[k] = lsb > 0.0 ? std::trunc(w * lsb) / lsb : w;
    b += sigma_mu * dt * gauss(rng);
  }
  return y;
}

AllanCurve oadev_curve(const std::vector<double>& y, double dt, unsigned per_decade = 20) {
  const std::size_t max_m = cubecal::max_averaging_factor(cubecal::Stat::oadev, y.size() + 1);
  const auto ms = cubecal::averaging_factors(cubecal::parse_tau_grid("log:" + std::to_string(per_decade)), max_m, dt);
  const auto pts = cubecal::stability(y, cubecal::DataType::freq, dt, cubecal::Stat::oadev, ms);
  return cubecal::to_allan_curve(pts);
}

std::size_t index_of_tau(const AllanCurve& c, double tau) {
  for (std::size_t i = 0; i < c.size(); ++i)
    if (std::abs(c.tau[i] - tau) < 1e-9 * tau) return i;
  ADD_FAILURE() << "tau " << tau << " not on the curve";
  return 0;
}

// ---------------------------------------------------------------------------
// Exact discrete AVARs

TEST(RandomWalkAvar, DiscreteRandomWalkAgainstClosedForms) {
  const double dt = 0.1;
  const double sigma_mu = 3.5e-3;
  const RandomWalkModel rw{0.0, sigma_mu, dt, 0.0};
  const double k2 = sigma_mu * sigma_mu * dt;  // K^2 with K^2 dt = (sigma_mu dt)^2
  // docs/formulas/noise-terms.md §6.2: K^2 tau / 3 + K^2 dt^2 / (6 tau).
  for (std::size_t m : {1u, 2u, 3u, 10u, 1000u, 100000u}) {
    const double tau = static_cast<double>(m) * dt;
    EXPECT_NEAR(cubecal::avar(rw, m) / (k2 * tau / 3.0 + k2 * dt * dt / (6.0 * tau)), 1.0, 1e-12) << "m=" << m;
  }
  // m = 1: 1.5 times the continuous sigma_mu^2 dt tau / 3; large m: the continuous value.
  EXPECT_NEAR(cubecal::avar(rw, 1) / (sigma_mu * sigma_mu * dt * dt / 3.0), 1.5, 1e-12);
  EXPECT_NEAR(cubecal::avar(rw, 100000) / (sigma_mu * sigma_mu * dt * 10000.0 / 3.0), 1.0, 1e-9);
}

TEST(RandomWalkAvar, WhiteAndQuantizationShare) {
  const RandomWalkModel white{13.9e-3, 0.0, 0.1, 0.0};
  const RandomWalkModel quant{13.9e-3, 0.0, 0.1, kGyroLsb};
  for (std::size_t m : {1u, 7u, 420u}) {
    const double md = static_cast<double>(m);
    EXPECT_NEAR(cubecal::avar(white, m), 13.9e-3 * 13.9e-3 / md, 1e-18);
    EXPECT_NEAR(cubecal::avar(quant, m) - cubecal::avar(white, m), 1.0 / (12.0 * kGyroLsb * kGyroLsb) / md, 1e-18);
  }
  EXPECT_TRUE(std::isnan(cubecal::avar(white, 0)));
}

// The generator of the paper's model (with int() truncation) against the
// model's AVAR: the white + quantization + random-walk sum and the discrete
// (2m^2+1)/(6m) factor are what a sampled record shows.
TEST(RandomWalkAvar, MatchesSimulatedRecord) {
  const std::size_t n = 400000;
  const RandomWalkModel model{13.9e-3, 0.05, 0.1, kGyroLsb};  // strong walk: visible at m = 1
  const auto y = simulate_paper_gyro(n, model.sigma_n, model.sigma_mu, model.dt, 0.1823, kGyroLsb, 7);
  const std::vector<std::size_t> ms{1, 3, 30};
  const auto pts = cubecal::stability(y, cubecal::DataType::freq, model.dt, cubecal::Stat::oadev, ms);
  for (const auto& p : pts) {
    const double want = cubecal::avar(model, p.m);
    const double sd = want * std::sqrt(2.0 / p.edf);  // of the AVAR estimate
    EXPECT_NEAR(p.dev * p.dev, want, 4.0 * sd) << "m=" << p.m;
  }
  // Without the quantization share the m = 1 value would be 2 % low: many sigmas here.
  const RandomWalkModel no_q{model.sigma_n, model.sigma_mu, model.dt, 0.0};
  const double sd1 = cubecal::avar(model, 1) * std::sqrt(2.0 / pts[0].edf);
  EXPECT_GT(pts[0].dev * pts[0].dev - cubecal::avar(no_q, 1), 3.0 * sd1);
}

TEST(GaussMarkovAvar, ZhangAr1TestValues) {
  // av_ar1(n, phi, sigma_w^2) of R avar: innovation variance sigma_w^2, so the
  // stationary variance is sigma_w^2 / (1 - phi^2).
  struct Case {
    std::size_t n;
    double phi, sw2, want;
  };
  for (const Case c : {Case{5, 0.9, 1.0, 1.304282188}, Case{8, 0.5, 2.0, 0.751300812}}) {
    const double dt = 1.0;
    const GaussMarkovModel gm{0.0, std::sqrt(c.sw2 / (1.0 - c.phi * c.phi)), -dt / std::log(c.phi), dt, 0.0};
    EXPECT_NEAR(cubecal::avar(gm, c.n), c.want, 2e-9) << "n=" << c.n;
  }
}

TEST(GaussMarkovAvar, ContinuousValuesAndPeak) {
  const double t = 1.0;
  const double dt = 1e-6;  // continuous limit: discrete corrections ~ (dt/tau)^2
  const GaussMarkovModel gm{0.0, 1.0, t, dt, 0.0};
  struct Case {
    double x, want, tol;
  };
  for (const Case c : {Case{0.01, 0.0066169, 1e-4}, Case{0.1, 0.0618919, 1e-5}, Case{1.0, 0.3361825, 1e-6},
                       Case{10.0, 0.1700018, 1e-6}, Case{100.0, 0.0197, 1e-3}}) {
    const auto m = static_cast<std::size_t>(std::llround(c.x * t / dt));
    EXPECT_NEAR(cubecal::avar(gm, m) / c.want, 1.0, c.tol) << "tau/T=" << c.x;
  }
  // ADEV peak 0.617364 sigma at tau = 1.892618 T.
  const GaussMarkovModel coarse{0.0, 1.0, 1.0, 1e-4, 0.0};
  double best = 0.0;
  std::size_t best_m = 0;
  for (std::size_t m = 17000; m <= 21000; ++m) {
    const double v = cubecal::avar(coarse, m);
    if (v > best) {
      best = v;
      best_m = m;
    }
  }
  EXPECT_NEAR(std::sqrt(best), 0.617364, 1e-6);
  EXPECT_NEAR(static_cast<double>(best_m) * 1e-4, 1.892618, 2e-4);
}

TEST(GaussMarkovAvar, DiscreteAtSmallAndLongCorrelation) {
  // docs/formulas/noise-terms.md §5.4: dt = 0.01, T = 100, sigma = 1, m = 1 (continuous 6.670e-5).
  // At m = 1 the AVAR is E[(y1 - y0)^2] / 2 = sigma^2 (1 - phi) = 9.99950e-5
  // (av_ar1 at n = 1 also gives (1 - phi) sigma_w^2 / (1 - phi^2)); a naive
  // double-precision evaluation of the closed form gives 9.99936e-5, 1.4e-5
  // off. Discrete and continuous agree to 1e-6 for m >= 1000.
  const GaussMarkovModel gm{0.0, 1.0, 100.0, 0.01, 0.0};
  EXPECT_NEAR(cubecal::avar(gm, 1) / 9.99950e-5, 1.0, 1e-6);
  EXPECT_NEAR(gm_continuous(0.01 / 100.0) / 6.670e-5, 1.0, 1e-3);
  for (std::size_t m : {1000u, 5000u, 20000u, 100000u}) {
    const double x = static_cast<double>(m) * 0.01 / 100.0;
    EXPECT_NEAR(cubecal::avar(gm, m) / gm_continuous(x), 1.0, 1e-6) << "m=" << m;
  }
  // T_c = 1e8 samples: the naive closed form has no correct digit left; the
  // value must be the random walk with step variance sigma^2 (1 - phi^2).
  const double dt = 1.0, tc = 1e8;
  const GaussMarkovModel slow{0.0, 1.0, tc, dt, 0.0};
  const double step2 = -std::expm1(-2.0 * dt / tc);
  for (std::size_t m : {1u, 2u, 10u, 1000u}) {
    const double md = static_cast<double>(m);
    EXPECT_NEAR(cubecal::avar(slow, m) / (step2 * (2.0 * md * md + 1.0) / (6.0 * md)), 1.0, 1e-5) << "m=" << m;
  }
  // Both branches of the evaluation meet: no jump across m * dt / T = 0.25.
  const GaussMarkovModel g2{0.0, 1.0, 400.0, 1.0, 0.0};
  const double v99 = cubecal::avar(g2, 99), v100 = cubecal::avar(g2, 100), v101 = cubecal::avar(g2, 101);
  EXPECT_NEAR((v99 + v101) / 2.0 / v100, 1.0, 1e-4);
  // White part adds as for the random-walk model; T_c = 0 is white with sigma_b.
  const GaussMarkovModel white{0.01, 0.002, 0.0, 0.1, kGyroLsb};
  EXPECT_NEAR(cubecal::avar(white, 4), (0.01 * 0.01 + 0.002 * 0.002 + 1.0 / (12.0 * kGyroLsb * kGyroLsb)) / 4.0, 1e-18);
}

// ---------------------------------------------------------------------------
// The paper's closed form and the adjustment

TEST(RandomWalkModelFit, PaperClosedFormMinimum) {
  const RandomWalkModel x{13.9e-3, 3.5e-3, kPaperDt, 0.0};
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_m = 0;
  for (std::size_t m = 1; m < 10000; ++m) {
    const double v = cubecal::avar(x, m);
    if (v < best) {
      best = v;
      best_m = m;
    }
  }
  const double tau_star = std::sqrt(3.0) * x.sigma_n / x.sigma_mu;
  EXPECT_NEAR(tau_star, 6.879, 5e-4);
  EXPECT_NEAR(static_cast<double>(best_m) * kPaperDt, tau_star, 0.5 * kPaperDt + 1e-9);
  EXPECT_NEAR(best / (2.0 * x.sigma_n * x.sigma_mu * kPaperDt / std::sqrt(3.0)), 1.0, 1e-3);
}

TEST(RandomWalkModelFit, RoundTripOnExactCurves) {
  const auto ms = log_grid(kPaperSamples / 4);
  for (int axis = 0; axis < 3; ++axis) {
    for (double lsb : {0.0, kGyroLsb}) {
      const RandomWalkModel truth{kSigmaN[axis], kSigmaMu[axis], kPaperDt, lsb};
      const auto curve = exact_curve(truth, ms, kPaperSamples);
      const auto fit = cubecal::fit_random_walk_model(curve, kPaperDt, lsb);
      // Only error left: the random-walk share at the tangent point (m = 1),
      // < 4e-4 of the white variance for these axes.
      EXPECT_NEAR(fit.sigma_n / truth.sigma_n, 1.0, 2e-4) << "axis " << axis << " lsb " << lsb;
      EXPECT_NEAR(fit.sigma_mu / truth.sigma_mu, 1.0, 1e-3) << "axis " << axis << " lsb " << lsb;
      EXPECT_EQ(fit.dt, kPaperDt);
      EXPECT_EQ(fit.lsb, lsb);
      // The paper's two conditions hold on the curve: same lowest point, white line.
      const double model_min = [&] {
        double v = std::numeric_limits<double>::infinity();
        for (std::size_t m : ms) v = std::min(v, cubecal::avar(fit, m));
        return v;
      }();
      const double meas_min = *std::min_element(curve.dev.begin(), curve.dev.end());
      EXPECT_NEAR(model_min / (meas_min * meas_min), 1.0, 1e-12);
    }
  }
}

TEST(RandomWalkModelFit, CoarseGridStillExact) {
  // On an octave grid the lowest point is far from the true minimum (up to
  // 6 % in variance); both curves are read on the same grid, so no bias.
  const RandomWalkModel truth{kSigmaN[1], kSigmaMu[1], kPaperDt, 0.0};
  const auto ms = cubecal::averaging_factors(cubecal::parse_tau_grid("octave"), 10500, kPaperDt);
  const auto fit = cubecal::fit_random_walk_model(exact_curve(truth, ms, kPaperSamples), kPaperDt);
  EXPECT_NEAR(fit.sigma_n / truth.sigma_n, 1.0, 1e-4);
  EXPECT_NEAR(fit.sigma_mu / truth.sigma_mu, 1.0, 1e-3);
}

TEST(RandomWalkModelFit, RejectsCurvesWithoutAV) {
  const auto ms = log_grid(10500);
  // White only: falls to the last tau.
  const auto falling = exact_curve(RandomWalkModel{0.01, 0.0, kPaperDt, 0.0}, ms, kPaperSamples);
  EXPECT_THROW(cubecal::fit_random_walk_model(falling, kPaperDt), cubecal::CalibrationError);
  try {
    cubecal::fit_random_walk_model(falling, kPaperDt);
  } catch (const cubecal::CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("no minimum"), std::string::npos) << e.what();
  }
  // Random walk only: rises from the first tau.
  const auto rising = exact_curve(RandomWalkModel{0.0, 1e-3, kPaperDt, 0.0}, ms, kPaperSamples);
  EXPECT_THROW(cubecal::fit_random_walk_model(rising, kPaperDt), cubecal::CalibrationError);
  try {
    cubecal::fit_random_walk_model(rising, kPaperDt);
  } catch (const cubecal::CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("no white-noise arm"), std::string::npos) << e.what();
  }
  // White noise below what the quantization alone gives.
  const auto fine = exact_curve(RandomWalkModel{1e-4, 1e-5, kPaperDt, 0.0}, ms, kPaperSamples);
  EXPECT_NO_THROW(cubecal::fit_random_walk_model(fine, kPaperDt));
  EXPECT_THROW(cubecal::fit_random_walk_model(fine, kPaperDt, kGyroLsb), cubecal::CalibrationError);
  // Malformed input.
  AllanCurve two = fine;
  two.tau.resize(2);
  two.dev.resize(2);
  two.edf.resize(2);
  EXPECT_THROW(cubecal::fit_random_walk_model(two, kPaperDt), cubecal::CalibrationError);
  EXPECT_THROW(cubecal::fit_random_walk_model(fine, 0.0), cubecal::CalibrationError);
}

using cubecal::test::reason_of;

TEST(RandomWalkModelFit, ErrorsCarryTheirReason) {
  const auto ms = log_grid(10500);
  const auto fine = exact_curve(RandomWalkModel{1e-4, 1e-5, kPaperDt, 0.0}, ms, kPaperSamples);
  auto rw = [](const AllanCurve& c, double dt, double lsb = 0.0) {
    return reason_of([&] { (void)cubecal::fit_random_walk_model(c, dt, lsb); });
  };
  auto gm = [](const AllanCurve& c, double dt) {
    return reason_of([&] { (void)cubecal::fit_gauss_markov_model(c, dt); });
  };
  EXPECT_EQ(rw(fine, kPaperDt), "(none)");
  // degenerate: no minimum (white only), no white-noise arm (random walk
  // only).
  EXPECT_EQ(rw(exact_curve(RandomWalkModel{0.01, 0.0, kPaperDt, 0.0}, ms, kPaperSamples), kPaperDt), "degenerate");
  EXPECT_EQ(rw(exact_curve(RandomWalkModel{0.0, 1e-3, kPaperDt, 0.0}, ms, kPaperSamples), kPaperDt), "degenerate");
  // bad_option: white noise below the LSB's quantization noise; dt 0; a
  // negative LSB.
  EXPECT_EQ(rw(fine, kPaperDt, kGyroLsb), "bad_option");
  EXPECT_EQ(rw(fine, 0.0), "bad_option");
  EXPECT_EQ(rw(fine, kPaperDt, -1.0), "bad_option");
  EXPECT_EQ(gm(fine, 0.0), "bad_option");
  // too_few_points: two points.
  AllanCurve two = fine;
  two.tau.resize(2);
  two.dev.resize(2);
  two.edf.resize(2);
  EXPECT_EQ(rw(two, kPaperDt), "too_few_points");
  EXPECT_EQ(gm(two, kPaperDt), "too_few_points");
  // bad_data: arrays of different lengths, a non-finite deviation, taus not
  // ascending.
  AllanCurve uneven = fine;
  uneven.dev.pop_back();
  EXPECT_EQ(rw(uneven, kPaperDt), "bad_data");
  AllanCurve nan_dev = fine;
  nan_dev.dev[4] = std::nan("");
  EXPECT_EQ(rw(nan_dev, kPaperDt), "bad_data");
  EXPECT_EQ(gm(nan_dev, kPaperDt), "bad_data");
  AllanCurve swapped = fine;
  std::swap(swapped.tau[3], swapped.tau[4]);
  EXPECT_EQ(rw(swapped, kPaperDt), "bad_data");
}

TEST(RandomWalkModelFit, IgnoresChanceDipInTheTail) {
  // The paper's y axis on log:20: a last point far below the V (as 2 of 20
  // simulated 42000-sample records show) is not the minimum the paper meant.
  const RandomWalkModel truth{kSigmaN[1], kSigmaMu[1], kPaperDt, kGyroLsb};
  auto curve = exact_curve(truth, log_grid(kPaperSamples / 4), kPaperSamples);
  const auto clean = cubecal::fit_random_walk_model(curve, kPaperDt, kGyroLsb);
  const double vmin = *std::min_element(curve.dev.begin(), curve.dev.end());
  curve.dev.back() = 0.7 * vmin;
  curve.interval.back() = {0.3 * vmin, 2.0 * vmin};
  const auto dipped = cubecal::fit_random_walk_model(curve, kPaperDt, kGyroLsb);
  EXPECT_EQ(dipped.sigma_n, clean.sigma_n);
  EXPECT_EQ(dipped.sigma_mu, clean.sigma_mu);
  // Without usable intervals the EDF decides; without EDF any rise does.
  curve.interval.clear();
  EXPECT_EQ(cubecal::fit_random_walk_model(curve, kPaperDt, kGyroLsb).sigma_mu, clean.sigma_mu);
  curve.edf.clear();
  EXPECT_EQ(cubecal::fit_random_walk_model(curve, kPaperDt, kGyroLsb).sigma_mu, clean.sigma_mu);
  // A Gauss-Markov curve falls again beyond its peak (~1.9 T_c); the V before
  // it is what the paper's model can be adjusted to.
  const GaussMarkovModel gm{0.01, 0.002, 50.0, kPaperDt, 0.0};
  const auto gm_curve = exact_curve(gm, log_grid(125000), 500000);
  EXPECT_LT(gm_curve.dev.back(), *std::min_element(gm_curve.dev.begin(), gm_curve.dev.end() - 1));
  const auto rw = cubecal::fit_random_walk_model(gm_curve, kPaperDt);
  EXPECT_NEAR(rw.sigma_n / gm.sigma_n, 1.0, 0.01);
  // Same lowest point as the V (tau <= 2 T_c), not as the tail.
  double v_min = std::numeric_limits<double>::infinity(), model_min = v_min;
  for (std::size_t i = 0; i < gm_curve.size(); ++i) {
    const auto m = static_cast<std::size_t>(std::llround(gm_curve.tau[i] / kPaperDt));
    model_min = std::min(model_min, cubecal::avar(rw, m));
    if (gm_curve.tau[i] <= 2.0 * gm.tau_c) v_min = std::min(v_min, gm_curve.dev[i]);
  }
  EXPECT_NEAR(model_min / (v_min * v_min), 1.0, 1e-12);
  // Below the V the GM is a random walk with K^2 = 2 sigma_b^2 / T_c, but it
  // already bends under it at the V (tau ~ 0.27 T_c: factor ~ 1 - 0.75 tau/T_c),
  // so the adjusted walk is ~20 % weaker in variance.
  const double k2_ratio = rw.sigma_mu * rw.sigma_mu * kPaperDt / (2.0 * gm.sigma_b * gm.sigma_b / gm.tau_c);
  EXPECT_GT(k2_ratio, 0.7);
  EXPECT_LT(k2_ratio, 0.9);
}

// The paper's model row reproduced from its own sigma_n, sigma_mu: 42000
// samples at 10 Hz of eq. 1-3 (quantized, int() truncation), OADEV on log:20,
// N = sigma(1 s) * 60, B = sigma_min / 0.664 * 3600, T = tau at the minimum.
// The minimum is read over tau <= record / 10 (420 s, at least ten
// independent clusters): beyond that a 42000-sample curve has 2-5 degrees of
// freedom, and 2 of 20 y-axis records dip there below their V (counted in the
// printout as "tail"). fit_random_walk_model finds the V bottom itself.
TEST(RandomWalkModelFit, MonteCarloReproducesPaperModelRow) {
  constexpr int kSeeds = 20;
  const double tau_read_max = 0.1 * static_cast<double>(kPaperSamples) * kPaperDt;
  const char* names = "xyz";
  for (double lsb : {kGyroLsb, 0.0}) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> n_s, nt_s, b_s, t_s, fn_s, fmu_s;
      int tail = 0;
      for (int seed = 0; seed < kSeeds; ++seed) {
        const auto y = simulate_paper_gyro(kPaperSamples, kSigmaN[axis], kSigmaMu[axis], kPaperDt, kFixedBias[axis],
                                           lsb, 1000u * static_cast<unsigned>(axis) + static_cast<unsigned>(seed));
        const auto c = oadev_curve(y, kPaperDt);
        std::size_t imin = 0;
        for (std::size_t i = 0; i < c.size() && c.tau[i] <= tau_read_max; ++i)
          if (c.dev[i] < c.dev[imin]) imin = i;
        if (*std::min_element(c.dev.begin(), c.dev.end()) < c.dev[imin]) ++tail;
        n_s.push_back(c.dev[index_of_tau(c, 1.0)] * 60.0);
        double n2 = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < imin; ++i) n2 = std::min(n2, c.dev[i] * c.dev[i] * c.tau[i]);
        nt_s.push_back(std::sqrt(n2) * 60.0);
        b_s.push_back(c.dev[imin] / cubecal::kFlickerFloor * 3600.0);
        t_s.push_back(c.tau[imin]);
        const auto fit = cubecal::fit_random_walk_model(c, kPaperDt, lsb);
        fn_s.push_back(fit.sigma_n);
        fmu_s.push_back(fit.sigma_mu);
      }
      std::printf(
          "[ paper  ] lsb %-5g axis %c  N %.4f [%.4f %.4f] Ntan %.4f [%.4f %.4f] paper %.4f | "
          "B %.3f [%.3f %.3f] paper %.3f | T %.1f [%.1f %.1f] paper %.1f tail %d | "
          "fit sigma_n %.2fe-3 [%.2f %.2f] sigma_mu %.3fe-3 [%.3f %.3f]\n",
          lsb, names[axis], quantile(n_s, 0.5), quantile(n_s, 0.025), quantile(n_s, 0.975), quantile(nt_s, 0.5),
          quantile(nt_s, 0.025), quantile(nt_s, 0.975), kPaperN[axis], quantile(b_s, 0.5), quantile(b_s, 0.025),
          quantile(b_s, 0.975), kPaperB[axis], quantile(t_s, 0.5), *std::min_element(t_s.begin(), t_s.end()),
          *std::max_element(t_s.begin(), t_s.end()), kPaperT[axis], tail, quantile(fn_s, 0.5) * 1e3,
          quantile(fn_s, 0.025) * 1e3, quantile(fn_s, 0.975) * 1e3, quantile(fmu_s, 0.5) * 1e3,
          quantile(fmu_s, 0.025) * 1e3, quantile(fmu_s, 0.975) * 1e3);
      // The adjustment run on the simulated curves gives back the model.
      EXPECT_NEAR(quantile(fn_s, 0.5) / kSigmaN[axis], 1.0, 0.02) << "axis " << names[axis];
      EXPECT_NEAR(quantile(fmu_s, 0.5) / kSigmaMu[axis], 1.0, 0.15) << "axis " << names[axis];
      // The paper's row within the 2.5-97.5 % range of the seeds. One
      // exception, a finding rather than a tolerance: with eq. 3's
      // quantization the white variance per sample grows by 1/(12 lsb^2)
      // (+1 % in N), and the paper's y-axis N = 0.2723 then lies 1.8 % (2.1
      // sigma) below the seeds' mean 0.2773, below all 20 seeds (lowest
      // 0.2727); without quantization it is inside the range. There it is
      // held to 3 sigma of the seeds.
      const bool y_quantized = axis == 1 && lsb > 0.0;
      if (!y_quantized) {
        EXPECT_GE(kPaperN[axis], quantile(n_s, 0.025)) << "axis " << names[axis] << " lsb " << lsb;
        EXPECT_LE(kPaperN[axis], quantile(n_s, 0.975)) << "axis " << names[axis] << " lsb " << lsb;
      } else {
        double mean = 0.0, var = 0.0;
        for (double v : n_s) mean += v / kSeeds;
        for (double v : n_s) var += (v - mean) * (v - mean) / (kSeeds - 1);
        EXPECT_LT(std::abs(kPaperN[axis] - mean), 3.0 * std::sqrt(var));
      }
      EXPECT_GE(kPaperB[axis], quantile(b_s, 0.025)) << "axis " << names[axis] << " lsb " << lsb;
      EXPECT_LE(kPaperB[axis], quantile(b_s, 0.975)) << "axis " << names[axis] << " lsb " << lsb;
      EXPECT_GE(kPaperT[axis], *std::min_element(t_s.begin(), t_s.end())) << "axis " << names[axis];
      EXPECT_LE(kPaperT[axis], *std::max_element(t_s.begin(), t_s.end())) << "axis " << names[axis];
    }
  }
}

// ---------------------------------------------------------------------------
// Gauss-Markov fit and residuals

TEST(GaussMarkovModelFit, RecoversExactCurve) {
  const double dt = 0.1;
  for (double lsb : {0.0, kGyroLsb}) {
    const GaussMarkovModel truth{0.01, 0.002, 50.0, dt, lsb};
    const auto ms = log_grid(125000);
    const auto fit = cubecal::fit_gauss_markov_model(exact_curve(truth, ms, 500000), dt, lsb);
    EXPECT_NEAR(fit.sigma_n / truth.sigma_n, 1.0, 0.02);
    EXPECT_NEAR(fit.sigma_b / truth.sigma_b, 1.0, 0.02);
    EXPECT_NEAR(fit.tau_c / truth.tau_c, 1.0, 0.02);
    EXPECT_EQ(fit.dt, dt);
    EXPECT_EQ(fit.lsb, lsb);
  }
}

TEST(GaussMarkovModelFit, RecoversSimulatedRecord) {
  const double dt = 0.1, sigma_n = 0.01, sigma_b = 0.002, tc = 50.0;
  const std::size_t n = 500000;
  const double phi = std::exp(-dt / tc);
  std::mt19937_64 rng(42);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> y(n);
  double b = sigma_b * gauss(rng);  // stationary start
  for (std::size_t k = 0; k < n; ++k) {
    y[k] = b + sigma_n * gauss(rng);
    b = phi * b + sigma_b * std::sqrt(1.0 - phi * phi) * gauss(rng);
  }
  const auto curve = oadev_curve(y, dt);
  const auto fit = cubecal::fit_gauss_markov_model(curve, dt);
  std::printf("[ gm sim ] sigma_n %.5f sigma_b %.5f T_c %.2f\n", fit.sigma_n, fit.sigma_b, fit.tau_c);
  EXPECT_NEAR(fit.sigma_n / sigma_n, 1.0, 0.15);
  EXPECT_NEAR(fit.sigma_b / sigma_b, 1.0, 0.15);
  EXPECT_NEAR(fit.tau_c / tc, 1.0, 0.15);
  // The fit minimizes the weighted chi-squared in variance that residual()
  // reports (weights edf / (2 dev^4)): any nearby model is worse.
  const double chi2 = cubecal::residual(fit, curve).chi2;
  for (int k = 0; k < 3; ++k) {
    for (double f : {0.99, 1.01}) {
      GaussMarkovModel other = fit;
      (k == 0 ? other.sigma_n : k == 1 ? other.sigma_b : other.tau_c) *= f;
      EXPECT_GT(cubecal::residual(other, curve).chi2, chi2) << "parameter " << k << " x " << f;
    }
  }
}

TEST(ModelResidual, ZeroOnOwnCurve) {
  const auto ms = log_grid(10500);
  const RandomWalkModel rw{kSigmaN[0], kSigmaMu[0], kPaperDt, kGyroLsb};
  const auto r1 = cubecal::residual(rw, exact_curve(rw, ms, kPaperSamples));
  EXPECT_NEAR(r1.rms_log, 0.0, 1e-9);
  EXPECT_NEAR(r1.chi2, 0.0, 1e-9);
  const GaussMarkovModel gm{0.01, 0.002, 50.0, kPaperDt, 0.0};
  const auto r2 = cubecal::residual(gm, exact_curve(gm, ms, kPaperSamples));
  EXPECT_NEAR(r2.rms_log, 0.0, 1e-9);
  EXPECT_NEAR(r2.chi2, 0.0, 1e-9);

  // A known offset: model dev 2 % high everywhere.
  auto shifted = exact_curve(rw, ms, kPaperSamples);
  double chi2 = 0.0;
  for (std::size_t i = 0; i < shifted.size(); ++i) {
    shifted.dev[i] /= 1.02;
    chi2 += shifted.edf[i] / 2.0 * (1.02 * 1.02 - 1.0) * (1.02 * 1.02 - 1.0);
  }
  const auto r3 = cubecal::residual(rw, shifted);
  EXPECT_NEAR(r3.rms_log, std::log(1.02), 1e-12);
  EXPECT_NEAR(r3.chi2 / chi2, 1.0, 1e-12);
}

TEST(ModelResidual, GaussMarkovBeatsRandomWalkOnGaussMarkovCurve) {
  // Up to tau = 2 T_c the GM curve has a V (white arm, then the rising GM
  // arm), so the paper's adjustment applies; its unbounded walk cannot bend
  // over toward the GM peak.
  const GaussMarkovModel truth{0.01, 0.002, 50.0, kPaperDt, 0.0};
  const auto ms = log_grid(1000);
  const auto curve = exact_curve(truth, ms, 500000);
  const auto rw = cubecal::fit_random_walk_model(curve, kPaperDt);
  const auto gm = cubecal::fit_gauss_markov_model(curve, kPaperDt);
  const auto r_rw = cubecal::residual(rw, curve);
  const auto r_gm = cubecal::residual(gm, curve);
  EXPECT_LT(r_gm.rms_log, 1e-4);
  EXPECT_GT(r_rw.rms_log, 0.01);
  EXPECT_LT(r_gm.rms_log, r_rw.rms_log);
  EXPECT_LT(r_gm.chi2, r_rw.chi2);
}

}  // namespace
