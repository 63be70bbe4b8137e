// The JSON form of a `cubecal model` result (what `model --format json`
// prints): {command: "model", file, rate_hz, samples, model, ci, bootstrap,
// seed, channels [{name, unit (null when none was given), objective,
// converged, replicates, terms [{term ("WN", "QN", "RW", "DR", "GM"),
// parameters {value (sigma2, Q2, gamma2 or omega per sample), phi (GM)},
// quantities [{name, value, unit, sd, lo, hi, display {value, sigma, lo,
// hi, unit}}]}], wavelet_variance {tau_samples [], tau_s [], nu2 [], lo [], hi [],
// edf [], n [], model []}}]}. sd, lo, hi are null without a bootstrap.
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/model_fit.hpp"

namespace cubecal::pipeline {

nlohmann::json to_json(const ModelResult& r);

}  // namespace cubecal::pipeline
