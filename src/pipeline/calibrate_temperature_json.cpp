#include "detail/matrix_json.hpp"
#include "cubecal/pipeline/calibrate_temperature_json.hpp"

#include <string>

namespace cubecal::pipeline {

nlohmann::json to_json(const TemperatureResult& r) {
  nlohmann::json j;
  j["file"] = r.file;
  j["temperature_column"] = r.temperature_column;
  j["order"] = r.order;
  j["unit"] = r.unit;
  j["samples"] = r.samples;
  j["model"] = "bias(T) = sum_p coeff[p] (T - t_ref)^p; corrected = raw - sum_{p>=1} coeff[p] (T - t_ref)^p";
  for (const auto& c : r.channels)
    j["channels"].push_back({{"name", c.name},
                             {"t_ref", c.fit.t_ref},
                             {"coeff", c.fit.coeff},
                             {"coeff_sigma", c.fit.coeff_sigma},
                             {"coeff_units", c.coeff_units},
                             {"covariance", detail::to_json(c.fit.cov)},
                             {"r2", c.fit.r2},
                             {"residual_rms", c.fit.residual_rms},
                             {"order", c.fit.order}});
  return j;
}

TemperatureResult temperature_result_from_json(const nlohmann::json& j) {
  TemperatureResult r;
  r.file = j.at("file").get<std::string>();
  r.temperature_column = j.at("temperature_column").get<std::string>();
  r.order = j.at("order").get<std::size_t>();
  r.unit = j.at("unit").get<std::string>();
  r.samples = j.at("samples").get<std::size_t>();
  if (!j.contains("channels")) return r;
  for (const auto& c : j["channels"]) {
    TemperatureChannel ch;
    ch.name = c.at("name").get<std::string>();
    ch.coeff_units = c.at("coeff_units").get<std::vector<std::string>>();
    ch.fit.t_ref = c.at("t_ref").get<double>();
    ch.fit.coeff = c.at("coeff").get<std::vector<double>>();
    ch.fit.coeff_sigma = c.at("coeff_sigma").get<std::vector<double>>();
    ch.fit.cov = detail::matrix_from_json(c.at("covariance"));
    ch.fit.r2 = c.at("r2").get<double>();
    ch.fit.residual_rms = c.at("residual_rms").get<double>();
    ch.fit.order = c.at("order").get<std::size_t>();
    r.channels.push_back(std::move(ch));
  }
  return r;
}

}  // namespace cubecal::pipeline
