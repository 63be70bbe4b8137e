/// @file
/// Files written by `cubecal analyze --out DIR`: analysis.json (stable keys,
/// every number with its unit), adev.csv, drift.csv, a Kalibr imu.yaml and the
/// estimator files asked for (estimator_config.hpp).
#pragma once
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/estimator_config.hpp"

namespace cubecal::pipeline {

/// What analyze's output files record besides the result: the command line and the estimator files asked for.
struct OutputContext {
  std::string command;  ///< the command line that reproduces the result
  /// The IMU topic written into imu.yaml (Kalibr's rostopic).
  std::string rostopic = "/imu0";
  std::vector<Estimator> estimators{};  ///< estimator files asked for (analyze --for)
  double inflate = 1.0;                 ///< factor on their noise terms (analyze --inflate)
};

/// analysis.json: to_json(AnalysisResult) of analysis_json.hpp, the command
/// and "estimator_files": {"for": [names], "noise_factor": K (--inflate)}.
nlohmann::json to_json(const AnalysisResult& r, const OutputContext& ctx);
/// The text of analysis.json (to_json(r, ctx) serialised), as the file holds it.
std::string analysis_json(const AnalysisResult& r, const OutputContext& ctx);

/// `cubecal dev --format json` (to_json(DevResult) of analysis_json.hpp) with
/// the file and interval settings of `ctx`.
struct DevJsonContext {
  /// The input's path, as given.
  std::string file;
  /// Confidence factor of the intervals.
  double ci = 0.683;
  /// "greenhall" or "simple".
  std::string edf_method = "greenhall";
  /// False when no intervals were computed ("ci" is then null).
  bool intervals = true;
};
/// The `dev --format json` text of `r`. Throws nothing beyond std::bad_alloc.
std::string dev_json(const DevResult& r, const DevJsonContext& ctx);

/// The names of the files `analyze --out` writes, in order.
inline constexpr const char* kAnalysisFiles[] = {"analysis.json", "adev.csv", "drift.csv", "imu.yaml"};

/// Long format, one row per channel and tau: measured OADEV with its interval,
/// and the fitted five-term, random-walk and Gauss-Markov model deviations
/// (and, with analyze --composite, the composite model's: composite_dev).
std::string adev_csv(const AnalysisResult& r);

/// Long format: channel, t (s from the record start), drift (data unit).
std::string drift_csv(const AnalysisResult& r);

/// drift.csv of an earlier run read back through the io layer's table reader
/// (columns t and drift) into the channels' DriftSeries, in channel order,
/// points[c] rows for channel c (the counts analysis.json records). False,
/// and `r` unchanged, when the file does not hold that many rows. Throws
/// InputError for a malformed file.
bool read_drift_csv(const std::string& path, const std::vector<std::size_t>& points, AnalysisResult& r);

/// The Kalibr imu.yaml written by default: estimator_config(kalibr) with
/// ctx.inflate when a rate channel is present, else an empty string.
std::string kalibr_yaml(const AnalysisResult& r, const OutputContext& ctx);

/// Every file `analyze --out` writes for `ctx`, in order, computed before any
/// is written (so an error leaves no partial set): analysis.json, adev.csv,
/// drift.csv, imu.yaml (Kalibr: with rate channels, or always when asked for),
/// then the other estimator files asked for. Throws as estimator_config.
std::vector<EstimatorFile> analysis_files(const AnalysisResult& r, const OutputContext& ctx);

/// The names analysis_files may write for `estimators`, for the check that
/// none exists before the work starts.
std::vector<std::string> analysis_file_names(const std::vector<Estimator>& estimators);

}  // namespace cubecal::pipeline
