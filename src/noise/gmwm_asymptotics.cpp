// The sandwich covariance of a GMWM fit (noise/gmwm_asymptotics.hpp;
// docs/formulas/noise-terms.md §8d).
#include "cubecal/noise/gmwm_asymptotics.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <string>

#include "cubecal/error.hpp"
#include "detail/wavelet_variance_covariance.hpp"
#include "../detail/eigen_matrix.hpp"

namespace cubecal {

namespace {

using Eigen::MatrixXd;

// d nu2 / d ln a of a Gauss-Markov term: central differences in ln a,
// Richardson-extrapolated (error O(h^4), h = 1e-3: ~1e-11 relative).
double d_log_a(double a, double sigma2, double tau) {
  const auto diff = [&](double h) {
    return (gauss_markov_wavelet_variance(a * std::exp(h), sigma2, tau) -
            gauss_markov_wavelet_variance(a * std::exp(-h), sigma2, tau)) /
           (2.0 * h);
  };
  const double h = 1e-3;
  return (4.0 * diff(0.5 * h) - diff(h)) / 3.0;
}

}  // namespace

GmwmAsymptotics gmwm_asymptotics(const GmwmFit& fit, const WaveletVariance& wv, std::size_t samples, double inflation,
                                 bool pseudo_inverse) {
  const std::size_t J = wv.size();
  if (!(inflation >= 1.0) || !std::isfinite(inflation))
    throw UsageError(Field::model, "the wavelet variance's variance can only be inflated (a factor >= 1), not " +
                                       std::to_string(inflation));
  if (fit.sd.size() != J || fit.nu2_model.size() != J || fit.model.processes.empty())
    throw UsageError(Field::model, "the GMWM fit has " + std::to_string(fit.sd.size()) +
                                       " scales, the wavelet variance " + std::to_string(J) +
                                       ": they do not belong together");
  const std::size_t p = parameter_count(fit.model);

  // A: every parameter but ln a and an MA1's z = atanh(theta) enters
  // linearly, so its column is the term's own wavelet variance; an MA1's
  // d nu2 / dz = sigma2 (2 (1 + theta) tau - 6) / tau^2 (1 - theta^2).
  MatrixXd A(static_cast<Eigen::Index>(J), static_cast<Eigen::Index>(p));
  for (std::size_t j = 0; j < J; ++j) {
    Eigen::Index k = 0;
    const auto row = static_cast<Eigen::Index>(j);
    for (const Process& pr : fit.model.processes) {
      A(row, k++) = haar_wavelet_variance(pr, wv.tau[j]);
      if (pr.kind == ProcessKind::gm) A(row, k++) = d_log_a(-std::log(pr.phi), pr.value, wv.tau[j]);
      if (pr.kind == ProcessKind::ma1) {
        const double tau = wv.tau[j];
        A(row, k++) = pr.value * (2.0 * (1.0 + pr.theta) * tau - 6.0) / (tau * tau) * (1.0 - pr.theta * pr.theta);
      }
      if (pr.kind == ProcessKind::sin) {
        // nu2 = 2 A^2 s^4 / (tau^2 S^2), s = sin(omega tau / 4), S = sin(omega / 2):
        // d nu2 / d omega = 2 A^2 (tau s^3 c / S^2 - s^4 C / S^3) / tau^2, and
        // omega = pi / (1 + e^-z): d omega / dz = omega (1 - omega / pi).
        const double tau = wv.tau[j], w = pr.omega;
        const double s = std::sin(w * tau / 4.0), c = std::cos(w * tau / 4.0);
        const double S = std::sin(w / 2.0), C = std::cos(w / 2.0);
        const double d =
            2.0 * pr.value * (tau * s * s * s * c / (S * S) - s * s * s * s * C / (S * S * S)) / (tau * tau);
        A(row, k++) = d * w * (1.0 - w / std::numbers::pi);
      }
    }
  }
  if (!A.allFinite())
    throw UsageError(Field::model, "model " + model_name(fit.model) + ": a parameter is outside its range");

  Matrix v = wavelet_variance_covariance(fit.model, wv.tau, samples);
  for (double& x : v.values()) x *= inflation;
  const MatrixXd V = detail::to_eigen(v);

  // W^1/2 A = U S V': (A'WA)^-1 = V S^-2 V', B = (A'WA)^-1 A'W = V S^-1 U' W^1/2.
  Eigen::VectorXd rw(static_cast<Eigen::Index>(J));
  for (std::size_t j = 0; j < J; ++j) rw(static_cast<Eigen::Index>(j)) = 1.0 / fit.sd[j];
  const MatrixXd Aw = rw.asDiagonal() * A;
  const Eigen::JacobiSVD<MatrixXd> svd(Aw, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  const double tol = 1e-10 * s.maxCoeff();
  if (!pseudo_inverse && !(s.minCoeff() > tol))
    throw CalibrationError(CalibrationReason::degenerate,
                           "GMWM " + model_name(fit.model) +
                               ": the wavelet variance does not determine every parameter at the fit (singular A'WA)");
  // The pseudo-inverse: directions the curve does not see carry nothing.
  Eigen::VectorXd sinv = s;
  for (Eigen::Index i = 0; i < s.size(); ++i) sinv(i) = s(i) > tol ? 1.0 / s(i) : 0.0;
  const MatrixXd B = svd.matrixV() * sinv.asDiagonal() * svd.matrixU().transpose() * rw.asDiagonal();
  const MatrixXd naive = svd.matrixV() * sinv.cwiseAbs2().asDiagonal() * svd.matrixV().transpose();
  const MatrixXd cov = B * V * B.transpose();
  const MatrixXd hat = A * B;

  GmwmAsymptotics out;
  out.parameters = p;
  out.scales = J;
  out.covariance = detail::to_matrix(cov);
  out.naive = detail::to_matrix(naive);
  out.jacobian = detail::to_matrix(A);
  out.nu2_covariance = std::move(v);
  out.hat = detail::to_matrix(hat);
  Eigen::Index k = 0;
  for (const Process& pr : fit.model.processes) {
    ProcessSd sd;
    const double rel = std::sqrt(cov(k, k));
    ++k;
    // value = e^theta (omega = +-e^{theta / 2} for a drift); phi = exp(-e^theta_a).
    sd.value = pr.kind == ProcessKind::dr ? 0.5 * std::abs(pr.value) * rel : pr.value * rel;
    if (pr.kind == ProcessKind::gm) {
      sd.phi = pr.phi * -std::log(pr.phi) * std::sqrt(cov(k, k));
      ++k;
    }
    if (pr.kind == ProcessKind::ma1) {  // theta = tanh z
      sd.theta = (1.0 - pr.theta * pr.theta) * std::sqrt(cov(k, k));
      ++k;
    }
    if (pr.kind == ProcessKind::sin) {  // omega = pi / (1 + e^-z)
      sd.omega = pr.omega * (1.0 - pr.omega / std::numbers::pi) * std::sqrt(cov(k, k));
      ++k;
    }
    out.sd.push_back(sd);
  }
  return out;
}

}  // namespace cubecal
