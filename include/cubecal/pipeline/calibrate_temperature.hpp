/// @file
/// `calibrate temperature` as one call: a record with a temperature column
/// (already read) and the request in, the polynomial bias(T) of every channel
/// with the covariance of its coefficients out, in the form a flight computer
/// applies: corrected = raw - sum_{p>=1} c_p (T - t_ref)^p. JSON form:
/// calibrate_temperature_json.hpp.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/temperature.hpp"

namespace cubecal::pipeline {

/// What `calibrate temperature` is asked to do (the record already read).
struct TemperatureRequest {
  std::size_t order = 1;        ///< of the polynomial, 1 to 5
  std::string unit = "counts";  ///< of the channels, for the coefficient units
  std::size_t temp_index = 0;   ///< index into Series::extra of the temperature (degC)

  /// A UsageError naming the field at fault: an order outside 1 to 5, more
  /// than one unit.
  void validate() const;
};

/// The temperature model of one channel.
struct TemperatureChannel {
  /// The channel's name.
  std::string name;
  std::vector<std::string> coeff_units;  ///< "unit", "unit/degC", "unit/degC^2", ...
  /// The fit (coefficients in coeff_units).
  TemperatureFit fit;
};

/// A temperature calibration of every channel of a record.
struct TemperatureResult {
  /// The input's path, as given.
  std::string file;
  /// The temperature column's name.
  std::string temperature_column;
  /// Order of the polynomial (1 to 5).
  std::size_t order = 1;
  /// The channels' unit.
  std::string unit = "counts";
  /// Samples per channel.
  std::size_t samples = 0;
  /// One per channel, in the record's order.
  std::vector<TemperatureChannel> channels;
};

/// Throws UsageError ("polynomial_order": order out of 1..5; "temp_index": no such
/// extra column); a channel the fit cannot use throws UsageError (or the
/// core's CalibrationError) with the channel's name in front of the message.
TemperatureResult calibrate_temperature(const io::Series& series, const TemperatureRequest& request);

}  // namespace cubecal::pipeline
