/// @file
/// What the Welch estimator removes from each segment before windowing it:
/// nothing, the mean, or the least-squares line (scipy.signal.detrend of type
/// "constant" or "linear"). docs/formulas/spectral.md §2.3.
#pragma once
#include <span>

#include "cubecal/spectral/welch_options.hpp"

namespace cubecal {

/// In place.
void detrend(std::span<double> segment, Detrend how) noexcept;

}  // namespace cubecal
