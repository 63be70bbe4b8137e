// What the CLI tells a user to do when a calibration cannot be done with the
// data given: one hint per command and CalibrationReason, in the command's
// flags. The only place that maps reasons to advice; never by message text.
#pragma once
#include <string>

#include "cubecal/error.hpp"

namespace cubecal::cli {

enum class CalibrationCommand { rate_table, mag, multiposition, temperature };

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

// Runs `f`; a CalibrationError becomes InputError(file, "what (hint)"), a
// plain std::invalid_argument InputError(file, "what") without a hint.
template <class F>
decltype(auto) with_calibration_hints(const std::string& file, const HintContext& ctx, F&& f) {
  try {
    return f();
  } catch (const CalibrationError& e) {
    throw InputError(file, 0, 0, e.what(), calibration_hint(e.reason(), ctx));
  } catch (const std::invalid_argument& e) {
    throw InputError(file, 0, 0, e.what());
  }
}

}  // namespace cubecal::cli
