/// @file
/// The overlapping Allan deviation of a record with missing samples (NaN),
/// as AllanTools' gradev computes it: every second difference that needs a
/// missing sample is left out and the others are averaged, so a few lost
/// samples cost a few terms instead of splitting the record. `cubecal dev
/// --gaps skip`. docs/formulas/stability.md §7a.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// `data`: phase or frequency samples, NaN where a sample is missing (other
/// non-finite values are refused with std::invalid_argument). Phase: a term
/// x[i] - 2 x[i+m] + x[i+2m] counts when its three points are there.
/// Frequency: the phase is the running sum of the samples, and a term counts
/// when none of the 2m samples it spans is missing (its two m-averages are
/// whole). n is the number of terms that count (0: none at this m).
///
/// With options.intervals, each point gets an interval for the noise type
/// options.alpha, or else the type identified (as StabilityRecord does) on
/// the longest stretch without a missing sample, at the factors that stretch
/// holds (beyond them, the last identified type); its EDF is that of a record
/// without gaps giving the same number of terms (an approximation: missing
/// samples also break the overlaps between terms).
std::vector<StabilityPoint> oadev_skipping_missing(std::span<const double> data, DataType type, double tau0,
                                                   std::span<const std::size_t> ms,
                                                   const StabilityOptions& options = {});

/// The noise type oadev_skipping_missing (with intervals) gives each factor
/// of `ms`: options.alpha, or the type identified on the longest stretch
/// without a missing sample, carried beyond the factors that stretch holds.
/// For callers that need the types and not the deviations (davar's windows).
struct GapNoiseType {
  /// The noise type alpha (exponent of the frequency PSD).
  int alpha = 0;
  bool carried = false;  ///< not identified at this factor (StabilityPoint::type_carried)
};
/// The noise types for `ms`. Throws as oadev_skipping_missing does.
std::vector<GapNoiseType> noise_types_skipping_missing(std::span<const double> data, DataType type, double tau0,
                                                       std::span<const std::size_t> ms,
                                                       const StabilityOptions& options = {});

/// Samples of `data` that are missing (NaN).
std::size_t missing_samples(std::span<const double> data) noexcept;

}  // namespace cubecal
