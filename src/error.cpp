// The error types (error.hpp). One-line error messages in the compiler style "FILE:LINE:COL: problem (hint)"
// so that editors and terminals can jump to the offending field; printable (printable_text.hpp), since
// they quote file contents.
#include "cubecal/error.hpp"

#include <utility>

#include "cubecal/printable_text.hpp"

namespace cubecal {

namespace {

std::string format_message(const std::string& file, std::size_t line, std::size_t column, const std::string& problem,
                           const std::string& hint) {
  std::string msg = file;
  // A column without a line cannot be located, so it is dropped with it.
  if (line != 0) {
    msg += ':';
    msg += std::to_string(line);
    if (column != 0) {
      msg += ':';
      msg += std::to_string(column);
    }
  }
  msg += ": ";
  msg += problem;
  if (!hint.empty()) {
    msg += " (";
    msg += hint;
    msg += ')';
  }
  return printable_text(msg);
}

}  // namespace

InputError::InputError(std::string file, std::size_t line, std::size_t column, std::string what, std::string hint)
    : Error(format_message(file, line, column, what, hint)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      problem_(std::move(what)),
      hint_(std::move(hint)) {}

std::string_view to_string(CalibrationReason r) noexcept {
  switch (r) {
    case CalibrationReason::too_few_points: return "too_few_points";
    case CalibrationReason::poor_coverage: return "poor_coverage";
    case CalibrationReason::degenerate: return "degenerate";
    case CalibrationReason::bad_data: return "bad_data";
    case CalibrationReason::bad_option: return "bad_option";
    case CalibrationReason::field_norm: return "field_norm";
    case CalibrationReason::no_plateaus: return "no_plateaus";
    case CalibrationReason::too_few_intervals: return "too_few_intervals";
    case CalibrationReason::initial_static: return "initial_static";
    case CalibrationReason::scale_guess: return "scale_guess";
    case CalibrationReason::not_converged: return "not_converged";
  }
  return "unknown";
}

}  // namespace cubecal
