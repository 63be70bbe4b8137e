// Turn-on bias and run-to-run comparison over several records of the same
// sensor (the paper's five power-cycled 3 h runs, and its 10/100/250 Hz runs).
// JSON form: turnon_json.hpp.
#pragma once
#include <string>
#include <vector>

#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/stats/confidence.hpp"

namespace cubecal::pipeline {

// What a runs command shows of one channel of one run.
struct RunChannel {
  std::string name;
  Unit unit;
  double mean = 0.0;  // the run's bias
  double stddev = 0.0;
  std::vector<StabilityPoint> adev;  // OADEV with its interval
  SlopeReadOffs readoffs;            // N, B (and T = tau_min) of the curve
};

struct RunSummary {
  std::string file;
  std::size_t samples = 0;
  double rate_hz = 0.0;
  std::vector<RunChannel> channels;
};

struct TurnOnResult {
  std::vector<std::string> names;
  std::vector<Unit> units;
  std::vector<RunSummary> runs;
  std::vector<double> mean_bias;           // mean over runs of the run biases
  std::vector<double> turn_on;             // sample standard deviation of the run biases
  std::vector<Interval> turn_on_interval;  // its confidence interval (chi-squared, runs - 1 dof)
  double ci = 0.683;
};

// Every run is analysed as `analyze` does (same request); runs must have the
// same channels. Throws UsageError for fewer than 2 runs or mismatched
// channels.
TurnOnResult run_turnon(const std::vector<io::Series>& runs, const AnalyzeRequest& request);

// Each run analysed on its own, for side-by-side Allan curves and N, B, T.
std::vector<RunSummary> run_compare(const std::vector<io::Series>& runs, const AnalyzeRequest& request);
// The same with a request per run (runs read in different units); a count
// that differs from the runs' is a UsageError.
std::vector<RunSummary> run_compare(const std::vector<io::Series>& runs, const std::vector<AnalyzeRequest>& requests);

}  // namespace cubecal::pipeline
