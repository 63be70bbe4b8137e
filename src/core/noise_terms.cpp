// IEEE Std 952 noise terms from an Allan-deviation curve: slope read-offs
// (what the paper and most lab notebooks do) and a weighted non-negative
// least-squares fit of the five-term variance model.
#include "cubecal/core/noise_terms.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace cubecal {

namespace {

using Eigen::Index;

// ---------------------------------------------------------------------------
// Read-off rules

// A point belongs to a region of slope s0 when its local log-log slope is
// within this of s0. 0.15 is 30 % of the spacing between the IEEE 952
// slopes (-1, -1/2, 0, +1/2, +1), so neighbouring regions never share a
// point, and it keeps a white-noise arm as "white" until the next term
// brings in about 15 % of the variance.
constexpr double kSlopeTolerance = 0.15;

// The local slope at a point is taken between neighbours at least this many
// decades away on each side, so that a dense grid (every m) does not give
// slopes between points 0.1 % apart in tau, which are pure estimator noise.
constexpr double kHalfBaselineDecades = 0.05;

// A region must span at least a factor of 2 in tau (and two points): a curve
// that merely turns through a slope on its way between two regions (white
// to rate ramp passes through +1/2) does not show that noise term.
constexpr double kMinRegionDecades = 0.30103;

std::vector<double> local_slopes(const AllanCurve& c) {
  const std::size_t n = c.size();
  std::vector<double> s(n, std::numeric_limits<double>::quiet_NaN());
  if (n < 2) return s;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t j = i;
    if (i > 0) {
      j = i - 1;
      while (j > 0 && std::log10(c.tau[i] / c.tau[j]) < kHalfBaselineDecades) --j;
    }
    std::size_t k = i;
    if (i + 1 < n) {
      k = i + 1;
      while (k + 1 < n && std::log10(c.tau[k] / c.tau[i]) < kHalfBaselineDecades) ++k;
    }
    s[i] = std::log(c.dev[k] / c.dev[j]) / std::log(c.tau[k] / c.tau[j]);
  }
  return s;
}

struct Run {
  std::size_t first = 0;
  std::size_t last = 0;  // inclusive
};

// Maximal runs of consecutive points whose slope is within tolerance of s0
// and that are wide enough to count as a region.
std::vector<Run> regions_of_slope(const AllanCurve& c, const std::vector<double>& slope,
                                  double s0) {
  std::vector<Run> runs;
  const std::size_t n = c.size();
  std::size_t i = 0;
  while (i < n) {
    if (!(std::abs(slope[i] - s0) <= kSlopeTolerance)) { ++i; continue; }
    std::size_t j = i;
    while (j + 1 < n && std::abs(slope[j + 1] - s0) <= kSlopeTolerance) ++j;
    if (j > i && std::log10(c.tau[j] / c.tau[i]) >= kMinRegionDecades - 1e-12)
      runs.push_back({i, j});
    i = j + 1;
  }
  return runs;
}

// Relative half-width of a point's confidence interval, as a 1-sigma
// relative uncertainty of the deviation. Falls back to the chi-squared
// approximation 1/sqrt(2 edf) when the curve carries no interval.
double relative_sigma(const AllanCurve& c, std::size_t i) {
  if (c.hi[i] > c.lo[i] && c.lo[i] > 0.0) return (c.hi[i] - c.lo[i]) / (2.0 * c.dev[i]);
  if (c.edf[i] > 0.0) return 1.0 / std::sqrt(2.0 * c.edf[i]);
  return 0.0;
}

// One IEEE 952 straight-line term: sigma(tau) = value * (tau / tau_read)^slope.
struct LineTerm {
  double slope;
  double tau_read;     // where the line's ordinate is the term's value
  bool at_short_taus;  // where the region sits on a typical curve
};

// The line of the term's slope that lies on or below the curve and touches
// it: for a sum of power laws the curve is convex in log-log, and the line
// through point i has ordinate dev_i (tau_read / tau_i)^slope, smallest at
// the point where the curve's own slope equals the line's. Taking the
// minimum over the region is the paper's "line tangent to the curve".
TermEstimate read_line(const AllanCurve& c, const std::vector<double>& slope, LineTerm term) {
  TermEstimate e;
  const auto runs = regions_of_slope(c, slope, term.slope);
  if (runs.empty()) return e;
  const Run r = term.at_short_taus ? runs.front() : runs.back();
  std::size_t best = r.first;
  double best_value = std::numeric_limits<double>::infinity();
  for (std::size_t i = r.first; i <= r.last; ++i) {
    const double v = c.dev[i] * std::pow(term.tau_read / c.tau[i], term.slope);
    if (v < best_value) { best_value = v; best = i; }
  }
  e.valid = true;
  e.value = best_value;
  e.sigma = best_value * relative_sigma(c, best);
  e.tau_lo = c.tau[r.first];
  e.tau_hi = c.tau[r.last];
  return e;
}

// ---------------------------------------------------------------------------
// Lawson & Hanson (1974), "Solving Least Squares Problems", ch. 23:
// min ||A x - b|| subject to x >= 0, by an active set. `passive` returns
// which unknowns are free (strictly positive) at the solution.
Eigen::VectorXd nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                     std::vector<bool>& passive) {
  const Index n = a.cols();
  passive.assign(static_cast<std::size_t>(n), false);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  if (a.rows() == 0 || n == 0) return x;

  // Gradient components below this are round-off (scale-free: A's 1-norm
  // times b's size, as scipy's nnls).
  const double tol = 10.0 * std::numeric_limits<double>::epsilon() *
                     static_cast<double>(std::max(a.rows(), n)) *
                     a.cwiseAbs().colwise().sum().maxCoeff() * b.norm();

  const auto solve_passive = [&]() {
    std::vector<Index> cols;
    for (Index j = 0; j < n; ++j)
      if (passive[static_cast<std::size_t>(j)]) cols.push_back(j);
    Eigen::MatrixXd ap(a.rows(), static_cast<Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k) ap.col(static_cast<Index>(k)) = a.col(cols[k]);
    const Eigen::VectorXd sp = ap.colPivHouseholderQr().solve(b);
    Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < cols.size(); ++k) s(cols[k]) = sp(static_cast<Index>(k));
    return s;
  };

  // An unknown whose unconstrained value comes out <= 0 the moment it is
  // freed is not retried until the free set changes otherwise: round-off in
  // its gradient would cycle forever.
  std::vector<bool> blocked(static_cast<std::size_t>(n), false);
  const int max_outer = 10 * static_cast<int>(n) + 10;
  for (int outer = 0; outer < max_outer; ++outer) {
    const Eigen::VectorXd w = a.transpose() * (b - a * x);
    Index t = -1;
    double w_max = tol;
    for (Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      if (!passive[uj] && !blocked[uj] && w(j) > w_max) { w_max = w(j); t = j; }
    }
    if (t < 0) break;
    passive[static_cast<std::size_t>(t)] = true;

    Eigen::VectorXd s = solve_passive();
    bool changed_other = false;
    for (int inner = 0; inner < 10 * static_cast<int>(n) + 10; ++inner) {
      Index worst = -1;
      double alpha = 1.0;
      for (Index j = 0; j < n; ++j) {
        if (!passive[static_cast<std::size_t>(j)] || s(j) > 0.0) continue;
        const double den = x(j) - s(j);
        const double aj = den > 0.0 ? x(j) / den : 0.0;
        if (worst < 0 || aj < alpha) { alpha = aj; worst = j; }
      }
      if (worst < 0) break;
      x += alpha * (s - x);
      x(worst) = 0.0;
      for (Index j = 0; j < n; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        if (passive[uj] && x(j) <= 0.0) {
          passive[uj] = false;
          x(j) = 0.0;
          if (j != t) changed_other = true;
        }
      }
      s = solve_passive();
    }
    const bool t_kept = passive[static_cast<std::size_t>(t)];
    if (t_kept || changed_other) std::fill(blocked.begin(), blocked.end(), false);
    if (!t_kept) blocked[static_cast<std::size_t>(t)] = true;
    x = s;
  }
  return x;
}

// ---------------------------------------------------------------------------
// Fit helpers

constexpr int kPowers = 5;  // tau^-2 .. tau^2

double geometric_mean(const std::vector<double>& v, double power) {
  double s = 0.0;
  for (const double x : v) s += power * std::log(x);
  return std::exp(s / static_cast<double>(v.size()));
}

// Equivalent degrees of freedom for a point's weight, or nullopt when the
// curve says nothing about its uncertainty.
std::optional<double> weight_edf(const AllanCurve& c, std::size_t i) {
  if (c.edf[i] > 0.0) return c.edf[i];
  // Chi-squared interval half-width ~ dev / sqrt(2 edf).
  if (c.hi[i] > c.lo[i] && c.lo[i] > 0.0) {
    const double rel = (c.hi[i] - c.lo[i]) / (2.0 * c.dev[i]);
    return 1.0 / (2.0 * rel * rel);
  }
  return std::nullopt;
}

// The term's value and 1-sigma from C_k and its sigma: each term is
// value = sqrt(C_k / g) for the IEEE 952 shape factor g, so by the delta
// method sigma_value = sigma_C / (2 g value).
struct TermShape {
  double g;  // C_k = g * value^2
};
constexpr std::array<TermShape, kPowers> kShapes = {{
    {3.0},                                 // Q: 3 Q^2 / tau^2
    {1.0},                                 // N: N^2 / tau
    {kFlickerFloor * kFlickerFloor},       // B: (0.664 B)^2
    {1.0 / 3.0},                           // K: K^2 tau / 3
    {0.5},                                 // R: R^2 tau^2 / 2
}};

// Share of a term in the fitted variance at which it "dominates" a tau.
constexpr double kDominantShare = 0.25;

}  // namespace

// ---------------------------------------------------------------------------

SlopeReadOffs read_off_noise_terms(const AllanCurve& curve) {
  SlopeReadOffs out;
  const std::size_t n = curve.size();
  if (n == 0) return out;

  const auto slope = local_slopes(curve);
  out.Q = read_line(curve, slope, {-1.0, std::sqrt(3.0), true});
  out.N = read_line(curve, slope, {-0.5, 1.0, true});
  out.K = read_line(curve, slope, {+0.5, 3.0, false});
  out.R = read_line(curve, slope, {+1.0, std::sqrt(2.0), false});

  // Bias instability: the lowest point of the curve, B = sigma_min / 0.664.
  const auto it = std::min_element(curve.dev.begin(), curve.dev.end());
  const auto imin = static_cast<std::size_t>(it - curve.dev.begin());
  out.sigma_min = curve.dev[imin];
  out.tau_min = curve.tau[imin];
  // The flat bottom: the contiguous points around the minimum whose interval
  // reaches down to sigma_min (their upper bound is above it by definition).
  // Without intervals a point's interval is the point itself.
  const auto reaches = [&](std::size_t i) {
    const double lo = curve.hi[i] > curve.lo[i] ? curve.lo[i] : curve.dev[i];
    return lo <= out.sigma_min;
  };
  std::size_t lo_i = imin;
  while (lo_i > 0 && reaches(lo_i - 1)) --lo_i;
  std::size_t hi_i = imin;
  while (hi_i + 1 < n && reaches(hi_i + 1)) ++hi_i;
  out.tau_min_lo = curve.tau[lo_i];
  out.tau_min_hi = curve.tau[hi_i];

  out.B.value = out.sigma_min / kFlickerFloor;
  out.B.sigma = out.B.value * relative_sigma(curve, imin);
  out.B.tau_lo = out.tau_min_lo;
  out.B.tau_hi = out.tau_min_hi;
  // A minimum at either end of the curve is no minimum: the curve is still
  // falling (bias instability not reached) or rises from the start.
  out.B.valid = imin > 0 && imin + 1 < n;
  return out;
}

NoiseFit fit_noise_terms(const AllanCurve& curve) {
  NoiseFit fit;
  const std::size_t n = curve.size();
  if (n == 0) return fit;

  // Work in normalized units so that the system is well scaled for any data
  // unit (clock data reach 1e-30 in variance) and any tau span (1e-2 ..
  // 1e5 s makes tau^2 span 14 decades): variance over v_ref, tau over
  // tau_ref, then every weighted column scaled to unit norm.
  const double tau_ref = geometric_mean(curve.tau, 1.0);
  const double v_ref = geometric_mean(curve.dev, 2.0);

  std::vector<double> edf(n);
  bool absolute_weights = true;
  for (std::size_t i = 0; i < n; ++i) {
    const auto e = weight_edf(curve, i);
    // Unknown uncertainty: weight 1/dev^4 (relative residuals, edf 2) and
    // let the scatter of the residuals set the scale of the covariance.
    edf[i] = e.value_or(2.0);
    if (!e) absolute_weights = false;
  }

  const auto rows = static_cast<Index>(n);
  Eigen::MatrixXd powers(rows, kPowers);  // (tau / tau_ref)^k
  Eigen::VectorXd y(rows);                // dev^2 / v_ref
  for (Index i = 0; i < rows; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const double t = curve.tau[ui] / tau_ref;
    for (int k = 0; k < kPowers; ++k) powers(i, k) = std::pow(t, k - 2);
    const double d = curve.dev[ui] / std::sqrt(v_ref);
    y(i) = d * d;
  }

  // Var(AVAR estimate) = 2 sigma^4 / edf. The sigma^4 is taken first from
  // the measured point, then from the fitted model: weighting by the
  // measurement favours points that came out low and biases the fit down
  // where edf is small (the long-tau end, where K and R live).
  Eigen::VectorXd d = Eigen::VectorXd::Zero(kPowers);
  Eigen::VectorXd scale(kPowers);
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  std::vector<bool> free_set;
  Eigen::VectorXd model = y;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::VectorXd r(rows);  // sqrt(weight) in normalized units
    for (Index i = 0; i < rows; ++i) {
      const double v = model(i) > 0.0 ? model(i) : y(i);
      r(i) = std::sqrt(edf[static_cast<std::size_t>(i)] / 2.0) / v;
    }
    a = r.asDiagonal() * powers;
    for (int k = 0; k < kPowers; ++k) {
      scale(k) = a.col(k).norm();
      a.col(k) /= scale(k);
    }
    b = r.cwiseProduct(y);
    d = nnls(a, b, free_set);
    model = powers * d.cwiseQuotient(scale);
  }

  // C_k in data units: model/v_ref = sum (tau/tau_ref)^k d_k / scale_k.
  std::array<double, kPowers> to_c{};
  for (int k = 0; k < kPowers; ++k)
    to_c[static_cast<std::size_t>(k)] = v_ref / (scale(k) * std::pow(tau_ref, k - 2));

  const Eigen::VectorXd resid = b - a * d;
  fit.chi2 = resid.squaredNorm();
  std::vector<Index> cols;
  for (Index k = 0; k < kPowers; ++k)
    if (free_set[static_cast<std::size_t>(k)]) cols.push_back(k);
  const std::size_t p = cols.size();
  fit.dof = n > p ? n - p : 0;

  // Covariance of the free coefficients: (A_P^T W A_P)^-1, through the R of
  // a QR so as not to square the condition number. Neighbouring overlapping
  // points are correlated and the five-term model is only approximate, so
  // the covariance is inflated by the reduced chi-squared when that is > 1
  // (or always scaled by it when the curve gave no weights).
  std::vector<double> d_sigma(kPowers, 0.0);
  if (p > 0 && n >= p) {
    Eigen::MatrixXd ap(rows, static_cast<Index>(p));
    for (std::size_t j = 0; j < p; ++j) ap.col(static_cast<Index>(j)) = a.col(cols[j]);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ap);
    const auto pp = static_cast<Index>(p);
    const Eigen::MatrixXd rr = qr.matrixQR().topLeftCorner(pp, pp).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd rinv =
        rr.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(pp, pp));
    const Eigen::MatrixXd cov = rinv * rinv.transpose();
    double factor = 1.0;
    if (fit.dof > 0) {
      const double reduced = fit.chi2 / static_cast<double>(fit.dof);
      factor = absolute_weights ? std::max(1.0, reduced) : reduced;
    }
    for (std::size_t j = 0; j < p; ++j)
      d_sigma[static_cast<std::size_t>(cols[j])] =
          std::sqrt(std::max(0.0, cov(static_cast<Index>(j), static_cast<Index>(j))) * factor);
  }

  std::array<TermEstimate*, kPowers> terms = {&fit.Q, &fit.N, &fit.B, &fit.K, &fit.R};
  for (std::size_t k = 0; k < kPowers; ++k) {
    const auto kk = static_cast<Index>(k);
    fit.c[k] = free_set[k] ? std::max(0.0, d(kk)) * to_c[k] : 0.0;
    fit.c_sigma[k] = d_sigma[k] * to_c[k];
    TermEstimate& e = *terms[k];
    e.valid = free_set[k] && fit.c[k] > 0.0;
    if (!e.valid) continue;
    const double g = kShapes[k].g;
    e.value = std::sqrt(fit.c[k] / g);
    e.sigma = fit.c_sigma[k] / (2.0 * g * e.value);

    // Where the term carries at least a quarter of the fitted variance; a
    // term that never does is reported at the tau of its largest share.
    double best_share = -1.0;
    std::size_t best = 0;
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
      const auto ii = static_cast<Index>(i);
      if (!(model(ii) > 0.0)) continue;
      const double share = powers(ii, kk) * d(kk) / scale(kk) / model(ii);
      if (share > best_share) { best_share = share; best = i; }
      if (share >= kDominantShare) {
        if (!any) e.tau_lo = curve.tau[i];
        e.tau_hi = curve.tau[i];
        any = true;
      }
    }
    if (!any) e.tau_lo = e.tau_hi = curve.tau[best];
  }

  double ss = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double rel = noise_model_adev(fit.c, curve.tau[i]) / curve.dev[i] - 1.0;
    ss += rel * rel;
  }
  fit.rms_rel_residual = std::sqrt(ss / static_cast<double>(n));
  return fit;
}

double noise_model_adev(const std::array<double, 5>& c, double tau) noexcept {
  if (!(tau > 0.0)) return 0.0;
  double v = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) v += c[k] * std::pow(tau, static_cast<int>(k) - 2);
  return v > 0.0 ? std::sqrt(v) : 0.0;
}

}  // namespace cubecal
