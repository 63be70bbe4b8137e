// The weighted five-term fit of an Allan-deviation curve: non-negative least
// squares of sigma^2(tau) = sum_{k=-2..2} C_k tau^k, reweighted by the model,
// with a covariance that accounts for the correlation between the points.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"
#include "detail/avar_correlation.hpp"
#include "../detail/nnls.hpp"

namespace cubecal {

namespace {

using Eigen::Index;
using noise::detail::nnls;
using noise::detail::projected_correlation;
using noise::detail::psd_of;

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
      if (!(c.interval[i].hi > c.interval[i].lo && c.interval[i].lo > 0.0)) return std::nullopt;
      const double rel = (c.interval[i].hi - c.interval[i].lo) / (2.0 * c.dev[i]);
      e = 1.0 / (2.0 * rel * rel);
    }
    running = std::min(running, e);
    edf[i] = running;
  }
  return edf;
}

constexpr int kPowers = 5;  // tau^-2 .. tau^2

double geometric_mean(const std::vector<double>& v, double power) {
  double s = 0.0;
  for (const double x : v) s += power * std::log(x);
  return std::exp(s / static_cast<double>(v.size()));
}

// Each term is value = sqrt(C_k / g) for its IEEE 952 shape factor g, so by
// the delta method sigma_value = sigma_C / (2 g value).
constexpr std::array<double, kPowers> kShape = {
    3.0,                           // Q: 3 Q^2 / tau^2
    1.0,                           // N: N^2 / tau
    kFlickerFloor* kFlickerFloor,  // B: (0.664 B)^2
    1.0 / 3.0,                     // K: K^2 tau / 3
    0.5,                           // R: R^2 tau^2 / 2
};

// Reweighting stops when no point of the model moves by more than this
// (relative): 10-20 passes on measured curves, more (linear convergence)
// when the scatter is far beyond what the EDFs allow.
constexpr int kMaxReweightings = 50;
constexpr double kReweightTolerance = 1e-10;

// Share of the fitted variance from which a term "dominates" a tau.
constexpr double kDominantShare = 0.25;

// The curve in normalized units, so that the system is well scaled for any
// data unit (clock data reach 1e-30 in variance) and any tau span (1e-2 ..
// 1e5 s makes tau^2 span 14 decades): variance over v_ref, tau over
// tau_ref (every weighted column is then scaled to unit norm).
struct NormalizedCurve {
  double tau_ref = 0.0;
  double v_ref = 0.0;
  Eigen::MatrixXd powers;  // (tau / tau_ref)^k
  Eigen::VectorXd y;       // dev^2 / v_ref
};

NormalizedCurve normalized_curve(const AllanCurve& curve) {
  NormalizedCurve nc;
  nc.tau_ref = geometric_mean(curve.tau, 1.0);
  nc.v_ref = geometric_mean(curve.dev, 2.0);
  const auto rows = static_cast<Index>(curve.size());
  nc.powers.resize(rows, kPowers);
  nc.y.resize(rows);
  for (Index i = 0; i < rows; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const double t = curve.tau[ui] / nc.tau_ref;
    for (int k = 0; k < kPowers; ++k) nc.powers(i, k) = std::pow(t, k - 2);
    const double d = curve.dev[ui] / std::sqrt(nc.v_ref);
    nc.y(i) = d * d;
  }
  return nc;
}

// The reweighted NNLS solution: the whitened, column-scaled system (a, b)
// of the last pass, its solution d over scale, the free set and the model.
struct ReweightedSolution {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(kPowers);
  Eigen::VectorXd scale = Eigen::VectorXd(kPowers);
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  std::vector<bool> free_set;
  Eigen::VectorXd model;
};

// Var(AVAR estimate) = 2 sigma^4 / edf. The sigma^4 is taken first from
// the measured points, then from the fitted model until the fit stops
// changing: weighting by the measurement favours points that came out low
// and biases the fit down where edf is small (the long-tau end, where K
// and R live). At the fixed point the weights are those of the returned
// model, so the result satisfies the NNLS optimality conditions for them.
ReweightedSolution reweighted_nnls(const NormalizedCurve& nc, const std::vector<double>& edf) {
  const Eigen::MatrixXd& powers = nc.powers;
  const Eigen::VectorXd& y = nc.y;
  const Index rows = y.size();
  ReweightedSolution sol;
  Eigen::VectorXd& d = sol.d;
  Eigen::VectorXd& scale = sol.scale;
  Eigen::MatrixXd& a = sol.a;
  Eigen::VectorXd& b = sol.b;
  std::vector<bool>& free_set = sol.free_set;
  Eigen::VectorXd& model = sol.model;
  model = y;
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
  return sol;
}

// Covariance of the free coefficients, sandwich form for correlated
// points: with the whitened design A_P = Q R, cov = R^-1 (Q^T rho Q) R^-T,
// which is (A_P^T W A_P)^-1 when the points are independent (rho = I).
// The model is only approximate, so the covariance is inflated by
// chi2 / E[chi2] when that is > 1, with E[chi2] = tr((I - Q Q^T) rho)
// = n - tr(Q^T rho Q) (= dof for independent points); without weights on
// the curve it is always scaled by that ratio. Returns the sigma of each
// normalized coefficient d_k (0 for a bound one).
std::array<double, kPowers> coefficient_sigmas(const NoiseFit& fit, const AllanCurve& curve, const Eigen::MatrixXd& a,
                                               const std::vector<Index>& cols, double v_ref, bool absolute_weights) {
  const std::size_t n = curve.size();
  const auto rows = static_cast<Index>(n);
  const std::size_t p = cols.size();
  std::array<double, kPowers> d_sigma{};
  if (p > 0 && n >= p) {
    const auto pp = static_cast<Index>(p);
    Eigen::MatrixXd ap(rows, pp);
    for (Index j = 0; j < pp; ++j) ap.col(j) = a.col(cols[static_cast<std::size_t>(j)]);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(ap);
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(rows, pp);
    const Eigen::MatrixXd rinv =
        qr.matrixQR().topLeftCorner(pp, pp).triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(pp, pp));
    // Only the shape of the spectrum matters: in units of v_ref, S^2 stays
    // representable for any data unit.
    std::array<double, kPowers> c_rel{};
    for (std::size_t k = 0; k < kPowers; ++k) c_rel[k] = fit.c[k] / v_ref;
    const Eigen::MatrixXd rho_q = projected_correlation(curve.tau, q, psd_of(c_rel, 0.5 / curve.tau.front()));
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
  return d_sigma;
}

// Each term's value and sigma, and where the term carries at least a
// quarter of the fitted variance; a term that never does is reported at
// the tau of its largest share.
void term_estimates(NoiseFit& fit, const AllanCurve& curve, const NormalizedCurve& nc, const ReweightedSolution& sol,
                    const std::array<double, kPowers>& d_sigma, const std::array<double, kPowers>& to_c) {
  const std::size_t n = curve.size();
  const Eigen::MatrixXd& powers = nc.powers;
  const Eigen::VectorXd& d = sol.d;
  const Eigen::VectorXd& scale = sol.scale;
  const Eigen::VectorXd& model = sol.model;
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
      if (share > best_share) {
        best_share = share;
        best = i;
      }
      if (share >= kDominantShare) {
        if (!any) e.tau_lo = curve.tau[i];
        e.tau_hi = curve.tau[i];
        any = true;
      }
    }
    if (!any) e.tau_lo = e.tau_hi = curve.tau[best];
  }
}

}  // namespace

NoiseFit fit_noise_terms(const AllanCurve& curve) {
  NoiseFit fit;
  const std::size_t n = curve.size();
  if (n == 0) return fit;

  // Work in normalized units so that the system is well scaled for any data
  // unit and any tau span.
  const NormalizedCurve nc = normalized_curve(curve);
  const double tau_ref = nc.tau_ref;
  const double v_ref = nc.v_ref;

  // Without any uncertainty on the curve: weights 1/dev^4 (edf 2, i.e.
  // relative residuals) and the scatter of the residuals sets the scale.
  const auto known_edf = point_edfs(curve);
  const bool absolute_weights = known_edf.has_value();
  const std::vector<double> edf = known_edf.value_or(std::vector<double>(n, 2.0));

  const ReweightedSolution sol = reweighted_nnls(nc, edf);
  const Eigen::VectorXd& d = sol.d;
  const Eigen::VectorXd& scale = sol.scale;
  const std::vector<bool>& free_set = sol.free_set;

  // C_k in data units: model / v_ref = sum (tau / tau_ref)^k d_k / scale_k.
  std::array<double, kPowers> to_c{};
  for (int k = 0; k < kPowers; ++k) to_c[static_cast<std::size_t>(k)] = v_ref / (scale(k) * std::pow(tau_ref, k - 2));
  for (std::size_t k = 0; k < kPowers; ++k)
    fit.c[k] = free_set[k] ? std::max(0.0, d(static_cast<Index>(k))) * to_c[k] : 0.0;

  fit.chi2 = (sol.b - sol.a * d).squaredNorm();
  std::vector<Index> cols;
  for (Index k = 0; k < kPowers; ++k)
    if (free_set[static_cast<std::size_t>(k)]) cols.push_back(k);
  const std::size_t p = cols.size();
  fit.dof = n > p ? n - p : 0;

  const std::array<double, kPowers> d_sigma = coefficient_sigmas(fit, curve, sol.a, cols, v_ref, absolute_weights);
  term_estimates(fit, curve, nc, sol, d_sigma, to_c);

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
