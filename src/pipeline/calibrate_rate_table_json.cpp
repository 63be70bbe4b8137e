#include <numbers>
#include <string>

#include "detail/matrix_json.hpp"
#include "cubecal/pipeline/calibrate_rate_table_json.hpp"

namespace cubecal::pipeline {

namespace {

constexpr const char* kAxes = "xyz";
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// Off-diagonal angles keyed "xy" (axis x leaning toward y), in `scale` units.
nlohmann::json angles_json(const Mat3& m, double scale) {
  nlohmann::json j = nlohmann::json::object();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      if (i != k) j[std::string{kAxes[i], kAxes[k]}] = m[i][k] * scale;
  return j;
}

std::array<double, 3> scaled(const std::array<double, 3>& v, double s) { return {v[0] * s, v[1] * s, v[2] * s}; }

nlohmann::json plateau_json(const Plateau& p) {
  return {{"begin", p.begin}, {"end", p.end},        {"t_begin", p.t_begin}, {"t_end", p.t_end},
          {"n", p.n},         {"gyro", p.mean},      {"gyro_std", p.stddev}, {"gyro_cov", p.cov},
          {"ref", p.ref},     {"has_ref", p.has_ref}};
}

Plateau plateau_of(const nlohmann::json& j) {
  Plateau p;
  p.begin = j.at("begin").get<std::size_t>();
  p.end = j.at("end").get<std::size_t>();
  p.t_begin = j.at("t_begin").get<double>();
  p.t_end = j.at("t_end").get<double>();
  p.n = j.at("n").get<std::size_t>();
  p.mean = j.at("gyro").get<std::array<double, 3>>();
  p.stddev = j.at("gyro_std").get<std::array<double, 3>>();
  p.cov = j.at("gyro_cov").get<Mat3>();
  p.ref = j.at("ref").get<std::array<double, 3>>();
  p.has_ref = j.at("has_ref").get<bool>();
  return p;
}

}  // namespace

nlohmann::json to_json(const RateTableResult& r) {
  const RateTableCalibration& c = r.calibration;
  const std::string& u = r.unit;
  nlohmann::json j;
  j["file"] = r.file;
  j["unit"] = u;
  j["model"] = "w = A w_g + beta (paper eq. 6); forward w_g = S w + b_g, A = S^-1, beta = -S^-1 b_g";
  j["A"] = c.A;
  j["A_sigma"] = c.A_sigma;
  j["beta"] = c.beta;
  j["beta_sigma"] = c.beta_sigma;
  j["inverse_cov"] = detail::to_json(c.inverse_cov);
  j["residual_before"] = {{"max", c.residual_before.max_abs}, {"rms", c.residual_before.rms}, {"unit", u}};
  j["residual_after"] = {{"max", c.residual_after.max_abs}, {"rms", c.residual_after.rms}, {"unit", u}};
  j["error_covariance"] = c.error_covariance;
  j["error_covariance_unit"] = "(" + u + ")^2";
  j["forward"] = {{"S", c.S},
                  {"S_sigma", c.S_sigma},
                  {"bias", c.bias},
                  {"bias_sigma", c.bias_sigma},
                  {"cov", detail::to_json(c.forward_cov)},
                  {"scale_factor_error", c.scale_factor_error},
                  {"scale_factor_error_sigma", c.scale_factor_error_sigma},
                  {"scale_factor_ppm", scaled(c.scale_factor_error, 1e6)},
                  {"scale_factor_ppm_sigma", scaled(c.scale_factor_error_sigma, 1e6)},
                  {"scale_factor_percent", scaled(c.scale_factor_error, 100.0)},
                  {"misalignment", c.misalignment},
                  {"misalignment_sigma", c.misalignment_sigma},
                  {"misalignment_mrad", angles_json(c.misalignment, 1e3)},
                  {"misalignment_mrad_sigma", angles_json(c.misalignment_sigma, 1e3)},
                  {"misalignment_deg", angles_json(c.misalignment, kRadToDeg)},
                  {"misalignment_convention",
                   "key ij: angle by which gyro axis i leans toward reference axis j, atan(S_ij / S_ii)"}};
  j["fit"] = {{"plateaus", c.plateaus},
              {"dof", c.dof},
              {"noise_from_residuals", c.noise_from_residuals},
              {"noise_cov", c.noise_cov},
              {"earth_rate", r.earth_rate}};
  j["plateau_source"] = std::string(to_string(r.source));
  j["plateaus_dropped_short"] = r.found.dropped_short;
  j["plateaus_unmatched"] = r.found.unmatched;
  j["detection"] = {{"skipped_rows", r.found.skipped_rows}, {"noise", r.found.noise}};
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < r.found.plateaus.size(); ++k) {
    nlohmann::json p = plateau_json(r.found.plateaus[k]);
    if (k < c.residuals_after.size()) p["residual_after"] = c.residuals_after[k];
    list.push_back(std::move(p));
  }
  j["plateaus"] = list;
  return j;
}

RateTableResult rate_table_result_from_json(const nlohmann::json& j) {
  RateTableResult r;
  r.file = j.at("file").get<std::string>();
  r.unit = j.at("unit").get<std::string>();
  r.source = parse_plateau_source(j.at("plateau_source").get<std::string>()).value_or(PlateauSource::reference);
  RateTableCalibration& c = r.calibration;
  c.A = j.at("A").get<Mat3>();
  c.A_sigma = j.at("A_sigma").get<Mat3>();
  c.beta = j.at("beta").get<std::array<double, 3>>();
  c.beta_sigma = j.at("beta_sigma").get<std::array<double, 3>>();
  c.inverse_cov = detail::matrix_from_json(j.at("inverse_cov"));
  c.residual_before = {j.at("residual_before").at("max").get<double>(),
                       j.at("residual_before").at("rms").get<double>()};
  c.residual_after = {j.at("residual_after").at("max").get<double>(), j.at("residual_after").at("rms").get<double>()};
  c.error_covariance = j.at("error_covariance").get<Mat3>();
  const auto& f = j.at("forward");
  c.S = f.at("S").get<Mat3>();
  c.S_sigma = f.at("S_sigma").get<Mat3>();
  c.bias = f.at("bias").get<std::array<double, 3>>();
  c.bias_sigma = f.at("bias_sigma").get<std::array<double, 3>>();
  c.forward_cov = detail::matrix_from_json(f.at("cov"));
  c.scale_factor_error = f.at("scale_factor_error").get<std::array<double, 3>>();
  c.scale_factor_error_sigma = f.at("scale_factor_error_sigma").get<std::array<double, 3>>();
  c.misalignment = f.at("misalignment").get<Mat3>();
  c.misalignment_sigma = f.at("misalignment_sigma").get<Mat3>();
  const auto& fit = j.at("fit");
  c.plateaus = fit.at("plateaus").get<std::size_t>();
  c.dof = fit.at("dof").get<std::size_t>();
  c.noise_from_residuals = fit.at("noise_from_residuals").get<bool>();
  c.noise_cov = fit.at("noise_cov").get<Mat3>();
  r.earth_rate = fit.at("earth_rate").get<std::array<double, 3>>();
  r.found.dropped_short = j.at("plateaus_dropped_short").get<std::size_t>();
  r.found.unmatched = j.at("plateaus_unmatched").get<std::size_t>();
  r.found.skipped_rows = j.at("detection").at("skipped_rows").get<std::size_t>();
  r.found.noise = j.at("detection").at("noise").get<std::array<double, 3>>();
  for (const auto& p : j.at("plateaus")) {
    r.found.plateaus.push_back(plateau_of(p));
    if (p.contains("residual_after")) c.residuals_after.push_back(p["residual_after"].get<std::array<double, 3>>());
  }
  return r;
}

}  // namespace cubecal::pipeline
