/// @file
/// Temperature dependence of a bias: polynomial least squares of the channel
/// on temperature (docs/formulas/drift-covariance-temperature.md §3), with the covariance of the
/// coefficients, and the compensated series.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/math/matrix.hpp"

namespace cubecal {

/// A polynomial temperature model of a channel's bias: y = sum c_p (T - t_ref)^p, y in the data unit and T in the
/// temperature's unit.
struct TemperatureFit {
  double t_ref = 0.0;               ///< reference temperature (mean of T)
  std::vector<double> coeff;        ///< c0, c1, ... : y = sum c_p (T - t_ref)^p
  std::vector<double> coeff_sigma;  ///< 1-sigma, from the covariance below
  /// Coefficient covariance: sandwich estimate with batch means of the scores
  /// (20 contiguous batches), robust to the correlated residuals a drifting
  /// bias leaves; never below the white-residual sigma^2 (V^T V)^-1.
  Matrix cov;
  double residual_rms = 0.0;  ///< data unit
  double r2 = 0.0;            ///< coefficient of determination
  std::size_t order = 1;      ///< polynomial order fitted (1 to 5)
};

/// Throws CalibrationError (cubecal/error.hpp): bad_option (order not 1 to 5);
/// bad_data (y and temp of different lengths); too_few_points (no more
/// samples than order + 1); degenerate (the temperature is constant, or takes
/// too few distinct values for the order).
TemperatureFit fit_temperature(std::span<const double> y, std::span<const double> temp, std::size_t order = 1);

/// y minus the temperature-dependent part (orders >= 1): the bias at t_ref stays.
std::vector<double> compensate_temperature(std::span<const double> y, std::span<const double> temp,
                                           const TemperatureFit& fit);
/// The same into `out` (y.size() values; std::invalid_argument for a length
/// that differs): no allocation, for a multi-day record compensated repeatedly.
void compensate_temperature(std::span<const double> y, std::span<const double> temp, const TemperatureFit& fit,
                            std::span<double> out);

}  // namespace cubecal
