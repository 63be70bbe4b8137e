#include "cubecal/pipeline/calibrate_temperature.hpp"

#include <stdexcept>

#include "cubecal/error.hpp"

namespace cubecal::pipeline {

void TemperatureRequest::validate() const {
  if (order < 1 || order > 5)
    throw UsageError(Field::order, "{order}: the polynomial order is 1 to 5", UsageError::Named::in_text);
  if (unit.find(',') != std::string::npos)
    throw UsageError(Field::unit,
                     "one unit here, the unit of the coefficients of every channel: calibrate the channels "
                     "of each unit in their own run ({columns})");
}

TemperatureResult calibrate_temperature(const io::Series& s, const TemperatureRequest& req) {
  req.validate();
  if (req.temp_index >= s.extra.size()) throw UsageError(Field::temp_index, "the temperature column was not read");
  const auto& temp = s.extra[req.temp_index];
  TemperatureResult r;
  r.file = s.file;
  r.temperature_column = req.temp_index < s.extra_names.size() ? s.extra_names[req.temp_index] : std::string();
  r.order = req.order;
  r.unit = req.unit;
  r.samples = s.samples();
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    TemperatureChannel ch;
    ch.name = c < s.names.size() ? s.names[c] : "col" + std::to_string(c + 1);
    try {
      ch.fit = fit_temperature(s.channels[c], temp, req.order);
    } catch (const CalibrationError& e) {
      throw CalibrationError(e.reason(), ch.name + ": " + e.text());
    } catch (const std::invalid_argument& e) {
      throw UsageError(ch.name + ": " + e.what());
    }
    for (std::size_t p = 0; p < ch.fit.coeff.size(); ++p)
      ch.coeff_units.push_back(p == 0 ? req.unit : req.unit + (p == 1 ? "/degC" : "/degC^" + std::to_string(p)));
    r.channels.push_back(std::move(ch));
  }
  return r;
}

}  // namespace cubecal::pipeline
