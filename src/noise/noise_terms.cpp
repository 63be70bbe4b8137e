// IEEE Std 952 noise terms from an Allan-deviation curve: slope read-offs
// (what the paper and most lab notebooks do) and a weighted non-negative
// least-squares fit of the five-term variance model.
#include "cubecal/noise/noise_terms.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
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
// point. A white-noise arm stays "white" until its neighbour carries 15 %
// (rate random walk) to 30 % (flicker floor) of the variance.
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
  const double ratio = std::pow(10.0, kHalfBaselineDecades);
  // j: the last point at least `ratio` below tau_i (else the first point);
  // k: the first point at least `ratio` above it (else the last). Both only
  // move forward as i does.
  std::size_t j = 0, k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (j + 1 < i && c.tau[j + 1] * ratio <= c.tau[i]) ++j;
    k = std::max(k, std::min(i + 1, n - 1));
    while (k + 1 < n && c.tau[k] < c.tau[i] * ratio) ++k;
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

// Equivalent degrees of freedom of each point, from the curve's EDF or, when
// that is missing, from its interval (half-width ~ dev / sqrt(2 edf)).
// nullopt when the curve carries no uncertainty at all (any point lacking
// both counts: then the curve is treated as carrying none).
//
// The EDF is made non-increasing in tau: an estimate over longer averages
// of the same record cannot have more degrees of freedom. This guards
// against noise identification on a handful of averages (the B1 ratio
// below 30 points) calling the end of a random-walk curve white PM, whose
// EDF (~ half the record) would make three noisy points outweigh the rest.
std::optional<std::vector<double>> point_edfs(const AllanCurve& c) {
  std::vector<double> edf(c.size());
  double running = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < c.size(); ++i) {
    double e = c.edf[i];
    if (!(e > 0.0)) {
      if (!(c.hi[i] > c.lo[i] && c.lo[i] > 0.0)) return std::nullopt;
      const double rel = (c.hi[i] - c.lo[i]) / (2.0 * c.dev[i]);
      e = 1.0 / (2.0 * rel * rel);
    }
    running = std::min(running, e);
    edf[i] = running;
  }
  return edf;
}

// 1-sigma relative uncertainty of each point's deviation for the read-offs:
// the relative half-width of its confidence interval (1/sqrt(2 edf) without
// one), made non-decreasing in tau for the reason above. Zero when the
// curve carries no uncertainty.
std::vector<double> relative_sigmas(const AllanCurve& c) {
  std::vector<double> rel(c.size(), 0.0);
  double running = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    double r = 0.0;
    if (c.hi[i] > c.lo[i] && c.lo[i] > 0.0) r = (c.hi[i] - c.lo[i]) / (2.0 * c.dev[i]);
    else if (c.edf[i] > 0.0) r = 1.0 / std::sqrt(2.0 * c.edf[i]);
    running = std::max(running, r);
    rel[i] = running;
  }
  return rel;
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
TermEstimate read_line(const AllanCurve& c, const std::vector<double>& slope,
                       const std::vector<double>& rel_sigma, LineTerm term) {
  TermEstimate e;
  const auto runs = regions_of_slope(c, slope, term.slope);
  if (runs.empty()) return e;
  const Run r = term.at_short_taus ? runs.front() : runs.back();
  std::size_t best = r.first;
  double best_value = std::numeric_limits<double>::infinity();
  for (const std::size_t i : well_measured(c, r.first, r.last)) {
    const double v = c.dev[i] * std::pow(term.tau_read / c.tau[i], term.slope);
    if (v < best_value) { best_value = v; best = i; }
  }
  e.valid = true;
  e.value = best_value;
  e.sigma = best_value * rel_sigma[best];
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
// Correlation between the variance estimates at different taus.
//
// Overlapping estimates at neighbouring taus share most of their data:
// on a random-walk arm the residuals of a fit are smooth, chi-squared comes
// out well below its degrees of freedom, and covariances that treat the
// points as independent are several times too small. The long-record
// (spectral) approximation of the covariance of two Allan-variance
// estimates is
//   cov(s2_i, s2_j) ~ (1/T) int S_y(f)^2 g(f tau_i) g(f tau_j) df,
//   g(f tau) = 2 sin^4(pi f tau) / (pi f tau)^2 (the Allan filter),
// so their correlation follows from the noise spectrum alone; the variance
// of each point is kept from its EDF.

// One-sided PSD of y, S_y(f) = h2 f^2 + h0 + h_-1 / f + h_-2 / f^2, with the
// Allan variance of the stochastic terms of the fit (SP 1065 Table 2):
// white PM 3 f_h h2 / (4 pi^2 tau^2), white FM h0 / (2 tau), flicker FM
// 2 ln2 h_-1, random-walk FM (2 pi^2 / 3) h_-2 tau. The rate ramp is a
// deterministic drift with no spectrum; it enters through the EDFs only.
struct PowerLawPsd {
  double h2 = 0.0, h0 = 0.0, hm1 = 0.0, hm2 = 0.0;
  double operator()(double f) const noexcept { return h2 * f * f + h0 + hm1 / f + hm2 / (f * f); }
};

PowerLawPsd psd_of(const std::array<double, 5>& c, double f_high) {
  constexpr double pi2 = std::numbers::pi * std::numbers::pi;
  PowerLawPsd s;
  s.h2 = 4.0 * pi2 * c[0] / (3.0 * f_high);
  s.h0 = 2.0 * c[1];
  s.hm1 = c[2] / (2.0 * std::numbers::ln2);
  s.hm2 = 3.0 * c[3] / (2.0 * pi2);
  return s;
}

// Frequency grid of the correlation integrals: from three decades below
// 1/tau_max (where every Allan filter has died out) to the Nyquist frequency
// of the shortest tau, in steps of 1 % in f. Beyond x = pi f tau = 4 pi the
// filter's sin^4 is replaced by its mean 3/8 (and sin^8 by 35/128 on the
// diagonal): the oscillation is then faster than the grid and averages out.
constexpr double kLnStep = 0.01;
constexpr double kEnvelopeFrom = 4.0 * std::numbers::pi;

// Allan filter g(x) and the mean of its square, x = pi f tau.
struct FilterValue {
  double g;
  double g2;
};
FilterValue allan_filter(double x) noexcept {
  if (x < kEnvelopeFrom) {
    const double s2 = std::sin(x) * std::sin(x);
    const double g = 2.0 * s2 * s2 / (x * x);
    return {g, g * g};
  }
  const double x2 = x * x;
  return {0.75 / x2, 4.0 * (35.0 / 128.0) / (x2 * x2)};
}

// Q^T rho Q for the thin Q (n x p) of the whitened design, where rho is
// the correlation matrix of the whitened residuals (unit variances). rho is
// never formed: with r_i(f) = g_i(f) / sqrt(int S^2 g_i^2), rho = int S^2
// r r^T df + diag(e), where e_i >= 0 is the part of each point's variance
// the envelope leaves uncorrelated (all of it when the PSD is zero there).
Eigen::MatrixXd projected_correlation(const std::vector<double>& tau, const Eigen::MatrixXd& q,
                                      const PowerLawPsd& psd) {
  const std::size_t n = tau.size();
  const Index p = q.cols();
  const double f_lo = 1e-3 / tau.back();
  const double f_hi = 0.5 / tau.front();
  const auto steps = static_cast<std::size_t>(std::ceil(std::log(f_hi / f_lo) / kLnStep));
  std::vector<double> f(steps + 1), weight(steps + 1);
  for (std::size_t k = 0; k <= steps; ++k) {
    f[k] = f_lo * std::exp(static_cast<double>(k) * kLnStep);
    const double s = psd(f[k]);
    // int ... df = int ... f dln f, trapezoid ends.
    weight[k] = s * s * f[k] * kLnStep * (k == 0 || k == steps ? 0.5 : 1.0);
  }

  std::vector<double> self(n, 0.0), cross(n, 0.0);  // int S^2 <g^2>, int S^2 g^2
  for (std::size_t k = 0; k <= steps; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const FilterValue g = allan_filter(std::numbers::pi * f[k] * tau[i]);
      self[i] += weight[k] * g.g2;
      cross[i] += weight[k] * g.g * g.g;
    }
  }
  std::vector<double> norm(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (self[i] > 0.0 && std::isfinite(self[i])) norm[i] = 1.0 / std::sqrt(self[i]);

  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd u(p);
  for (std::size_t k = 0; k <= steps; ++k) {
    u.setZero();
    for (std::size_t i = 0; i < n; ++i) {
      if (norm[i] == 0.0) continue;
      const double r = allan_filter(std::numbers::pi * f[k] * tau[i]).g * norm[i];
      u += r * q.row(static_cast<Index>(i)).transpose();
    }
    m.noalias() += weight[k] * u * u.transpose();
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double e = norm[i] > 0.0 ? std::max(0.0, 1.0 - cross[i] / self[i]) : 1.0;
    const auto row = q.row(static_cast<Index>(i));
    m.noalias() += e * row.transpose() * row;
  }
  return m;
}

// ---------------------------------------------------------------------------
// Fit helpers

constexpr int kPowers = 5;  // tau^-2 .. tau^2

double geometric_mean(const std::vector<double>& v, double power) {
  double s = 0.0;
  for (const double x : v) s += power * std::log(x);
  return std::exp(s / static_cast<double>(v.size()));
}

// Each term is value = sqrt(C_k / g) for its IEEE 952 shape factor g, so by
// the delta method sigma_value = sigma_C / (2 g value).
constexpr std::array<double, kPowers> kShape = {
    3.0,                            // Q: 3 Q^2 / tau^2
    1.0,                            // N: N^2 / tau
    kFlickerFloor * kFlickerFloor,  // B: (0.664 B)^2
    1.0 / 3.0,                      // K: K^2 tau / 3
    0.5,                            // R: R^2 tau^2 / 2
};

// Reweighting stops when no point of the model moves by more than this
// (relative): 10-20 passes on measured curves, more (linear convergence)
// when the scatter is far beyond what the EDFs allow.
constexpr int kMaxReweightings = 50;
constexpr double kReweightTolerance = 1e-10;

// Share of the fitted variance from which a term "dominates" a tau.
constexpr double kDominantShare = 0.25;

}  // namespace

// ---------------------------------------------------------------------------

SlopeReadOffs read_off_noise_terms(const AllanCurve& curve) {
  SlopeReadOffs out;
  const std::size_t n = curve.size();
  if (n == 0) return out;

  const auto slope = local_slopes(curve);
  const auto rel = relative_sigmas(curve);
  out.Q = read_line(curve, slope, rel, {-1.0, std::sqrt(3.0), true});
  out.N = read_line(curve, slope, rel, {-0.5, 1.0, true});
  out.K = read_line(curve, slope, rel, {+0.5, 3.0, false});
  out.R = read_line(curve, slope, rel, {+1.0, std::sqrt(2.0), false});

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

  // Quoted with the interval of that point, as the paper reads it. (The
  // lowest of several scattered points sits a little below the curve they
  // sample.)
  out.B.value = out.sigma_min / kFlickerFloor;
  out.B.sigma = out.B.value * rel[imin];
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

  // Without any uncertainty on the curve: weights 1/dev^4 (edf 2, i.e.
  // relative residuals) and the scatter of the residuals sets the scale.
  const auto known_edf = point_edfs(curve);
  const bool absolute_weights = known_edf.has_value();
  const std::vector<double> edf = known_edf.value_or(std::vector<double>(n, 2.0));

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
  // the measured points, then from the fitted model until the fit stops
  // changing: weighting by the measurement favours points that came out low
  // and biases the fit down where edf is small (the long-tau end, where K
  // and R live). At the fixed point the weights are those of the returned
  // model, so the result satisfies the NNLS optimality conditions for them.
  Eigen::VectorXd d = Eigen::VectorXd::Zero(kPowers);
  Eigen::VectorXd scale(kPowers);
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  std::vector<bool> free_set;
  Eigen::VectorXd model = y;
  for (int pass = 0; pass < kMaxReweightings; ++pass) {
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
    const Eigen::VectorXd next = powers * d.cwiseQuotient(scale);
    double change = 0.0;
    for (Index i = 0; i < rows; ++i)
      if (next(i) > 0.0) change = std::max(change, std::abs(next(i) / model(i) - 1.0));
    model = next;
    if (pass > 0 && change < kReweightTolerance) break;
  }

  // C_k in data units: model / v_ref = sum (tau / tau_ref)^k d_k / scale_k.
  std::array<double, kPowers> to_c{};
  for (int k = 0; k < kPowers; ++k)
    to_c[static_cast<std::size_t>(k)] = v_ref / (scale(k) * std::pow(tau_ref, k - 2));
  for (std::size_t k = 0; k < kPowers; ++k)
    fit.c[k] = free_set[k] ? std::max(0.0, d(static_cast<Index>(k))) * to_c[k] : 0.0;

  fit.chi2 = (b - a * d).squaredNorm();
  std::vector<Index> cols;
  for (Index k = 0; k < kPowers; ++k)
    if (free_set[static_cast<std::size_t>(k)]) cols.push_back(k);
  const std::size_t p = cols.size();
  fit.dof = n > p ? n - p : 0;

  // Covariance of the free coefficients, sandwich form for correlated
  // points: with the whitened design A_P = Q R, cov = R^-1 (Q^T rho Q) R^-T,
  // which is (A_P^T W A_P)^-1 when the points are independent (rho = I).
  // The model is only approximate, so the covariance is inflated by
  // chi2 / E[chi2] when that is > 1, with E[chi2] = tr((I - Q Q^T) rho)
  // = n - tr(Q^T rho Q) (= dof for independent points); without weights on
  // the curve it is always scaled by that ratio.
  std::array<double, kPowers> d_sigma{};
  if (p > 0 && n >= p) {
    const auto pp = static_cast<Index>(p);
    Eigen::MatrixXd ap(rows, pp);
    for (Index j = 0; j < pp; ++j) ap.col(j) = a.col(cols[static_cast<std::size_t>(j)]);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ap);
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(rows, pp);
    const Eigen::MatrixXd rinv = qr.matrixQR()
                                     .topLeftCorner(pp, pp)
                                     .triangularView<Eigen::Upper>()
                                     .solve(Eigen::MatrixXd::Identity(pp, pp));
    // Only the shape of the spectrum matters: in units of v_ref, S^2 stays
    // representable for any data unit.
    std::array<double, kPowers> c_rel{};
    for (std::size_t k = 0; k < kPowers; ++k) c_rel[k] = fit.c[k] / v_ref;
    const Eigen::MatrixXd rho_q =
        projected_correlation(curve.tau, q, psd_of(c_rel, 0.5 / curve.tau.front()));
    const Eigen::MatrixXd cov = rinv * rho_q * rinv.transpose();
    const double expected_chi2 = static_cast<double>(n) - rho_q.trace();
    double factor = 1.0;
    if (expected_chi2 > 0.0 && fit.dof > 0) {
      const double ratio = fit.chi2 / expected_chi2;
      factor = absolute_weights ? std::max(1.0, ratio) : ratio;
    }
    for (Index j = 0; j < pp; ++j)
      d_sigma[static_cast<std::size_t>(cols[static_cast<std::size_t>(j)])] =
          std::sqrt(std::max(0.0, cov(j, j)) * factor);
  }

  std::array<TermEstimate*, kPowers> terms = {&fit.Q, &fit.N, &fit.B, &fit.K, &fit.R};
  for (std::size_t k = 0; k < kPowers; ++k) {
    const auto kk = static_cast<Index>(k);
    fit.c_sigma[k] = d_sigma[k] * to_c[k];
    TermEstimate& e = *terms[k];
    e.valid = fit.c[k] > 0.0;
    if (!e.valid) continue;
    e.value = std::sqrt(fit.c[k] / kShape[k]);
    e.sigma = fit.c_sigma[k] / (2.0 * kShape[k] * e.value);

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
