/// @file
/// The JSON form of a multi-position calibration (what `calibrate
/// multiposition --format json` prints, without the invocation), and back.
/// Keys: method, acc_file, gyro_file, model, samples, rate_hz, g,
/// init_static_s, window, interval_samples, min_intervals, th_mult, threshold,
/// init_variance_norm, static_intervals, intervals, trials, accelerometer
/// {...}, gyroscope {...} or null; and what multiposition_result_from_json needs besides (options,
/// accelerometer.init_samples, the misalignment angles of each model).
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/calibrate_multiposition.hpp"

namespace cubecal::pipeline {

/// The calibration as JSON (keys above). Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const MultipositionResult& r);
/// The result that to_json wrote.
MultipositionResult multiposition_result_from_json(const nlohmann::json& j);

}  // namespace cubecal::pipeline
