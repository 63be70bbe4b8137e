/// @file
/// Frequency-to-phase conversion.
#pragma once
#include <span>
#include <vector>

namespace cubecal {

/// x[0] = 0, x[i+1] = x[i] + (y[i] - mean(y)) * tau0: N frequency points give
/// N+1 phase points. The mean is removed first (it cancels in every
/// statistic built on second or higher differences) so that the running sum
/// stays small and keeps its precision over millions of samples.
///
/// `scale` (a power of two, so exact) divides every value first; callers use
/// it to keep sums of squares of extreme data inside the double range.
std::vector<double> freq_to_phase(std::span<const double> y, double tau0, double scale = 1.0);

/// Phase data as given, minus its first value (same reason), divided by scale.
std::vector<double> normalize_phase(std::span<const double> x, double scale = 1.0);

/// A power of two near the largest magnitude in v (1 for an all-zero span).
/// Dividing by it maps the data to [-2, 2] exactly. Throws
/// std::invalid_argument naming the index of a NaN or infinite sample.
double power_of_two_scale(std::span<const double> v);

}  // namespace cubecal
