/// @file
/// The asymptotic covariance of a GMWM fit (noise/gmwm.hpp): the sandwich
///   cov(theta) = (A'WA)^-1 A'W V W A (A'WA)^-1
/// of a weighted least-squares fit of moments (Guerrier et al., JASA 2013,
/// Prop. 2), with A = d nu2(theta) / d theta at the fit (J x p), W the fit's
/// diagonal weight diag(1 / sd_j^2) and V the covariance of the empirical
/// wavelet variance at the fitted model (wavelet_variance_covariance.hpp).
/// docs/formulas/noise-terms.md §8d.
///
/// theta is the fit's own parametrisation, one row per process in the
/// model's order: ln sigma2 (WN), ln Q2 (QN), ln gamma2 (RW), ln omega^2
/// (DR), for a Gauss-Markov term ln sigma2 then ln a, phi = e^-a, and for an
/// MA1 term ln sigma2 then z = atanh(theta). Its
/// standard deviations are relative ones of the variances; the per-sample
/// parameters' follow by the delta method.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/math/matrix.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {

/// Standard deviations of one process's parameters, in the units of Process (per sample).
struct ProcessSd {
  double value = 0.0;  ///< sd of Process::value (omega for a drift)
  double phi = 0.0;    ///< Gauss-Markov: sd of phi (0 otherwise)
  double theta = 0.0;  ///< MA1: sd of theta (0 otherwise)
  double omega = 0.0;  ///< SIN: sd of omega (0 otherwise)
};

/// The asymptotic (sandwich) covariance of a GMWM fit and the matrices it is made of.
struct GmwmAsymptotics {
  std::size_t parameters = 0;  ///< p
  std::size_t scales = 0;      ///< J
  Matrix covariance;           ///< p x p: the sandwich, of theta
  Matrix naive;                ///< p x p: (A'WA)^-1, the scales taken as independent with sd_j
  Matrix jacobian;             ///< J x p: A
  Matrix nu2_covariance;       ///< J x J: V
  Matrix hat;                  ///< J x J: P = A (A'WA)^-1 A'W, d nu2(theta_hat) / d nu2_hat
  std::vector<ProcessSd> sd;   ///< per process of the fitted model, from the sandwich
};

/// `samples`: the record's length (the wavelet variance's N). V is that of
/// the classical estimator times `inflation` (>= 1): for the robust wavelet
/// variance (stats/robust_wavelet_variance.hpp) 1 / efficiency bounds the
/// ratio of the two estimators' variances from above. Throws
/// UsageError(Field::model) when the fit and the wavelet variance do not belong
/// together, and CalibrationError(degenerate) when A'WA is singular (a
/// parameter the wavelet variance does not determine, e.g. a Gauss-Markov
/// term pushed to phi -> 0). With pseudo_inverse, a singular A'WA is
/// inverted on the directions the curve determines (singular values above
/// 1e-10 of the largest) and the others are left out: the hat matrix is then
/// the projection the fit makes, what the WIC's optimism needs of a fit with
/// a term driven to zero (the twin's search).
GmwmAsymptotics gmwm_asymptotics(const GmwmFit& fit, const WaveletVariance& wv, std::size_t samples,
                                 double inflation = 1.0, bool pseudo_inverse = false);

}  // namespace cubecal
