/// @file
/// IEEE Std 952 noise terms from an Allan-deviation curve.
///
/// Units: the data unit u (deg/s, mGauss, g...) and seconds throughout:
///   Q  angle quantization   u*s        sigma(tau) = sqrt(3) Q / tau
///   N  angle random walk    u*sqrt(s)  sigma(tau) = N / sqrt(tau)
///   B  bias instability     u          sigma_min  = sqrt(2 ln2 / pi) B = 0.664 B
///   K  rate random walk     u/sqrt(s)  sigma(tau) = K sqrt(tau / 3)
///   R  rate ramp            u/s        sigma(tau) = R tau / sqrt(2)
/// Conversion to display units (deg/sqrt(h), deg/h...) is the caller's.
#pragma once
#include <array>
#include <cstddef>

#include "cubecal/stats/allan_curve.hpp"

namespace cubecal {

/// sqrt(2 ln 2 / pi): the flicker floor of the Allan deviation over B.
inline constexpr double kFlickerFloor = 0.6642824702007757;

/// One IEEE 952 noise term's estimate: value and 1-sigma uncertainty in the term's unit (Q: u s, N: u sqrt(s), B: u, K:
/// u / sqrt(s), R: u / s; u the data unit), and the taus it came from.
struct TermEstimate {
  bool valid = false;  ///< false: the curve has no region of this slope
  /// The term's value, in its unit (see above).
  double value = 0.0;
  double sigma = 0.0;   ///< 1-sigma uncertainty from the confidence intervals
  double tau_lo = 0.0;  ///< tau range the estimate was read from (s)
  /// Upper end of that tau range (s).
  double tau_hi = 0.0;
};

/// Slope read-offs as IEEE 952 and the paper make them.
struct SlopeReadOffs {
  TermEstimate Q;           ///< -1 slope region, line read at tau = sqrt(3)
  TermEstimate N;           ///< -1/2 slope region (line tangent to the white-noise arm), read at tau = 1 s
  TermEstimate B;           ///< sigma_min / 0.664
  TermEstimate K;           ///< +1/2 slope region, read at tau = 3 s
  TermEstimate R;           ///< +1 slope region, read at tau = sqrt(2)
  double tau_min = 0.0;     ///< T: tau at the minimum of the curve (s)
  double tau_min_lo = 0.0;  ///< taus around the minimum whose intervals reach sigma_min
  /// Upper end of that range (s).
  double tau_min_hi = 0.0;
  /// The curve's smallest deviation (data unit).
  double sigma_min = 0.0;
};

/// The five terms read off the measured OADEV curve (tau in s, deviation in the data unit). A term the curve has no
/// region for is valid false. Throws nothing.
SlopeReadOffs read_off_noise_terms(const AllanCurve& curve);

/// Weighted non-negative least squares of sigma^2(tau) = sum_{k=-2..2} C_k tau^k
/// (weights edf / (2 sigma^4): the variance of an AVAR estimate), giving the
/// five terms with uncertainties from the covariance of C.
struct NoiseFit {
  /// value 0 / valid false when C_k is at its bound
  ///@{
  TermEstimate Q, N, B, K, R;
  ///@}
  std::array<double, 5> c{};  ///< C_-2 .. C_2
  /// 1 sigma of each C_k, from the fit's covariance.
  std::array<double, 5> c_sigma{};
  double chi2 = 0.0;              ///< weighted residual sum of squares
  std::size_t dof = 0;            ///< points - free coefficients
  double rms_rel_residual = 0.0;  ///< RMS of (fit - measured) / measured, in deviation
};

/// The weighted five-term fit of the measured OADEV curve (tau in s, deviation in the data unit). Throws nothing.
NoiseFit fit_noise_terms(const AllanCurve& curve);

/// Allan deviation of the five-term model at tau.
double noise_model_adev(const std::array<double, 5>& c, double tau) noexcept;

}  // namespace cubecal
