/// @file
/// The JSON form of the runs commands (what `turnon --format json` and
/// `compare --format json` print), and back. A run: {file, samples, rate_hz,
/// channels [{name, unit, mean, arw, bias_instability, time_constant_s (in
/// display units, null when not read), adev {tau, dev, lo, hi, m, n, edf,
/// alpha}, stddev, unit_si, readoffs (the raw read-offs)}]}. Turn-on: {ci,
/// runs, channels [{name, unit, mean_bias, turn_on_bias, turn_on_bias_lo,
/// turn_on_bias_hi}]}. Compare: {runs}.
#pragma once
#include <nlohmann/json.hpp>
#include <vector>

#include "cubecal/pipeline/turnon.hpp"

namespace cubecal::pipeline {

/// One run's summary as JSON. Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const RunSummary& r);
/// `cubecal turnon --format json`: the result as JSON. Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const TurnOnResult& t);
nlohmann::json to_json(const std::vector<RunSummary>& compared);  ///< {"runs": [...]}
/// The results that to_json wrote; a compare document's runs are
/// run_summary_from_json of each element of j.at("runs").
RunSummary run_summary_from_json(const nlohmann::json& j);
/// The TurnOnResult that to_json(const TurnOnResult&) wrote. A missing key or
/// a value of the wrong type throws the JSON library's exception
/// (nlohmann::json::out_of_range, type_error), no cubecal::Error.
TurnOnResult turn_on_result_from_json(const nlohmann::json& j);

}  // namespace cubecal::pipeline
