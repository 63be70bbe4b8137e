/// @file
/// The JSON form of a `cubecal model` result (what `model --format json`
/// prints): {command: "model", file, rate_hz, samples, model, ci, bootstrap,
/// seed, channels [{name, unit (null when none was given), objective,
/// converged, replicates, terms [{term ("WN", "QN", "RW", "DR", "GM"),
/// parameters {value (sigma2, Q2, gamma2 or omega per sample), phi (GM)},
/// quantities [{name, value, unit, sd, lo, hi, display {value, sigma, lo,
/// hi, unit}}]}], wavelet_variance {tau_samples [], tau_s [], nu2 [], lo [], hi [],
/// edf [], n [], model []}}]}. sd, lo, hi are null without a bootstrap.
#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "cubecal/pipeline/model_fit.hpp"

namespace cubecal::pipeline {

/// `cubecal model --format json`: the result as JSON. Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const ModelResult& r);
/// One channel of it (channels[i]); analysis.json carries the same as
/// channels[i].model.composite (analyze --composite). sd, lo and hi are
/// written when `bootstrapped`, null otherwise.
nlohmann::json to_json(const ModelChannel& c, double rate_hz, bool bootstrapped);

/// The inverses (model_fit_json_read.cpp), for `simulate --model model.json`
/// and analysis.json: what to_json wrote, read back (the weights' standard
/// deviations, GmwmFit::sd, are not written and come back empty). `where`
/// (the file) and `path` (the place in the document) start every message;
/// a document without a key it needs is a UsageError naming the key.
ModelResult model_result_from_json(const nlohmann::json& j, const std::string& where);
/// One channel, as to_json(const ModelChannel&, double, bool) wrote it;
/// `path` is its place in the document ("channels[0]"). Throws UsageError as
/// model_result_from_json does.
ModelChannel model_channel_from_json(const nlohmann::json& j, const std::string& where, const std::string& path);

}  // namespace cubecal::pipeline
