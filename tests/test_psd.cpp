// The Welch PSD, its EDF and bin covariance, log bins, the power-law fit
// and the PSD <-> Allan variance conversions (docs/formulas/spectral.md),
// against closed forms and seeded Monte Carlo within derived bounds.
#include <gtest/gtest.h>

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/pipeline/welch_psd.hpp"
#include "cubecal/spectral/allan_conversion.hpp"
#include "../src/spectral/detail/bin_covariance.hpp"
#include "cubecal/spectral/log_bins.hpp"
#include "cubecal/spectral/power_law_fit.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/deviation.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> white(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<double> x(n);
  for (auto& v : x) v = g(rng);
  return x;
}

// A rate random walk of coefficient K (u/sqrt(s)): increments K sqrt(tau0).
std::vector<double> random_walk(std::size_t n, double k, double rate_hz, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, k / std::sqrt(rate_hz));
  std::vector<double> x(n);
  double y = 0.0;
  for (auto& v : x) {
    y += g(rng);
    v = y;
  }
  return x;
}

WelchOptions options(Window w, Detrend d, std::size_t l, double overlap) {
  WelchOptions o;
  o.window = w;
  o.detrend = d;
  o.segment_length = l;
  o.overlap = overlap;
  return o;
}

// ---------------------------------------------------------------------------
// White noise: the level 2 sigma^2 / f_s, and each bin chi-squared with the
// EDF the estimator states.

struct WhiteCase {
  Window window;
  double overlap;
};

class WhiteNoisePsd : public ::testing::TestWithParam<WhiteCase> {};

TEST_P(WhiteNoisePsd, LevelAndPerBinChiSquared) {
  const double sigma = 2.0;
  const double rate = 100.0;
  const std::size_t n = std::size_t{1} << 18;
  const std::size_t l = std::size_t{1} << 12;
  const auto x = white(n, sigma, 11);
  const Psd p = pipeline::welch_psd(x, rate, options(GetParam().window, Detrend::constant, l, GetParam().overlap));
  const double s0 = 2.0 * sigma * sigma / rate;  // one-sided white level
  ASSERT_EQ(p.density.size(), l / 2 + 1);
  // The mean over the interior bins: expectation s0, variance from the bin
  // covariance (the bins are correlated by the window and the overlap).
  const std::size_t first = 1;
  const std::size_t count = l / 2 - 1;
  double mean = 0.0;
  for (std::size_t k = first; k < first + count; ++k) mean += p.density[k];
  mean /= static_cast<double>(count);
  const BinCovariance cov(p);
  const double sd = std::sqrt(cov.between(first, count, first, count));
  EXPECT_NEAR(mean / s0, 1.0, 4.0 * sd) << "sd " << sd;
  // Each bin: D nu / s0 ~ chi2(nu). Outside the central 95 %: 5 % of the
  // bins, with a binomial scatter widened by the correlation of neighbours
  // (at most a factor 2 in variance here): 6 sigma.
  std::size_t outside = 0;
  double sum_sq = 0.0;
  for (std::size_t k = first; k < first + count; ++k) {
    const double nu = p.edf[k];
    const boost::math::chi_squared chi(nu);
    const double z = p.density[k] * nu / s0;
    if (z < quantile(chi, 0.025) || z > quantile(chi, 0.975)) ++outside;
    sum_sq += (p.density[k] / s0 - 1.0) * (p.density[k] / s0 - 1.0);
  }
  const double frac = static_cast<double>(outside) / static_cast<double>(count);
  const double frac_sd = std::sqrt(2.0 * 0.05 * 0.95 / static_cast<double>(count));
  EXPECT_NEAR(frac, 0.05, 6.0 * frac_sd);
  // The scatter of the bins is 2 / nu (the stated EDF), within the sampling
  // error of a variance over ~count / 2 independent bins (6 sigma).
  const double nu = p.edf[l / 4];
  const double var = sum_sq / static_cast<double>(count);
  EXPECT_NEAR(var / (2.0 / nu), 1.0, 6.0 * std::sqrt(2.0 / (0.5 * static_cast<double>(count)) * (1.0 + 12.0 / nu)));
}

INSTANTIATE_TEST_SUITE_P(Windows, WhiteNoisePsd,
                         ::testing::Values(WhiteCase{Window::hann, 0.5}, WhiteCase{Window::rectangular, 0.0},
                                           WhiteCase{Window::blackman, 0.75}, WhiteCase{Window::hamming, 0.5}));

TEST(WelchPsd, RectangularWithoutOverlapHasTwiceTheSegmentsAsEdf) {
  // Independent segments, no taper: each interior bin is chi2 with 2 Ns.
  const auto x = white(64 * 256, 1.0, 3);
  const Psd p = pipeline::welch_psd(x, 1.0, options(Window::rectangular, Detrend::none, 256, 0.0));
  EXPECT_EQ(p.segments, 64u);
  EXPECT_NEAR(p.edf[10], 128.0, 1e-9);
  EXPECT_NEAR(p.edf[0], 64.0, 1e-9);    // DC: real, half
  EXPECT_NEAR(p.edf[128], 64.0, 1e-9);  // Nyquist: real, half
  EXPECT_NEAR(p.enbw_hz, 1.0 / 256.0, 1e-15);
}

TEST(WelchPsd, HannHalfOverlapEdfIsWelchs) {
  // Welch (1967) / Percival & Walden (1993) eq. 292b: nu = 2 Ns / (1 + 2 (1 - 1/Ns) rho^2),
  // with rho = sum h_t h_{t+L/2} = 1/6 for the Hann window at 50 % overlap.
  const std::size_t l = 1024;
  const auto x = white(l * 16, 1.0, 5);
  const Psd p = pipeline::welch_psd(x, 1.0, options(Window::hann, Detrend::constant, l, 0.5));
  const double ns = static_cast<double>(p.segments);
  EXPECT_EQ(p.segments, 31u);
  const double rho = 1.0 / 6.0;
  EXPECT_NEAR(p.edf[l / 4], 2.0 * ns / (1.0 + 2.0 * (1.0 - 1.0 / ns) * rho * rho), 1e-9);
}

TEST(WelchPsd, DefaultSegmentAndMinimumFrequency) {
  const auto x = white(100000, 1.0, 1);
  const Psd p = pipeline::welch_psd(x, 10.0);
  EXPECT_EQ(p.segment_length, 8192u);  // largest power of two <= 100000 / 8
  EXPECT_EQ(p.overlap, 4096u);
  EXPECT_EQ(p.segments, (100000u - 4096u) / 4096u);
  WelchOptions o;
  o.min_frequency_hz = 0.01;  // rate / L <= 0.01 Hz: L >= 1000
  const Psd q = pipeline::welch_psd(x, 10.0, o);
  EXPECT_EQ(q.segment_length, 1024u);
  EXPECT_LE(q.resolution_hz(), 0.01);
}

TEST(WelchPsd, RefusesWhatTheRecordCannotGive) {
  const auto x = white(100, 1.0, 1);
  auto option_of = [&](const WelchOptions& o) {
    try {
      (void)pipeline::welch_psd(x, 10.0, o);
    } catch (const UsageError& e) {
      return e.field() ? std::string(cubecal::field_name(*e.field())) : std::string();
    }
    return std::string("none");
  };
  WelchOptions o;
  o.segment_length = 101;
  EXPECT_EQ(option_of(o), "segment_length");
  o.segment_length = 2;
  EXPECT_EQ(option_of(o), "segment_length");
  o = {};
  o.min_frequency_hz = 0.01;  // 1024 samples at 10 Hz
  EXPECT_EQ(option_of(o), "min_frequency");
  o = {};
  o.overlap = 1.0;
  EXPECT_EQ(option_of(o), "overlap");
  const auto tiny = white(10, 1.0, 1);
  EXPECT_THROW((void)pipeline::welch_psd(tiny, 10.0), UsageError);
  std::vector<double> bad = white(64, 1.0, 1);
  bad[5] = std::nan("");
  EXPECT_THROW((void)pipeline::welch_psd(bad, 10.0), std::invalid_argument);
}

// ---------------------------------------------------------------------------
// Parseval

// sum_k P_k df over the whole one-sided spectrum.
double integral(const Psd& p) { return std::accumulate(p.density.begin(), p.density.end(), 0.0) * p.resolution_hz(); }

TEST(Parseval, ExactForRectangularWithoutDetrendOrOverlap) {
  const std::size_t l = 1000;
  auto x = white(20 * l + 37, 3.0, 8);  // the last 37 samples fall outside every segment
  for (double& v : x) v += 0.5;         // a mean, which no detrend keeps
  const Psd p = pipeline::welch_psd(x, 50.0, options(Window::rectangular, Detrend::none, l, 0.0));
  double ms = 0.0;
  for (std::size_t i = 0; i < 20 * l; ++i) ms += x[i] * x[i];
  ms /= static_cast<double>(20 * l);
  EXPECT_NEAR(integral(p) / ms, 1.0, 1e-13);
}

TEST(Parseval, TheWindowWeightedMeanSquareForAnyWindow) {
  // sum_k P_k df = sum_i sum_t w_t^2 x'_{i,t}^2 / (Ns sum w^2): the identity
  // behind the scaling, exact whatever the window, overlap and detrend.
  const std::size_t l = 512;
  const auto x = white(20 * l, 1.0, 9);
  for (Window w : {Window::hann, Window::hamming, Window::blackman, Window::rectangular}) {
    const Psd p = pipeline::welch_psd(x, 2.0, options(w, Detrend::constant, l, 0.5));
    const auto win = window_coefficients(w, l);
    double sw2 = 0.0;
    for (double v : win) sw2 += v * v;
    double s = 0.0;
    for (std::size_t i = 0; i < p.segments; ++i) {
      double mean = 0.0;
      for (std::size_t t = 0; t < l; ++t) mean += x[i * (l / 2) + t];
      mean /= static_cast<double>(l);
      for (std::size_t t = 0; t < l; ++t) {
        const double v = x[i * (l / 2) + t] - mean;
        s += win[t] * win[t] * v * v;
      }
    }
    EXPECT_NEAR(integral(p) / (s / (static_cast<double>(p.segments) * sw2)), 1.0, 1e-12) << to_string(w);
  }
}

TEST(Parseval, TheVarianceWithinItsDerivedTolerance) {
  // Hann, constant detrend, 50 % overlap on white noise of variance s2:
  // E[integral] = s2 (1 - 1/L) (the mean removed from each segment), and
  // Var[integral] = 2 s2^2 sum_n a_n^2, a_n = sum_i w^2_{n - i step} / (Ns sum w^2)
  // (each sample's weight in the integral; the detrend's O(1/L) correction
  // to the variance left out).
  const std::size_t l = 256;
  const double sigma = 1.5;
  const auto x = white(200 * l, sigma, 10);
  const Psd p = pipeline::welch_psd(x, 1.0, options(Window::hann, Detrend::constant, l, 0.5));
  const auto win = window_coefficients(Window::hann, l);
  double sw2 = 0.0;
  for (double v : win) sw2 += v * v;
  std::vector<double> a(x.size(), 0.0);
  for (std::size_t i = 0; i < p.segments; ++i)
    for (std::size_t t = 0; t < l; ++t) a[i * (l / 2) + t] += win[t] * win[t] / (static_cast<double>(p.segments) * sw2);
  double sa2 = 0.0;
  for (double v : a) sa2 += v * v;
  const double s2 = sigma * sigma;
  const double expected = s2 * (1.0 - 1.0 / static_cast<double>(l));
  const double sd = std::sqrt(2.0 * s2 * s2 * sa2);
  EXPECT_NEAR(integral(p), expected, 4.0 * sd) << "relative sd " << sd / s2;
  EXPECT_LT(sd / s2, 0.0075);  // a 3 % error in the expectation would show
}

// ---------------------------------------------------------------------------
// Bin covariance and log bins: the variance of a band mean over many seeded
// records is the one BinCovariance states.

struct BandCase {
  Window window;
  double overlap;
};

class BandVariance : public ::testing::TestWithParam<BandCase> {};

TEST_P(BandVariance, MatchesMonteCarlo) {
  const std::size_t l = 256;
  const std::size_t n = 16 * l;
  const int runs = 400;
  const std::size_t a = 10, m = 20;  // a band of 20 raw bins
  const std::size_t b = 30, k = 5;   // its neighbour
  std::vector<double> ga, gb;
  Psd first;
  for (int r = 0; r < runs; ++r) {
    const auto x = white(n, 1.0, 1000 + static_cast<std::uint64_t>(r));
    const Psd p = pipeline::welch_psd(x, 1.0, options(GetParam().window, Detrend::constant, l, GetParam().overlap));
    if (r == 0) first = p;
    double sa = 0.0, sb = 0.0;
    for (std::size_t i = a; i < a + m; ++i) sa += p.density[i];
    for (std::size_t i = b; i < b + k; ++i) sb += p.density[i];
    ga.push_back(sa / static_cast<double>(m) / 2.0);  // over the level 2 sigma^2 / fs = 2
    gb.push_back(sb / static_cast<double>(k) / 2.0);
  }
  const BinCovariance cov(first);
  auto var = [](const std::vector<double>& v) {
    const double mu = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
    double s = 0.0;
    for (double x : v) s += (x - mu) * (x - mu);
    return s / static_cast<double>(v.size() - 1);
  };
  // A variance over `runs` draws: relative sd sqrt(2 / (runs - 1)) (near
  // Gaussian band means); 4 sd.
  const double tol = 4.0 * std::sqrt(2.0 / (runs - 1));
  EXPECT_NEAR(var(ga) / cov.between(a, m, a, m), 1.0, tol);
  EXPECT_NEAR(var(gb) / cov.between(b, k, b, k), 1.0, tol);
  // A log bin's EDF is 2 / that variance.
  const Psd lb = log_bin(first, 5);
  for (std::size_t i = 0; i < lb.size(); ++i)
    EXPECT_NEAR(lb.edf[i], cov.edf(lb.first_bin[i], lb.bins[i]), 1e-9 * lb.edf[i]);
}

INSTANTIATE_TEST_SUITE_P(Windows, BandVariance,
                         ::testing::Values(BandCase{Window::hann, 0.5}, BandCase{Window::rectangular, 0.5},
                                           BandCase{Window::blackman, 0.0}));

TEST(LogBins, AverageEveryInteriorBinOnceInLogBands) {
  const auto x = white(1 << 14, 1.0, 4);
  const Psd raw = pipeline::welch_psd(x, 100.0, options(Window::hann, Detrend::constant, 1024, 0.5));
  const Psd lb = log_bin(raw, 10);
  std::size_t total = 0;
  for (std::size_t i = 0; i < lb.size(); ++i) {
    double s = 0.0;
    for (std::size_t k = lb.first_bin[i]; k < lb.first_bin[i] + lb.bins[i]; ++k) s += raw.density[k];
    EXPECT_DOUBLE_EQ(lb.density[i], s / static_cast<double>(lb.bins[i]));
    // Every bin of the band lies in [10^(j/10), 10^((j+1)/10)).
    const double j = std::floor(10.0 * std::log10(raw.frequency[lb.first_bin[i]]));
    const double last = raw.frequency[lb.first_bin[i] + lb.bins[i] - 1];
    EXPECT_LT(last, std::pow(10.0, (j + 1.0) / 10.0));
    EXPECT_GE(lb.frequency[i], raw.frequency[lb.first_bin[i]]);
    EXPECT_LE(lb.frequency[i], last * (1.0 + 1e-14));  // exp(log f) of a single bin: f to rounding
    if (i > 0) {
      EXPECT_EQ(lb.first_bin[i], lb.first_bin[i - 1] + lb.bins[i - 1]);
    }
    total += lb.bins[i];
  }
  EXPECT_EQ(lb.first_bin.front(), 1u);
  EXPECT_EQ(total, 1024u / 2 - 1);  // all but DC and Nyquist
  EXPECT_EQ(lb.bins.front(), 1u);   // a decade below 1 Hz holds single bins
  EXPECT_GT(lb.bins.back(), 50u);
}

// ---------------------------------------------------------------------------
// Power-law fit

TEST(PowerLawFit, RandomWalkSlopeMinusTwoAndK) {
  const double rate = 10.0;
  const double k = 2e-3;  // u/sqrt(s)
  const auto x = random_walk(std::size_t{1} << 20, k, rate, 21);
  const Psd p = pipeline::welch_psd(x, rate);  // hann, L = 2^17, half overlap, constant detrend
  // The sampled walk is K^2 / (2 pi^2 f^2) to within (pi f / f_s)^2 / 3
  // relative: below f_s / 50 that is under 0.2 %, far inside the fit's sigma.
  const double f_hi = rate / 50.0;
  // From raw bin 10 up, where the Hann window's leakage of the steep
  // spectrum is below 1.5 % (spectral.md §5.1), as the fit's default band.
  const SlopeFit s = fit_slope(p, 10.0 * p.resolution_hz(), f_hi);
  EXPECT_NEAR(s.slope, -2.0, 3.0 * s.slope_sigma);
  EXPECT_LT(s.slope_sigma, 0.05);
  PowerLawFitOptions o;
  o.exponents = {-2};
  o.max_frequency_hz = f_hi;
  const PowerLawFit fit = fit_power_law(p, o);
  ASSERT_TRUE(fit.terms[0].valid);
  const TermEstimate kk = term_from_power_law(Term::K, fit.terms[0].h, fit.terms[0].sigma);
  EXPECT_NEAR(kk.value, k, 3.0 * kk.sigma) << "sigma " << kk.sigma;
  EXPECT_LT(kk.sigma / k, 0.02);
  EXPECT_NEAR(fit.terms[0].h, k * k / (2.0 * kPi * kPi), 3.0 * fit.terms[0].sigma);
}

TEST(PowerLawFit, WhitePlusWalkGivesNAndKBesideTheAllanFit) {
  // The default model (-2, -1, 0, +2) on white noise plus a rate random
  // walk: N and K within 3 sigma of the truth, the flicker and quantization
  // terms absent or within 3 sigma of 0, and N, K within 3 combined sigma of
  // the five-term Allan fit that `analyze` makes on the same record.
  const double rate = 100.0;
  const double dt = 1.0 / rate;
  const double sigma = 0.05, walk = 0.02;
  const auto y = test::white_plus_walk(std::size_t{1} << 20, dt, sigma, walk, 7);
  const double n_true = sigma * std::sqrt(dt);
  const double k_true = walk * std::sqrt(dt);
  const Psd p = pipeline::welch_psd(y, rate);
  const PowerLawFit fit = fit_power_law(p);
  ASSERT_EQ(fit.terms.size(), 4u);
  const PowerLawTerm* h0 = fit.term(0);
  const PowerLawTerm* hm2 = fit.term(-2);
  ASSERT_TRUE(h0->valid);
  ASSERT_TRUE(hm2->valid);
  const TermEstimate n = term_from_power_law(Term::N, h0->h, h0->sigma);
  const TermEstimate k = term_from_power_law(Term::K, hm2->h, hm2->sigma);
  EXPECT_NEAR(n.value, n_true, 3.0 * n.sigma);
  EXPECT_NEAR(k.value, k_true, 3.0 * k.sigma);
  for (int alpha : {-1, 2}) {
    const PowerLawTerm* t = fit.term(alpha);
    if (t->valid) {
      EXPECT_LT(t->h, 3.0 * t->sigma) << alpha;
    }
  }
  // White dominates above the crossing f_c = sqrt(h_-2 / h_0), the walk below.
  const double fc = std::sqrt(hm2->h / h0->h);
  EXPECT_LT(hm2->f_hi, fc * 1.05);
  EXPECT_GT(h0->f_lo, fc * 0.95);
  EXPECT_LT(fit.scale, 1.5);

  const AllanCurve curve = to_allan_curve(oadev(y, rate, DataType::freq, parse_tau_grid("log:10")));
  const NoiseFit afit = fit_noise_terms(curve);
  EXPECT_NEAR(n.value, afit.N.value, 3.0 * std::hypot(n.sigma, afit.N.sigma));
  EXPECT_NEAR(k.value, afit.K.value, 3.0 * std::hypot(k.sigma, afit.K.sigma));
}

TEST(PowerLawFit, StatedUncertaintiesMatchTheScatterOverSeeds) {
  // 150 seeded records of white noise plus walk: the standardized errors
  // (h - h_true) / sigma of h_0 and h_-2 have unit variance (chi-squared
  // bounds of a variance over 150 draws, 99.9 %: 0.69 .. 1.38).
  const double rate = 10.0;
  const double dt = 1.0 / rate;
  const double sigma = 1.0, walk = 2.0;  // the walk dominates below f_c = 0.32 Hz
  const double h0_true = 2.0 * sigma * sigma * dt;
  const double hm2_true = walk * walk * dt / (2.0 * kPi * kPi);
  PowerLawFitOptions o;
  o.exponents = {-2, 0};
  o.max_frequency_hz = rate / 20.0;  // where the sampled walk is K^2/(2 pi^2 f^2) to 0.8 %
  const int runs = 150;
  double z0 = 0.0, z2 = 0.0;
  for (int r = 0; r < runs; ++r) {
    const auto y = test::white_plus_walk(1 << 14, dt, sigma, walk, 500 + static_cast<std::uint64_t>(r));
    const Psd p = pipeline::welch_psd(y, rate, options(Window::hann, Detrend::constant, 1024, 0.5));
    const PowerLawFit fit = fit_power_law(p, o);
    const PowerLawTerm* a = fit.term(0);
    const PowerLawTerm* b = fit.term(-2);
    ASSERT_TRUE(a->valid && b->valid);
    z0 += std::pow((a->h - h0_true) / a->sigma, 2);
    z2 += std::pow((b->h - hm2_true) / b->sigma, 2);
  }
  const boost::math::chi_squared chi(runs);
  const double lo = quantile(chi, 0.0005) / runs, hi = quantile(chi, 0.9995) / runs;
  EXPECT_GT(z0 / runs, lo);
  EXPECT_LT(z0 / runs, hi);
  EXPECT_GT(z2 / runs, lo);
  EXPECT_LT(z2 / runs, hi);
}

TEST(PowerLawFit, RefusesATooNarrowBandAndBadExponents) {
  const auto x = white(1 << 12, 1.0, 2);
  const Psd p = pipeline::welch_psd(x, 1.0);
  PowerLawFitOptions o;
  o.min_frequency_hz = 0.2;
  o.max_frequency_hz = 0.21;
  try {
    (void)fit_power_law(p, o);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::fit_range);
  }
  o = {};
  o.exponents = {0, 0};
  EXPECT_THROW((void)fit_power_law(p, o), UsageError);
  o.exponents = {5};
  EXPECT_THROW((void)fit_power_law(p, o), UsageError);
}

// ---------------------------------------------------------------------------
// PSD <-> Allan variance

TEST(AllanConversion, TermsToCoefficientsAndBack) {
  const double fh = 50.0;
  struct Row {
    Term term;
    double value;
    double h;           // one-sided, by the formulas of noise-terms.md §1.2
    double avar_at_2s;  // the IEEE 952 AVAR of the term at tau = 2 s
  };
  const double q = 0.01, n = 0.2, b = 0.03, k = 0.004;
  const Row rows[] = {
      {Term::Q, q, 4.0 * kPi * kPi * q * q / fh, 3.0 * q * q / 4.0},
      {Term::N, n, 2.0 * n * n, n * n / 2.0},
      {Term::B, b, b * b / kPi, 2.0 * std::log(2.0) / kPi * b * b},
      {Term::K, k, k * k / (2.0 * kPi * kPi), k * k * 2.0 / 3.0},
  };
  for (const Row& r : rows) {
    const double h = power_law_coefficient(r.term, r.value, fh);
    EXPECT_NEAR(h / r.h, 1.0, 1e-15);
    const TermEstimate t = term_from_power_law(r.term, h, 0.1 * h, fh);
    EXPECT_TRUE(t.valid);
    EXPECT_NEAR(t.value / r.value, 1.0, 1e-15);
    EXPECT_NEAR(t.sigma / r.value, 0.05, 1e-15);  // a 10 % h is a 5 % term
    const double avar = power_law_avar(power_law_exponent(r.term), h, 2.0, fh);
    EXPECT_NEAR(avar / r.avar_at_2s, 1.0, 1e-14);
    // IEEE 952's two-sided forms, half the one-sided.
    const double f = 0.7;
    const double two = two_sided_density(r.term, r.value, f, fh);
    EXPECT_NEAR(two / (0.5 * h * std::pow(f, power_law_exponent(r.term))), 1.0, 1e-15);
  }
  EXPECT_NEAR(two_sided_density(Term::N, n, 3.0) / (n * n), 1.0, 1e-15);
  EXPECT_NEAR(two_sided_density(Term::K, k, 3.0) / (k * k / std::pow(2.0 * kPi * 3.0, 2)), 1.0, 1e-15);
  EXPECT_NEAR(two_sided_density(Term::B, b, 3.0) / (b * b / (2.0 * kPi * 3.0)), 1.0, 1e-15);
  EXPECT_FALSE(term_from_power_law(Term::N, 0.0, 1.0).valid);
  EXPECT_THROW((void)power_law_exponent(Term::R), std::invalid_argument);
}

// The one-sided density on k df, k = 0..L/2, with the end values halved
// (the trapezoid rule, as the estimator's DC and Nyquist bins).
std::vector<double> grid(std::size_t l, double rate, double (*s)(double, double), double param) {
  std::vector<double> d(l / 2 + 1);
  const double df = rate / static_cast<double>(l);
  for (std::size_t k = 1; k < d.size(); ++k) d[k] = s(static_cast<double>(k) * df, param);
  d.back() *= 0.5;
  return d;
}

TEST(AllanConversion, SampledWhiteNoiseIsSigmaSquaredOverM) {
  // Samples of variance s2: S = 2 s2 / fs on [0, fs/2]; AVAR(m tau0) = s2 / m.
  const double rate = 20.0, s2 = 0.3;
  const std::size_t l = 1 << 14;
  auto d = grid(
      l, rate, [](double, double v) { return v; }, 2.0 * s2 / rate);
  d[0] = 0.5 * 2.0 * s2 / rate;
  std::vector<double> taus;
  for (std::size_t m = 1; m <= 1024; m *= 2) taus.push_back(static_cast<double>(m) / rate);
  const auto avar = avar_from_density(d, rate / static_cast<double>(l), taus, rate, AllanKernel::sampled);
  for (std::size_t i = 0; i < taus.size(); ++i) EXPECT_NEAR(avar[i] / (s2 / (taus[i] * rate)), 1.0, 1e-12) << taus[i];
}

TEST(AllanConversion, SampledRandomWalkIsExact) {
  // y_n = y_{n-1} + e_n, var e = q: one-sided S(f) = q tau0 / (2 sin^2(pi f tau0)),
  // AVAR(m tau0) = q (2 m^2 + 1) / (6 m). The integrand tends to q m^2 tau0 / 2
  // at f = 0, the trapezoid's first node, added here (S itself is infinite there).
  const double rate = 10.0, q = 1e-4;
  const double tau0 = 1.0 / rate;
  const std::size_t l = 1 << 16;
  const double df = rate / static_cast<double>(l);
  auto d = grid(
      l, rate, [](double f, double qt) { return qt / (2.0 * std::pow(std::sin(kPi * f / 10.0), 2)); }, q * tau0);
  for (double m : {1.0, 2.0, 5.0, 16.0, 100.0, 512.0}) {
    const double tau = m * tau0;
    const double avar = avar_from_density(d, df, std::vector<double>{tau}, rate)[0] + q * m * m * tau0 * df / 2.0;
    EXPECT_NEAR(avar / (q * (2.0 * m * m + 1.0) / (6.0 * m)), 1.0, 1e-9) << m;
  }
}

TEST(AllanConversion, ContinuousRandomWalkWithinTheTruncationBound) {
  // S = h / f^2, continuous kernel: AVAR = (2 pi^2 / 3) h tau. The grid adds
  // the f = 0 node's limit h pi^2 tau^2 (trapezoid); what lies above f_s/2 is
  // at most 2 h / (3 pi^2 tau^2 F^3) (sin^4 <= 1), the bound of the test.
  const double rate = 100.0, h = 3e-6;
  const std::size_t l = 1 << 18;
  const double df = rate / static_cast<double>(l);
  const double big_f = rate / 2.0;
  auto d = grid(
      l, rate, [](double f, double hh) { return hh / (f * f); }, h);
  for (double tau : {0.1, 1.0, 10.0, 50.0}) {
    const double num = avar_from_density(d, df, std::vector<double>{tau}, rate, AllanKernel::continuous)[0] +
                       h * kPi * kPi * tau * tau * df;
    const double exact = power_law_avar(-2, h, tau);
    const double bound = 2.0 * h / (3.0 * kPi * kPi * tau * tau * big_f * big_f * big_f) + 1e-9 * exact;
    EXPECT_NEAR(num, exact, bound) << tau;
  }
}

TEST(AllanConversion, SimulatedRecordOadevAgreesWithThePsdIntegral) {
  // White noise plus a rate random walk: at each tau up to a sixteenth of a
  // segment, the AVAR integrated over the record's Welch PSD lies inside the
  // 95 % interval of the record's OADEV.
  const double rate = 50.0;
  const double dt = 1.0 / rate;
  const auto y = test::white_plus_walk(std::size_t{1} << 19, dt, 0.1, 0.05, 77);
  const Psd p = pipeline::welch_psd(y, rate);  // L = 2^16
  StabilityOptions so;
  so.ci = 0.95;
  const auto points = oadev(y, rate, DataType::freq, {}, so);
  std::size_t checked = 0;
  for (const auto& pt : points) {
    if (pt.m > p.segment_length / 16) break;
    const double adev = std::sqrt(avar_from_psd(p, std::vector<double>{pt.tau})[0]);
    EXPECT_GE(adev, pt.interval.lo) << "tau " << pt.tau;
    EXPECT_LE(adev, pt.interval.hi) << "tau " << pt.tau;
    ++checked;
  }
  EXPECT_GE(checked, 10u);
}

}  // namespace
}  // namespace cubecal
