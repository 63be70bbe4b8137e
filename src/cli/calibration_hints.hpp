// What the CLI tells a user to do when a calibration cannot be done with the
// data given: one hint per command and CalibrationReason, in the command's
// flags. The only place that maps reasons to advice; never by message text.
#pragma once
#include <string>
#include <vector>

#include "cubecal/error.hpp"

namespace cubecal::cli {

enum class CalibrationCommand { rate_table, mag, multiposition, temperature, model, composite };

// The facts of the run a hint depends on.
struct HintContext {
  CalibrationCommand command = CalibrationCommand::rate_table;
  bool reference_columns = false;  // rate-table: plateaus from --ref-columns (else a schedule)
  bool bias_only = false;          // mag: --method twostep
  bool field_col = false;          // mag: --field-col given
  bool gyroscope = false;          // multiposition: the gyroscope step (else the accelerometer's)
};

// Empty when there is nothing better to say than the message.
std::string calibration_hint(CalibrationReason reason, const HintContext& ctx);

// A given field norm far (over 4x either way) from the data's own field
// magnitude, taken as the largest half 5-95 % range of an axis after --lsb
// (about the radius of the points' sphere, whatever the hard-iron offset and
// a few outliers): says so and
// asks whether both are in the same unit. Empty when they are comparable.
std::string field_norm_warning(double field_norm, const std::vector<std::vector<double>>& xyz, double lsb);

// Runs `f`; a CalibrationError becomes InputError(file, "what (hint)"), a
// plain std::invalid_argument InputError(file, "what") without a hint.
template <class F>
decltype(auto) with_calibration_hints(const std::string& file, const HintContext& ctx, F&& f) {
  try {
    return f();
  } catch (const CalibrationError& e) {
    throw InputError(file, 0, 0, e.text(), calibration_hint(e.reason(), ctx));
  } catch (const std::invalid_argument& e) {
    throw InputError(file, 0, 0, e.what());
  }
}

}  // namespace cubecal::cli
