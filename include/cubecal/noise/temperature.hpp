// Temperature dependence of a bias: polynomial least squares of the channel
// on temperature (formulas.md section 4), with the covariance of the
// coefficients, and the compensated series.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

namespace cubecal {

struct TemperatureFit {
  double t_ref = 0.0;                    // reference temperature (mean of T)
  std::vector<double> coeff;             // c0, c1, ... : y = sum c_p (T - t_ref)^p
  std::vector<double> coeff_sigma;       // 1-sigma, from the covariance below
  // Coefficient covariance: sandwich estimate with batch means of the scores
  // (20 contiguous batches), robust to the correlated residuals a drifting
  // bias leaves; never below the white-residual sigma^2 (V^T V)^-1.
  std::vector<std::vector<double>> cov;
  double residual_rms = 0.0;             // data unit
  double r2 = 0.0;                       // coefficient of determination
  std::size_t order = 1;
};

// Throws std::invalid_argument when the temperature does not vary enough
// for the order asked (fewer distinct values than order + 1, or order > 5).
TemperatureFit fit_temperature(std::span<const double> y, std::span<const double> temp,
                               std::size_t order = 1);

// y minus the temperature-dependent part (orders >= 1): the bias at t_ref stays.
std::vector<double> compensate_temperature(std::span<const double> y, std::span<const double> temp,
                                           const TemperatureFit& fit);

}  // namespace cubecal
