// The library's error types as Python exceptions (cubecal.Error and its
// subclasses), mapped by type as the CLI maps them to its one-line messages.
#pragma once
#include <pybind11/pybind11.h>

namespace cubecal::python {

// Defines cubecal.Error (a ValueError), cubecal.InputError (file, line,
// column, problem, hint), cubecal.UsageError (option) and
// cubecal.CalibrationError (reason), and registers their translation.
void bind_errors(pybind11::module_& m);

}  // namespace cubecal::python
