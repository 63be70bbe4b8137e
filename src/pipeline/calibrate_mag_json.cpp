#include "detail/matrix_json.hpp"
#include "cubecal/pipeline/calibrate_mag_json.hpp"

#include <string>

namespace cubecal::pipeline {

namespace {

nlohmann::json norm_json(const mag::NormError& e, const std::string& unit) {
  return {{"mean", e.mean}, {"rms", e.rms}, {"max", e.max}, {"unit", unit}};
}

mag::NormError norm_of(const nlohmann::json& j) {
  return {j.at("mean").get<double>(), j.at("rms").get<double>(), j.at("max").get<double>()};
}

}  // namespace

nlohmann::json to_json(const MagResult& m) {
  const mag::Result& r = m.calibration;
  nlohmann::json j;
  j["file"] = m.file;
  j["method"] = std::string(mag::to_string(r.method));
  j["model"] = "h_cal = soft_iron * (h - bias), |h_cal| = field_norm";
  j["unit"] = m.unit;
  j["bias"] = r.bias;
  j["bias_sigma"] = r.bias_sigma;
  j["soft_iron"] = r.soft_iron;
  j["soft_iron_sigma"] = r.soft_iron_sigma;
  j["soft_iron_unit"] = "1";
  j["field_norm"] = r.field_norm;
  j["field_norm_source"] = std::string(to_string(m.field_source));
  j["field_norm_default"] = r.field_norm_default;
  j["field_norm_per_point"] = r.field_norm_per_point;
  j["norm_error_before"] = norm_json(r.before, m.unit);
  j["norm_error_after"] = norm_json(r.after, m.unit);
  j["chi2"] = r.chi2;
  j["dof"] = r.dof;
  j["p_value"] = r.p_value ? nlohmann::json(*r.p_value) : nlohmann::json(nullptr);
  j["noise"] = r.noise;
  j["noise_estimated"] = r.noise_estimated;
  j["points"] = r.points_used;
  j["points_total"] = m.points.size();
  j["rejected"] = r.points_rejected;
  j["reject_sigma"] = r.reject_sigma;
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t k : r.rejected) lines.push_back(m.first_data_line + k);
  j["rejected_lines"] = lines;
  nlohmann::json gross = nlohmann::json::array();
  for (std::size_t k : r.rejected_gross) gross.push_back(m.first_data_line + k);
  j["rejected_gross_lines"] = gross;
  j["first_data_line"] = m.first_data_line;
  j["iterations"] = r.iterations;
  j["converged"] = r.converged;
  j["eta"] = r.eta;
  j["semi_axes"] = r.semi_axes;
  j["axis_ratio"] = r.axis_ratio;
  j["coverage"] = {{"centre", r.coverage.centre},       {"centre_from_sphere_fit", r.coverage.centre_from_sphere_fit},
                   {"resultant", r.coverage.resultant}, {"lambda_min", r.coverage.lambda_min},
                   {"spread", r.coverage.spread},       {"octants", r.coverage.octants}};
  j["covariance"] = {{"names", r.covariance_names}, {"matrix", detail::to_json(r.covariance)}};
  j["notes"] = r.notes;
  return j;
}

MagResult mag_result_from_json(const nlohmann::json& j) {
  MagResult m;
  m.file = j.at("file").get<std::string>();
  m.unit = j.at("unit").get<std::string>();
  m.field_source =
      parse_field_norm_source(j.at("field_norm_source").get<std::string>()).value_or(FieldNormSource::mean_raw_norm);
  m.first_data_line = j.at("first_data_line").get<std::size_t>();
  mag::Result& r = m.calibration;
  r.method = mag::parse_method(j.at("method").get<std::string>()).value_or(mag::Method::ellipsoid);
  r.bias = j.at("bias").get<Vec3>();
  r.bias_sigma = j.at("bias_sigma").get<Vec3>();
  r.soft_iron = j.at("soft_iron").get<Mat3>();
  r.soft_iron_sigma = j.at("soft_iron_sigma").get<Mat3>();
  r.field_norm = j.at("field_norm").get<double>();
  r.field_norm_default = j.at("field_norm_default").get<bool>();
  r.field_norm_per_point = j.at("field_norm_per_point").get<bool>();
  r.before = norm_of(j.at("norm_error_before"));
  r.after = norm_of(j.at("norm_error_after"));
  r.chi2 = j.at("chi2").get<double>();
  r.dof = j.at("dof").get<std::size_t>();
  if (!j.at("p_value").is_null()) r.p_value = j["p_value"].get<double>();
  r.noise = j.at("noise").get<double>();
  r.noise_estimated = j.at("noise_estimated").get<bool>();
  r.points_used = j.at("points").get<std::size_t>();
  r.points_rejected = j.at("rejected").get<std::size_t>();
  r.reject_sigma = j.at("reject_sigma").get<double>();
  for (const auto& line : j.at("rejected_lines")) r.rejected.push_back(line.get<std::size_t>() - m.first_data_line);
  if (j.contains("rejected_gross_lines"))
    for (const auto& line : j.at("rejected_gross_lines"))
      r.rejected_gross.push_back(line.get<std::size_t>() - m.first_data_line);
  r.iterations = j.at("iterations").get<std::size_t>();
  r.converged = j.at("converged").get<bool>();
  r.eta = j.at("eta").get<double>();
  r.semi_axes = j.at("semi_axes").get<Vec3>();
  r.axis_ratio = j.at("axis_ratio").get<double>();
  const auto& c = j.at("coverage");
  r.coverage.centre = c.at("centre").get<Vec3>();
  r.coverage.centre_from_sphere_fit = c.at("centre_from_sphere_fit").get<bool>();
  r.coverage.resultant = c.at("resultant").get<double>();
  r.coverage.lambda_min = c.at("lambda_min").get<double>();
  r.coverage.spread = c.at("spread").get<Vec3>();
  r.coverage.octants = c.at("octants").get<std::size_t>();
  r.covariance_names = j.at("covariance").at("names").get<std::vector<std::string>>();
  r.covariance = detail::matrix_from_json(j.at("covariance").at("matrix"));
  r.notes = j.at("notes").get<std::vector<std::string>>();
  return m;
}

}  // namespace cubecal::pipeline
