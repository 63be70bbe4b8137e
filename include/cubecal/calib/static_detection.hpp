/// @file
/// Static detection for the multi-position calibration (docs/formulas/multiposition.md §2):
/// the windowed accelerometer variance norm v(i), the variance norm of a block
/// and the maximal runs of v(i) below a threshold.
///
/// v(i) = |(var_x, var_y, var_z)| of the samples over the centred window
/// [i-h, i+h] (window = 2h+1 samples, unbiased variance); a static interval is
/// a maximal run of window centres with v(i) below the threshold, [begin, end)
/// (end is the first centre at or above it).
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/math/vec3.hpp"

namespace cubecal::multipos {

/// Samples of the static detector's moving window by default (imu_tk's).
inline constexpr std::size_t kDefaultWindow = 101;
/// The smallest window accepted (samples).
inline constexpr std::size_t kMinWindow = 11;

/// The window rule: window must be at least kMinWindow; an even window is
/// made odd (+1), as imu_tk does. Throws CalibrationError (bad_option) below
/// 11.
std::size_t normalised_window(std::size_t window);

/// v(i) for every sample; +infinity for the h samples at each end, whose
/// centred window does not fit (never static). Throws as normalised_window.
std::vector<double> variance_norm(std::span<const Vec3> x, std::size_t window = kDefaultWindow);

/// |(var_x, var_y, var_z)| over all of x (unbiased variance). Throws
/// CalibrationError (too_few_points) for fewer than 2 samples.
double block_variance_norm(std::span<const Vec3> x);

/// Maximal runs of v(i) < threshold, in order, of any length.
std::vector<IndexRange> static_intervals(std::span<const double> v, double threshold);

}  // namespace cubecal::multipos
