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
/// nlohmann's convention: j.get<TemperatureResult>() calls it.
void from_json(const nlohmann::json& j, TemperatureResult& r);

}  // namespace cubecal::pipeline
