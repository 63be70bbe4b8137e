#include "cubecal/noise/reported_terms.hpp"

#include <Eigen/Core>

#include "cubecal/noise/minimum_spread.hpp"
#include "cubecal/noise/record_plan.hpp"
#include "detail/avar_correlation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cubecal {

namespace {

// min over the curve of dev(tau) * f(tau): the largest term value the curve
// allows when the term's own AVAR arm is f^-2 (the other arms are >= 0).
// tau_lo = tau_hi = the tau that sets it.
template <class F>
TermEstimate bound_over_curve(const AllanCurve& c, F f) {
  TermEstimate e;
  double b = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!(c.tau[i] > 0.0) || !std::isfinite(c.dev[i])) continue;
    const double v = c.dev[i] * f(c.tau[i]);
    if (v < b) {
      b = v;
      e.tau_lo = e.tau_hi = c.tau[i];
    }
  }
  e.valid = std::isfinite(b);
  e.value = e.valid ? b : 0.0;
  return e;
}

ReportedTerm estimate(const TermEstimate& t, TermSource s) { return {s, t}; }
ReportedTerm bound(const TermEstimate& t) { return {TermSource::upper_bound, t}; }

}  // namespace

std::string_view to_string(TermSource s) noexcept {
  switch (s) {
    case TermSource::fit: return "fit";
    case TermSource::read_off: return "read-off";
    case TermSource::upper_bound: return "UPPER BOUND";
  }
  return "fit";
}

bool significant(const TermEstimate& t) noexcept {
  return t.valid && std::isfinite(t.value) && std::isfinite(t.sigma) && t.value > kSignificanceSigmas * t.sigma;
}

namespace {

// N read as the weighted mean of sigma(tau) sqrt(tau) over the points near
// 1 s (slope_read_offs.cpp): its 1-sigma is that of a weighted mean of
// correlated estimates, sqrt(w' Sigma w) / sum w with Sigma_ij = r_i r_j
// rho_ij, rho the long-record correlation of the estimates under the
// spectrum `fit` finds (avar_correlation.hpp). The read-off's own sigma
// takes the points as fully correlated, which overstates it by about 15 %
// (docs/formulas/planning.md §1). A tangent read-off (no point near 1 s)
// keeps its one point's sigma.
double windowed_white_sigma(const AllanCurve& c, const NoiseFit& fit, const TermEstimate& n) {
  constexpr double eps = 1e-9;
  if (!(n.tau_lo >= 0.5 - eps && n.tau_hi <= 2.0 + eps && n.tau_lo <= 1.0 + eps && n.tau_hi >= 1.0 - eps))
    return n.sigma;
  const std::vector<double> rel = running_relative_uncertainty(c);
  std::vector<double> tau, r;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c.tau[i] >= n.tau_lo * (1 - eps) && c.tau[i] <= n.tau_hi * (1 + eps) && rel[i] > 0.0)
      tau.push_back(c.tau[i]), r.push_back(rel[i]);
  const double v0 = n.value * n.value;  // the spectrum's shape in units of N^2 (per s)
  std::array<double, 5> shape{};
  for (std::size_t k = 0; k < 5; ++k) shape[k] = fit.c[k] / v0;
  if (tau.size() < 2 || std::none_of(shape.begin(), shape.end(), [](double x) { return x > 0.0; })) return n.sigma;
  const auto k = static_cast<Eigen::Index>(tau.size());
  const double tau0 =
      c.m.empty() || c.m.front() == 0 ? c.tau.front() : c.tau.front() / static_cast<double>(c.m.front());
  Eigen::MatrixXd rho = noise::detail::projected_correlation(tau, Eigen::MatrixXd::Identity(k, k),
                                                             noise::detail::psd_of(shape, 0.5 / tau0));
  double sw = 0.0, var = 0.0;
  for (Eigen::Index i = 0; i < k; ++i) {
    rho(i, i) = 1.0;
    sw += 1.0 / (r[static_cast<std::size_t>(i)] * r[static_cast<std::size_t>(i)]);
  }
  for (Eigen::Index i = 0; i < k; ++i)
    for (Eigen::Index j = 0; j < k; ++j)
      var += rho(i, j) / (r[static_cast<std::size_t>(i)] * r[static_cast<std::size_t>(j)]);
  return n.value * std::sqrt(var) / sw;
}

}  // namespace

ReportedTerms reported_terms(const SlopeReadOffs& ro, const NoiseFit& fit, const AllanCurve& curve) {
  ReportedTerms r;
  r.constant = std::none_of(curve.dev.begin(), curve.dev.end(), [](double d) { return d > 0.0; });
  if (r.constant) {
    r.N.estimate = r.K.estimate = r.B.estimate = TermEstimate{};
    return r;
  }

  r.N = ro.N.valid ? estimate(ro.N, TermSource::read_off)
                   : bound(bound_over_curve(curve, [](double tau) { return std::sqrt(tau); }));

  r.K_candidate_source = fit.K.valid ? TermSource::fit : TermSource::read_off;
  r.K_candidate = fit.K.valid ? fit.K : ro.K;
  if (significant(fit.K)) {
    r.K = estimate(fit.K, TermSource::fit);
    // K's uncertainty over records (the plan's, record_plan.hpp): the sandwich sigma of this fit is that of the
    // coefficients it freed, which on a measured curve include those its noise pushed above zero.
    // The model the data support: N and K, and Q, the flicker floor and R where the fit measures them (C_k above
    // twice its sigma); a coefficient whose true value is zero comes out positive in half the records.
    std::array<double, 5> supported = fit.c;
    for (const std::size_t k : {0u, 2u, 4u})
      if (!(fit.c[k] > 2.0 * fit.c_sigma[k])) supported[k] = 0.0;
    const double rel = planned_random_walk_sigma(curve, supported);
    if (std::isfinite(rel) && rel > 0.0) r.K.estimate.sigma = rel * r.K.value();
  } else if (significant(ro.K))
    r.K = estimate(ro.K, TermSource::read_off);
  else
    r.K = bound(bound_over_curve(curve, [](double tau) { return std::sqrt(3.0 / tau); }));

  if (r.N.source == TermSource::read_off) r.N.estimate.sigma = windowed_white_sigma(curve, fit, ro.N);

  r.no_minimum = !ro.B.valid;
  if (!r.no_minimum) {
    r.B = estimate(ro.B, TermSource::read_off);
    r.T = ro.tau_min;
    // The spread of the minimum over records, at the curve's confidence.
    const MinimumSpread s = minimum_spread(curve, fit);
    const auto imin =
        static_cast<std::size_t>(std::min_element(curve.dev.begin(), curve.dev.end()) - curve.dev.begin());
    if (s.valid && curve.edf[imin] > 0.0) {
      const double at_ci = relative_uncertainty(curve, imin) * std::sqrt(2.0 * curve.edf[imin]);
      // The intervals at the curve's confidence, ci = 2 Phi(at_ci) - 1.
      const double ci = std::erf(at_ci / std::sqrt(2.0));
      r.B.estimate.sigma = r.B.value() * s.b_half_width(ci);
      r.T_rel_sigma = s.t_half_width(ci);
    }
  } else {
    // AVAR >= (0.664 B)^2 at every tau: the lowest point bounds B, at
    // whichever end of the record it lies.
    TermEstimate b;
    b.valid = true;
    b.value = ro.sigma_min / kFlickerFloor;
    b.tau_lo = b.tau_hi = ro.tau_min;
    r.B = bound(b);
  }
  return r;
}

}  // namespace cubecal
