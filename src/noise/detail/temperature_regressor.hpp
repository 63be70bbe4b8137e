// The scaled temperature regressor shared by the least-squares fits of a
// channel on temperature (temperature.cpp, temperature_random_walk.cpp).
// Not an installed header.
#pragma once
#include <cstddef>
#include <span>

namespace cubecal::noise::detail {

// u = (T - t_ref) / half_span, t_ref the mean temperature, half_span half
// its range: V^T V stays well conditioned for every order up to 5
// (docs/formulas/drift-covariance-temperature.md §3.2).
struct TemperatureRegressor {
  double t_ref = 0.0;
  double half_span = 0.0;
  double operator()(double t) const noexcept { return (t - t_ref) / half_span; }
};

// Checks the inputs of a fit of `order` and returns its regressor. Throws
// CalibrationError: bad_option (order not 1 to 5), bad_data (lengths
// differ), too_few_points (no more samples than order + 1), degenerate
// (constant temperature, or fewer distinct values than coefficients).
TemperatureRegressor temperature_regressor(std::span<const double> y, std::span<const double> temp, std::size_t order);

// The degenerate error of a normal matrix that came out singular.
[[noreturn]] void throw_too_few_distinct(std::size_t order);

}  // namespace cubecal::noise::detail
