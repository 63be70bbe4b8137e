/// @file
/// Bias drift as the paper plots it (Figs. 3 and 5, docs/paper.md §2.5;
/// docs/formulas/drift-covariance-temperature.md §1): a moving average of the
/// static record over a window, minus the fixed bias (the record mean).
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace cubecal {

/// The bias drift of a record: moving averages minus the fixed bias, in the data unit.
struct DriftSeries {
  std::vector<double> t;      ///< s from the start, at the window centre
  std::vector<double> drift;  ///< moving average - mean, data unit
  double mean = 0.0;          ///< the fixed bias
  std::size_t window = 0;     ///< samples per average
};

/// Averages of `window` consecutive samples, one every `stride` samples
/// (stride 0: window/10, at least 1), minus the fixed bias: the mean of y, or
/// `fixed_bias` when given (a segment of a longer record uses the record's
/// mean). Empty when the record is shorter than the window.
DriftSeries bias_drift(std::span<const double> y, double dt, std::size_t window, std::size_t stride = 0,
                       std::optional<double> fixed_bias = std::nullopt);

}  // namespace cubecal
