// `calibrate temperature` as one call: a record with a temperature column
// (already read) and the request in, the polynomial bias(T) of every channel
// with the covariance of its coefficients out, in the form a flight computer
// applies: corrected = raw - sum_{p>=1} c_p (T - t_ref)^p. JSON form:
// calibrate_temperature_json.hpp.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/temperature.hpp"

namespace cubecal::pipeline {

struct TemperatureRequest {
  std::size_t order = 1;        // of the polynomial, 1 to 5
  std::string unit = "counts";  // of the channels, for the coefficient units
  std::size_t temp_index = 0;   // index into Series::extra of the temperature (degC)

  // A UsageError naming the field at fault: an order outside 1 to 5, more
  // than one unit.
  void validate() const;
};

struct TemperatureChannel {
  std::string name;
  std::vector<std::string> coeff_units;  // "unit", "unit/degC", "unit/degC^2", ...
  TemperatureFit fit;
};

struct TemperatureResult {
  std::string file;
  std::string temperature_column;
  std::size_t order = 1;
  std::string unit = "counts";
  std::size_t samples = 0;
  std::vector<TemperatureChannel> channels;
};

// Throws UsageError ("polynomial_order": order out of 1..5; "temp_index": no such
// extra column); a channel the fit cannot use throws UsageError (or the
// core's CalibrationError) with the channel's name in front of the message.
TemperatureResult calibrate_temperature(const io::Series& series, const TemperatureRequest& request);

}  // namespace cubecal::pipeline
