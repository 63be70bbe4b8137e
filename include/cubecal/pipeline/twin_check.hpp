/// @file
/// `analyze --twin-check K`: K twins of the record simulated at its length
/// (each channel's composite model, sim/composite_simulator.hpp, seeds
/// seed + k), their OADEV at the taus of the curve the model was fitted to,
/// and the mean of their Allan variances against the measured curve: what a
/// user of the twin in a simulator will see, and the figure of merit of
/// docs/twins.md (the worst |sigma_twins / sigma_measured - 1| to 10 s and
/// to 100 s).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace cubecal::pipeline {

struct AnalysisResult;

/// The twin check of one channel: the mean curve of its simulated twins against the measured one.
struct TwinCheckChannel {
  /// The channel's name.
  std::string name;
  std::vector<double> tau;       ///< s, the points of the channel's model.adev
  std::vector<double> measured;  ///< the record's OADEV there
  std::vector<double> twins;     ///< sqrt of the mean over the twins of their Allan variance
  std::vector<double> twins_lo;  ///< the smallest and largest twin's deviation
  std::vector<double> twins_hi;  ///< the largest twin's deviation
  double max_error_10s = 0.0;    ///< largest |twins / measured - 1| for tau <= 10 s
  double max_error_100s = 0.0;   ///< for tau <= 100 s
  double max_error = 0.0;        ///< over every tau
  double max_error_tau_s = 0.0;  ///< where that is
};

/// The twin check of a record (analyze --twin-check).
struct TwinCheck {
  /// Twins simulated per channel.
  std::size_t twins = 0;
  /// Seed of the first twin.
  std::uint64_t seed = 1;
  std::size_t samples = 0;                 ///< of each twin: the samples the model was fitted on
  std::vector<TwinCheckChannel> channels;  ///< those with a composite model, in column order
};

/// Throws UsageError(Field::twin_check) for twins = 0 or above 10000, or when no
/// channel of `r` carries a composite model (the reason of
/// AnalysisResult::composite_skipped included). `threads` 0: all cores.
TwinCheck twin_check(const AnalysisResult& r, std::size_t twins, std::uint64_t seed, unsigned threads = 0);

}  // namespace cubecal::pipeline
