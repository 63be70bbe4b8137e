// The library's error types as Python exceptions (cubecal.Error and its
// subclasses), mapped by type as the CLI maps them to its one-line messages.
#pragma once
#include <pybind11/pybind11.h>

#include <string>
#include <string_view>
#include <utility>

#include "cubecal/error.hpp"

namespace cubecal::python {

// A UsageError on an argument only Python has (the arrays passed in, a
// profile given as a string): `argument` is its keyword, raised as the
// UsageError's .option.
class ArgumentError : public UsageError {
 public:
  ArgumentError(std::string argument, const std::string& what) : UsageError(what), argument_(std::move(argument)) {}
  const std::string& argument() const noexcept { return argument_; }

 private:
  std::string argument_;
};

// The keyword of a Python function that sets `f` (its name, but for the
// arguments named as the CLI's options: lsb, reject, columns).
std::string_view python_keyword(Field f) noexcept;

// `text` (a library message with field markers) in Python's words: a field
// as its keyword, `stream=`.
std::string python_words(const std::string& text);

// Defines cubecal.Error (a ValueError), cubecal.InputError (file, line,
// column, problem, hint), cubecal.UsageError (option) and
// cubecal.CalibrationError (reason), and registers their translation.
void bind_errors(pybind11::module_& m);

}  // namespace cubecal::python
