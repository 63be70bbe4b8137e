// A result's JSON value (the pipeline's to_json) as Python objects, built
// from the value itself, without writing and parsing the text.
#pragma once
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <utility>

namespace cubecal::python {

// The objects json.loads gives for its text: dict, list, str, int, float,
// bool, None. Needs the GIL. A non-finite number is None, as the text writes
// it (null).
pybind11::object to_python(const nlohmann::json& j);

// As to_python, but every array of numbers is a read-only NumPy array made
// here in one pass over the value: int64 when every element is an integer,
// else float64 with null (and a non-finite number) as NaN; an array of
// booleans is a bool array; an array of such arrays of one length and kind
// (a matrix) is a 2-D array. Arrays of anything else (strings, objects, only
// nulls, nothing) stay lists. The typed results (cubecal/_result.py) are
// made of these objects; their to_dict() turns the arrays back into the
// lists json.loads gives (NaN as None).
pybind11::object to_python_arrays(const nlohmann::json& j);

// A binding of f, which returns a JSON value, that returns its Python
// objects with NumPy arrays (f may release the GIL inside; the objects are
// made after it).
template <class... Args>
auto returning_python(nlohmann::json (*f)(Args...)) {
  return [f](Args... args) { return to_python_arrays(f(std::forward<Args>(args)...)); };
}

}  // namespace cubecal::python
