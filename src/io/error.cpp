// One-line error messages in the compiler style "FILE:LINE:COL: problem (hint)"
// so that editors and terminals can jump to the offending field.
#include "cubecal/io/error.hpp"

#include <utility>

namespace cubecal::io {

namespace {

std::string format_message(const std::string& file, std::size_t line, std::size_t column,
                           const std::string& problem, const std::string& hint) {
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
  return msg;
}

}  // namespace

InputError::InputError(std::string file, std::size_t line, std::size_t column, std::string what,
                       std::string hint)
    : std::runtime_error(format_message(file, line, column, what, hint)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      problem_(std::move(what)),
      hint_(std::move(hint)) {}

}  // namespace cubecal::io
