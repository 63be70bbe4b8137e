/// @file
/// The JSON form of a rate-table calibration (what `calibrate rate-table
/// --format json` prints, without the invocation), and back. Keys: file, unit,
/// model, A, A_sigma, beta, beta_sigma, residual_before/after {max, rms,
/// unit}, error_covariance(_unit), forward {S, S_sigma, bias, bias_sigma,
/// scale_factor_ppm(_sigma), scale_factor_percent, misalignment_mrad(_sigma),
/// misalignment_deg, ...}, fit {plateaus, dof, noise_from_residuals,
/// noise_cov, earth_rate}, plateau_source, plateaus_dropped_short,
/// plateaus_unmatched, plateaus [...]; and the exact values behind the scaled
/// ones (inverse_cov, forward.cov, forward.scale_factor_error(_sigma),
/// forward.misalignment(_sigma) in rad, detection {...}) so that
/// rate_table_result_from_json(to_json(r)) gives r back.
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/calibrate_rate_table.hpp"

namespace cubecal::pipeline {

/// The calibration as JSON (keys above). Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const RateTableResult& r);
/// The result that to_json wrote.
RateTableResult rate_table_result_from_json(const nlohmann::json& j);

}  // namespace cubecal::pipeline
