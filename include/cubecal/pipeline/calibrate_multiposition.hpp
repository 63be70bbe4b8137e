/// @file
/// `calibrate multiposition` as calls: the accelerometer (and gyroscope)
/// samples, already read, and the request in; the calibration of each triad
/// from static poses without a turntable out (Tedaldi, Pretto & Menegatti
/// 2014; X' = T K (X - B)). JSON form: calibrate_multiposition_json.hpp.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/calib/multiposition.hpp"
#include "cubecal/math/vec3.hpp"

namespace cubecal::pipeline {

/// One triad's record: raw samples, and their time stamps (s, increasing) or none.
struct TriadSamples {
  /// The record's path, as given.
  std::string file;
  /// Raw samples (raw unit).
  std::vector<Vec3> x;
  std::vector<double> t;  ///< empty: sampled at MultipositionRequest::rate_hz
};

/// What `calibrate multiposition` is asked to do (the samples already read).
struct MultipositionRequest {
  multipos::Options options;  ///< gravity, initial static period, windows, initial guesses
  double rate_hz = 0.0;       ///< when the samples have no time stamps (> 0 then)
};

/// A multi-position calibration with what an output needs.
struct MultipositionResult {
  /// The accelerometer record's path.
  std::string acc_file;
  std::optional<std::string> gyro_file;  ///< unset: accelerometer alone
  std::size_t samples = 0;               ///< accelerometer samples
  double rate_hz = 0.0;                  ///< from the time stamps (mean), else the request's
  multipos::Options options;             ///< as used
  /// Times (s) of each static interval's first and last sample, per AccResult::intervals.
  std::vector<std::pair<double, double>> interval_times;
  /// The accelerometer's calibration.
  multipos::AccResult accelerometer;
  /// The gyroscope's calibration; unset: accelerometer alone.
  std::optional<multipos::GyroResult> gyroscope;
};

/// The accelerometer alone. Throws UsageError ("sampling": neither time
/// stamps nor a rate, or both); what the core throws passes through.
MultipositionResult calibrate_multiposition_accelerometer(const TriadSamples& acc, const MultipositionRequest& request);

/// Adds the gyroscope to a result of the accelerometer step (same `acc`).
void add_multiposition_gyroscope(MultipositionResult& result, const TriadSamples& acc, const TriadSamples& gyro,
                                 const MultipositionRequest& request);

/// Both steps (the gyroscope when given).
MultipositionResult calibrate_multiposition(const TriadSamples& acc, const std::optional<TriadSamples>& gyro,
                                            const MultipositionRequest& request);

/// The unit of each parameter of the accelerometer (9) and of the gyroscope (9 or 12).
std::vector<std::string> multiposition_acc_units();
/// The gyroscope's parameter units, for 9 or 12 parameters. Throws nothing beyond std::bad_alloc.
std::vector<std::string> multiposition_gyro_units(std::size_t parameters);

}  // namespace cubecal::pipeline
