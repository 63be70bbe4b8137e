/// @file
/// The sampling of a time-stamped record: its period (the median interval),
/// the missing samples (gaps) and the intervals off the period (jitter).
#pragma once
#include <cstddef>
#include <limits>
#include <span>

namespace cubecal {

/// An interval of at least this many periods has a sample (or more) missing;
/// anything closer to one period is timing noise.
inline constexpr double kGapPeriods = 1.5;

/// What the time stamps of a record say about its sampling: the period (s), gaps and jitter.
struct SamplingCheck {
  /// No such interval.
  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();
  double period_s = 0.0;         ///< the median interval
  std::size_t intervals = 0;     ///< t.size() - 1
  std::size_t gaps = 0;          ///< intervals >= kGapPeriods periods
  std::size_t first_gap = npos;  ///< i of the first gap: t[i] - t[i-1] >= kGapPeriods * period
  std::size_t jittered = 0;      ///< other intervals off the period by more than the tolerance
  /// i of the first jittered interval (npos: none).
  std::size_t first_jitter = npos;
  double max_jitter = 0.0;  ///< largest |dt - period| / period among the intervals that are not gaps
};

/// t: strictly increasing, finite time stamps in seconds (std::invalid_argument
/// otherwise); tolerance: the allowed |dt - period| / period.
SamplingCheck check_sampling(std::span<const double> t, double tolerance = 0.01);

/// The median of the intervals t[i+1] - t[i] (the mean of the two middle
/// ones for an even count), exactly, with memory for a few per cent of the
/// intervals rather than all of them (a column of a long record).
/// std::invalid_argument for fewer than two stamps.
double median_interval(std::span<const double> t);

}  // namespace cubecal
