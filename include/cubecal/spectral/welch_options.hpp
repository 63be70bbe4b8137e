/// @file
/// What the Welch estimator is asked for (window, segment length, overlap,
/// detrending) and the segment plan it follows from on a record, as
/// scipy.signal.welch(x, fs, window, nperseg, noverlap, detrend) takes them.
/// docs/formulas/spectral.md §2.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "cubecal/spectral/window.hpp"

namespace cubecal {

/// What is removed from each segment before it is windowed: nothing, its
/// mean, or its least-squares line.
enum class Detrend { none, constant, linear };

/// "none", "constant", "linear". Throws nothing.
std::string_view to_string(Detrend d) noexcept;
std::optional<Detrend> parse_detrend(std::string_view name);  ///< "none", "constant", "linear"

/// What a Welch spectrum is asked for: window, segment length or lowest frequency (Hz), overlap and detrending.
struct WelchOptions {
  /// The window of each segment.
  Window window = Window::hann;
  /// Samples per segment (L). 0: from min_frequency_hz when that is given,
  /// else the largest power of two not above a record's n / 8 (so that about
  /// 15 to 30 half-overlapping segments are averaged), at least 16 samples.
  std::size_t segment_length = 0;
  /// > 0 (and segment_length 0): the smallest power of two L with
  /// rate / L <= min_frequency_hz, so that the first bin above zero lies at or
  /// below it.
  double min_frequency_hz = 0.0;
  /// Fraction of a segment shared with the next one, 0 <= overlap < 1; the
  /// samples are floor(overlap * L) (scipy's noverlap = nperseg // 2 at 0.5).
  double overlap = 0.5;
  /// What is removed from each segment before it is windowed.
  Detrend detrend = Detrend::constant;
};

/// The segments a Welch spectrum averages, in samples.
struct WelchPlan {
  std::size_t segment_length = 0;  ///< L
  std::size_t overlap = 0;         ///< samples shared by consecutive segments
  std::size_t step = 0;            ///< L - overlap
};

/// The plan for a record whose longest contiguous piece has `longest`
/// samples. Throws UsageError naming the field at fault: "rate" (not a
/// positive finite number), "segment_length" (below 4, or longer than the
/// record), "min_frequency" (not positive, or asking for segments longer than
/// the record), "overlap" (outside [0, 1), or leaving no step), and "samples"
/// for a record too short for the default (fewer than 16 samples).
WelchPlan plan_welch(const WelchOptions& options, std::size_t longest, double rate_hz);

/// Segments of a piece of n samples: floor((n - overlap) / step), 0 when
/// n < L (the samples after the last whole segment are not used).
std::size_t welch_segments(std::size_t n, const WelchPlan& plan) noexcept;

}  // namespace cubecal
