/// @file
/// The JSON form of a temperature calibration (what `calibrate temperature
/// --format json` prints), and back. Keys: file, temperature_column, order,
/// model, channels [{name, t_ref, coeff, coeff_sigma, coeff_units,
/// covariance, r2, residual_rms, order}], unit, samples.
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/calibrate_temperature.hpp"

namespace cubecal::pipeline {

/// The calibration as JSON. Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const TemperatureResult& r);
/// The result that to_json wrote.
TemperatureResult temperature_result_from_json(const nlohmann::json& j);

}  // namespace cubecal::pipeline
