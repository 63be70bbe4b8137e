/// @file
/// Turn-on bias and run-to-run comparison over several records of the same
/// sensor (the paper's five power-cycled 3 h runs, and its 10/100/250 Hz runs).
/// JSON form: turnon_json.hpp.
#pragma once
#include <string>
#include <vector>

#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/stats/confidence.hpp"

namespace cubecal::pipeline {

/// What a runs command shows of one channel of one run.
struct RunChannel {
  /// The channel's name.
  std::string name;
  /// The channel's data unit.
  Unit unit;
  double mean = 0.0;  ///< the run's bias
  /// The run's sample standard deviation (data unit).
  double stddev = 0.0;
  std::vector<StabilityPoint> adev;  ///< OADEV with its interval
  SlopeReadOffs readoffs;            ///< N, B (and T = tau_min) of the curve
};

/// One run of a turn-on or compare command.
struct RunSummary {
  /// The run's path, as given.
  std::string file;
  /// Samples per channel.
  std::size_t samples = 0;
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  /// One per channel, in the record's order.
  std::vector<RunChannel> channels;
};

/// The result of `cubecal turnon`: the runs and the turn-on bias of every channel.
struct TurnOnResult {
  /// The channels' names.
  std::vector<std::string> names;
  /// The channels' data units.
  std::vector<Unit> units;
  /// The runs, in the order given.
  std::vector<RunSummary> runs;
  std::vector<double> mean_bias;           ///< mean over runs of the run biases
  std::vector<double> turn_on;             ///< sample standard deviation of the run biases
  std::vector<Interval> turn_on_interval;  ///< its confidence interval (chi-squared, runs - 1 dof)
  double ci = 0.683;                       ///< confidence of turn_on_interval (AnalyzeRequest::ci)
};

/// Every run is analysed as `analyze` does (same request); runs must have the
/// same channels. Throws UsageError for fewer than 2 runs or mismatched
/// channels.
TurnOnResult run_turnon(const std::vector<io::Series>& runs, const AnalyzeRequest& request);

/// Each run analysed on its own, for side-by-side Allan curves and N, B, T.
std::vector<RunSummary> run_compare(const std::vector<io::Series>& runs, const AnalyzeRequest& request);
/// The same with a request per run (runs read in different units); a count
/// that differs from the runs' is a UsageError.
std::vector<RunSummary> run_compare(const std::vector<io::Series>& runs, const std::vector<AnalyzeRequest>& requests);

}  // namespace cubecal::pipeline
