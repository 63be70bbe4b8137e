/// @file
/// Running sums of a sequence for its lag-1 autocorrelation with the mean
/// removed, taken a piece at a time: the statistic of Stable32's noise
/// identification (noise_id) over the averages at one factor, in memory or
/// streamed.
#pragma once
#include <cstddef>

namespace cubecal {

/// Running sums of a sequence for its lag-1 autocorrelation.
struct LagSums {
  /// Values added.
  std::size_t n = 0;
  /// Sum, sum of squares, lag-1 product sum, and the first and last values.
  ///@{
  double s1 = 0, s2 = 0, p = 0, first = 0, last = 0;
  ///@}
  /// Appends w[0 .. len) to the sequence (independent partial sums: the loop
  /// runs vectorized).
  void add(const double* w, std::size_t len) noexcept;
  /// Stable32's r1: the lag-1 sum / N over the sample variance (N - 1); 0
  /// below two values or for a constant sequence.
  double r1() const noexcept;
};

}  // namespace cubecal
