/// @file
/// The JSON form of a magnetometer calibration (what `calibrate mag --format
/// json` prints, without the invocation), and back. Keys: file, method, model,
/// unit, bias(_sigma), soft_iron(_sigma, _unit), field_norm(_source),
/// norm_error_before/after {mean, rms, max, unit}, chi2, dof, p_value, noise,
/// noise_estimated, points, points_total, rejected, reject_sigma,
/// rejected_lines, iterations, converged, semi_axes, axis_ratio, coverage
/// {...}, covariance {names, matrix}, notes; and what mag_result_from_json needs besides
/// (eta, field_norm_default, field_norm_per_point, first_data_line,
/// coverage.centre_from_sphere_fit). The input points and per-point field
/// norms are the input file's content and are not written: mag_result_from_json leaves
/// the points and the field norms of a MagResult empty.
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/calibrate_mag.hpp"

namespace cubecal::pipeline {

/// The calibration as JSON (keys above). Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const MagResult& r);
/// The result that to_json wrote.
MagResult mag_result_from_json(const nlohmann::json& j);

}  // namespace cubecal::pipeline
