// The spread of an Allan curve's minimum (minimum_spread.hpp; docs/formulas/planning.md §3).
#include "cubecal/noise/minimum_spread.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <boost/math/special_functions/trigamma.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "cubecal/noise/mixture_edf.hpp"
#include "detail/avar_correlation.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kDraws = 4000;
constexpr std::uint64_t kSeed = 952;
// Points whose deviation is within this many of their (and the minimum's)
// log-sds of the minimum can hold it.
constexpr double kReach = 6.0;

// The EDF of point i: the mixture's where the curve knows its factors, else the curve's own.
double point_edf(const AllanCurve& c, const NoiseFit& fit, std::size_t i) {
  if (i < c.m.size() && i < c.terms.size() && c.m[i] > 0) {
    const double tau0 = c.tau[i] / static_cast<double>(c.m[i]);
    const double e = oadev_mixture_edf(fit.c, c.m[i], tau0, c.terms[i] + 2 * c.m[i]);
    if (e > 0.0) return e;
  }
  return c.edf[i];
}

// ln(dev estimate / dev) for the standard normal z of a chi-squared
// estimate of edf degrees of freedom: Wilson & Hilferty's cube,
// chi2 / edf ~ (1 - 2 / (9 edf) + z sqrt(2 / (9 edf)))^3, which keeps the
// long lower tail of a few degrees of freedom that a log-normal law lacks
// (the far points of the curve, where a low fluctuation can become the minimum).
double log_ratio(double edf, double z) {
  const double a = 2.0 / (9.0 * edf);
  const double cube = 1.0 - a + z * std::sqrt(a);
  return cube > 1e-6 ? 1.5 * std::log(cube) : 1.5 * std::log(1e-6);
}

// The points that can hold the minimum of `dev`: within kReach of their (and
// the minimum's) log-sds of it. Returns {imin, lo, hi}.
std::array<std::size_t, 3> minimum_window(const std::vector<double>& dev, const std::vector<double>& sdln) {
  const auto imin = static_cast<std::size_t>(std::min_element(dev.begin(), dev.end()) - dev.begin());
  const auto near = [&](std::size_t i) { return std::log(dev[i] / dev[imin]) < kReach * (sdln[i] + sdln[imin]); };
  std::size_t lo = imin, hi = imin;
  while (lo > 0 && near(lo - 1)) --lo;
  while (hi + 1 < dev.size() && near(hi + 1)) ++hi;
  return {imin, lo, hi};
}

double sd_of_log(double edf) { return 0.5 * std::sqrt(boost::math::trigamma(edf / 2.0)); }

// True when the fit's curve lies within three log-sds of every measured point that can hold the minimum.
bool fit_describes_minimum(const AllanCurve& c, const NoiseFit& fit) {
  if (std::none_of(fit.c.begin(), fit.c.end(), [](double x) { return x > 0.0; })) return false;
  std::vector<double> sdln(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) sdln[i] = sd_of_log(c.edf[i]);
  const auto [imin, lo, hi] = minimum_window(c.dev, sdln);
  (void)imin;
  for (std::size_t i = lo; i <= hi; ++i) {
    const double f = noise_model_adev(fit.c, c.tau[i]);
    if (!(f > 0.0) || !std::isfinite(f) || std::abs(std::log(c.dev[i] / f)) > 3.0 * sdln[i]) return false;
  }
  return true;
}

}  // namespace

double MinimumSpread::b_half_width(double ci) const noexcept {
  if (!valid || b_quantiles.empty() || !(ci > 0.0 && ci < 1.0)) return 0.0;
  const auto q = [&](double p) {
    const double x = p * static_cast<double>(b_quantiles.size() - 1);
    const auto i = static_cast<std::size_t>(x);
    const double f = x - static_cast<double>(i);
    return i + 1 < b_quantiles.size() ? b_quantiles[i] * (1 - f) + b_quantiles[i + 1] * f : b_quantiles.back();
  };
  return 0.5 * (q(0.5 + ci / 2.0) - q(0.5 - ci / 2.0)) / q(0.5);
}

double MinimumSpread::t_half_width(double ci) const noexcept {
  if (!valid || t_probability.empty() || !(ci > 0.0 && ci < 1.0)) return 0.0;
  // The quantile q of the law uniform over each cell.
  const auto quantile = [&](double q) {
    double cum = 0.0;
    for (std::size_t i = 0; i < t_probability.size(); ++i) {
      const double p = t_probability[i];
      if (p > 0.0 && cum + p >= q) return t_edges[i] + (q - cum) / p * (t_edges[i + 1] - t_edges[i]);
      cum += p;
    }
    return t_edges.back();
  };
  return 0.5 * (quantile(0.5 + ci / 2.0) - quantile(0.5 - ci / 2.0));
}

MinimumSpread minimum_spread(const AllanCurve& c, const NoiseFit& fit) {
  MinimumSpread s;
  const std::size_t n = c.size();
  if (n < 2 || c.edf.size() != n) return s;
  for (std::size_t i = 0; i < n; ++i)
    if (!(c.edf[i] > 0.0) || !(c.dev[i] > 0.0)) return s;
  // The curve's shape and its points' EDFs: the fit's (its curve, the EDFs of
  // its mixture of noises) where it describes the measured curve around the
  // minimum, for a measured curve's own points already carry one record's
  // noise, which the draws would add twice; else the measured curve with its
  // own EDFs (a fit that misses the bottom, as on the ADIS16405
  // accelerometers, would put the minimum elsewhere).
  std::vector<double> dev = c.dev, edf = c.edf;
  if (fit_describes_minimum(c, fit)) {
    for (std::size_t i = 0; i < n; ++i) {
      dev[i] = noise_model_adev(fit.c, c.tau[i]);
      edf[i] = point_edf(c, fit, i);
    }
  }
  std::vector<double> sdln(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) sdln[i] = sd_of_log(edf[i]);
  const auto [imin, lo, hi] = minimum_window(dev, sdln);
  const std::size_t k = hi - lo + 1;
  const std::vector<double> tau(c.tau.begin() + static_cast<std::ptrdiff_t>(lo),
                                c.tau.begin() + static_cast<std::ptrdiff_t>(hi + 1));
  // The correlation of the estimates over the whole curve (so that each point's draws do not depend on which
  // points can hold the minimum: the result moves continuously with the curve). The spectrum's shape is all it
  // needs: the fit's coefficients relative to the minimum's variance.
  std::array<double, 5> rel{};
  const double v0 = dev[imin] * dev[imin];
  for (std::size_t j = 0; j < 5; ++j) rel[j] = fit.c[j] / v0;
  const double tau0 =
      c.m.empty() || c.m.front() == 0 ? c.tau.front() : c.tau.front() / static_cast<double>(c.m.front());
  const auto ni = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd rho = Eigen::MatrixXd::Identity(ni, ni);
  if (std::any_of(rel.begin(), rel.end(), [](double x) { return x > 0.0; }))
    rho = noise::detail::projected_correlation(c.tau, Eigen::MatrixXd::Identity(ni, ni),
                                               noise::detail::psd_of(rel, 0.5 / tau0));
  // Unit variances (the sds are the EDFs'), and a hair on the diagonal for a factor of a matrix that is
  // positive semi-definite only to rounding.
  for (Eigen::Index i = 0; i < ni; ++i) rho(i, i) = 1.0 + 1e-9;
  const Eigen::MatrixXd l = Eigen::LLT<Eigen::MatrixXd>(rho).matrixL();

  std::mt19937_64 engine(kSeed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd z(ni);
  std::vector<double> lowest;
  lowest.reserve(kDraws);
  std::size_t ends = 0;
  std::vector<double> hist(k, 0.0);
  for (std::size_t draw = 0; draw < kDraws; ++draw) {
    for (Eigen::Index i = 0; i < ni; ++i) z(i) = normal(engine);
    double best = std::numeric_limits<double>::infinity();
    std::size_t at = 0;
    for (std::size_t i = lo; i <= hi; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      const double e = l.row(ii).head(ii + 1).dot(z.head(ii + 1));
      const double v = std::log(dev[i] / dev[imin]) + log_ratio(edf[i], e);
      if (v < best) best = v, at = i - lo;
    }
    // A lowest point at either end of the curve is no minimum (reported_terms.hpp): such a record states no B or T.
    if (lo + at == 0 || lo + at + 1 == n) {
      ++ends;
      continue;
    }
    lowest.push_back(std::exp(best));
    hist[at] += 1.0;
  }
  const double m = static_cast<double>(kDraws - ends);
  s.valid = true;
  std::sort(lowest.begin(), lowest.end());
  s.b_quantiles = std::move(lowest);
  for (double& h : hist) h /= m;
  s.t_probability = std::move(hist);
  // Cell edges half-way between neighbouring taus in ln tau; the end cells as wide as their neighbour's half.
  const double tau_min = c.tau[imin];  // (a structured binding is not captured by every compiler's lambdas)
  const auto ln = [&](std::size_t i) { return std::log(tau[i] / tau_min); };
  s.t_edges.resize(k + 1);
  for (std::size_t i = 1; i < k; ++i) s.t_edges[i] = 0.5 * (ln(i - 1) + ln(i));
  s.t_edges[0] = k > 1 ? ln(0) - (ln(1) - ln(0)) / 2 : ln(0) - 0.1;
  s.t_edges[k] = k > 1 ? ln(k - 1) + (ln(k - 1) - ln(k - 2)) / 2 : ln(0) + 0.1;
  s.lo = lo;
  s.hi = hi;
  s.at_end = static_cast<double>(ends) / static_cast<double>(kDraws);
  return s;
}

}  // namespace cubecal
