/// @file
/// `cubecal dev` as a library call: one statistic on every channel of a
/// record, over a tau grid, with confidence intervals. Channels, segments and
/// averaging factors run in parallel.
#pragma once
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "cubecal/stage_times.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_exclusions.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::pipeline {

/// What `cubecal dev` is asked to do with a record (the data already read).
struct DevRequest {
  /// The statistic.
  Stat stat = Stat::oadev;
  /// Frequency or phase data.
  DataType type = DataType::freq;
  TauGrid grid;              ///< default octave
  StabilityOptions options;  ///< ci, edf method, fixed alpha, intervals on/off
  unsigned threads = 0;      ///< 0: all cores
  /// Called now and then with the fraction of the work done (0..1), always
  /// from the calling thread (optional; must not throw).
  std::function<void(double)> progress;
  /// Where the time goes (optional): phase, kernels, noise id, intervals.
  StageTimes* times = nullptr;
};

/// What a run_dev call will cost, before it starts: the terms its kernels sum
/// (about N - 2m per averaging factor m for OADEV, N/m for ADEV, ...; noise
/// identification and intervals included), and the seconds that takes at the
/// rate measured on this machine by a short trial on the record itself.
struct DevWorkEstimate {
  std::size_t taus = 0;           ///< averaging factors of the grid that fit
  double terms = 0.0;             ///< over every channel and segment
  double terms_per_second = 0.0;  ///< measured, one thread
  unsigned threads = 1;           ///< the run's threads
  double seconds = 0.0;           ///< terms / (terms_per_second * threads)
};
/// The cost of run_dev(series, request), measured by a short trial on the record. Throws UsageError as run_dev does for
/// a grid that does not fit.
DevWorkEstimate estimate_dev(const io::Series& series, const DevRequest& request);

/// The points of one channel.
struct DevChannel {
  /// The channel's name.
  std::string name;
  /// One point per tau (tau in s, deviation in the data unit).
  std::vector<StabilityPoint> points;
  /// Streamed runs (run_dev_stream): the stride of each point's terms (1:
  /// fully overlapping); empty for the in-memory path.
  std::vector<std::size_t> strides;
};

/// The result of `cubecal dev`: one stability curve per channel.
struct DevResult {
  /// The statistic.
  Stat stat = Stat::oadev;
  /// Frequency or phase data.
  DataType type = DataType::freq;
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  /// Sample period 1 / rate_hz (s).
  double tau0 = 0.0;
  /// Samples per channel.
  std::size_t samples = 0;
  std::size_t segments = 1;       ///< > 1 when the record was split at gaps
  std::size_t segments_used = 1;  ///< segments long enough for at least m = 1
  std::string file;               ///< the record's file (empty for in-memory arrays)
  StabilityOptions options;       ///< ci, EDF method and intervals of the points
  /// Taus of an explicit list that the statistic cannot evaluate on the
  /// longest segment (with the reason), and listed taus merged with an
  /// earlier one on the same averaging factor. Empty for generated grids.
  TauListOutcome tau_list;
  /// One per channel, in the record's order.
  std::vector<DevChannel> channels;
  /// > 0: computed in one pass over a stream (pipeline/dev_stream.hpp), the
  /// terms of factors whose span exceeds this many samples taken at a stride.
  std::size_t window_bound = 0;
};

/// Throws UsageError when no averaging factor of the grid fits the record
/// (the series is too short for the statistic). Listed taus that do not fit
/// are not evaluated and are reported in DevResult::tau_list.
DevResult run_dev(const io::Series& series, const DevRequest& request);

/// The same on raw arrays (one contiguous segment each), for callers that
/// have their data in memory already.
DevResult run_dev(const std::vector<std::string>& names, const std::vector<std::vector<double>>& channels,
                  double rate_hz, const DevRequest& request);

/// The same on views of the caller's arrays (all of one length), cut into
/// `segments` as a Series is (empty: one contiguous segment); nothing is
/// copied but the phase record of the channel being evaluated.
/// std::invalid_argument for mismatched names, lengths or segments.
DevResult run_dev(const std::vector<std::string>& names, const std::vector<std::span<const double>>& channels,
                  double rate_hz, const std::vector<IndexRange>& segments, const DevRequest& request);

}  // namespace cubecal::pipeline
