/// @file
/// Temperature coefficients estimated jointly with a random-walk bias and white
/// noise (docs/formulas/drift-covariance-temperature.md §4): generalized least
/// squares with the covariance the sensor noise model implies, computed by a
/// scalar Kalman filter in O(n), and the iteration that takes the noise model
/// from the compensated series.
///
/// Measurement model, sample k (the paper's eq. 1-3, 14-16 with a temperature
/// term):
///   y_k = c_0 + sum_{p=1..P} c_p (T_k - T_ref)^p + s_k + v_k,
///   s_0 = 0,  s_{k+1} = s_k + w_k,  w_k ~ N(0, (sigma_mu dt)^2),
///   v_k ~ N(0, sigma_n^2 + q^2)   (q^2 = 1/(12 lsb^2), the quantizer as white noise).
#pragma once
#include <cstddef>
#include <functional>
#include <span>

#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/temperature.hpp"

namespace cubecal {

/// Samples missing before sample `index` (a gap between two segments of a
/// record): the bias walks `steps` unobserved steps there.
struct BiasGap {
  /// The first sample after the gap.
  std::size_t index = 0;
  /// Sample periods the gap lasts.
  double steps = 0.0;
};

/// Generalized least squares of y on the temperature polynomial of `order`
/// with the covariance of white noise plus a random-walk bias given by
/// `noise` (sigma_n, sigma_mu, dt, lsb). The coefficient covariance is the
/// GLS one, (X^T Sigma^-1 X)^-1: right when the noise model is. c_0 is the
/// record's mean bias at T_ref, mean(y - sum_{p>=1} c_p (T - T_ref)^p), with
/// the white-noise and coefficient share of its uncertainty. residual_rms and
/// r2 are those of y - the fitted polynomial, as for fit_temperature.
/// Throws CalibrationError as fit_temperature does, and bad_option for a
/// noise model without white noise or with a negative or non-finite term.
TemperatureFit fit_temperature_gls(std::span<const double> y, std::span<const double> temp, std::size_t order,
                                   const RandomWalkModel& noise, std::span<const BiasGap> gaps = {});

/// The noise model of a compensated series (e.g. its Allan curve and
/// fit_random_walk_model). It throws CalibrationError when no model fits.
using CompensatedNoiseModel = std::function<RandomWalkModel(std::span<const double> compensated)>;

/// The temperature model estimated jointly with the random-walk bias, and the iteration that reached it.
struct TemperatureRandomWalkFit {
  TemperatureFit fit;          ///< the joint (GLS) estimate
  TemperatureFit ols;          ///< the ordinary least-squares start (batch-means sandwich covariance)
  RandomWalkModel noise;       ///< the noise model fit was weighted with
  std::size_t iterations = 0;  ///< noise-model fits (one per GLS)
  bool converged = false;      ///< the last GLS moved no coefficient by more than 0.05 sigma
};

/// The iteration: OLS; then, up to max_iterations times, the noise model of
/// the series compensated with the current coefficients, and the GLS with
/// that model; it stops when a GLS moves no coefficient (order >= 1) by more
/// than 0.05 of its sigma. Throws what fit_temperature and noise_model throw.
TemperatureRandomWalkFit fit_temperature_random_walk(std::span<const double> y, std::span<const double> temp,
                                                     std::size_t order, const CompensatedNoiseModel& noise_model,
                                                     std::span<const BiasGap> gaps = {},
                                                     std::size_t max_iterations = 5);

/// The same iteration started from an OLS fit the caller already has
/// (fit_temperature of the same y, temp and order): a caller that reports the
/// OLS fit too need not compute it twice.
TemperatureRandomWalkFit fit_temperature_random_walk(std::span<const double> y, std::span<const double> temp,
                                                     std::size_t order, TemperatureFit ols,
                                                     const CompensatedNoiseModel& noise_model,
                                                     std::span<const BiasGap> gaps = {},
                                                     std::size_t max_iterations = 5);

}  // namespace cubecal
