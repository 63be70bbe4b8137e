// A result's JSON value (the pipeline's to_json) as the Python objects
// json.loads gives for its text: dict, list, str, int, float, bool, None.
// Built from the value itself, without writing and parsing the text.
#pragma once
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <utility>

namespace cubecal::python {

// Needs the GIL. A non-finite number is None, as the text writes it (null).
pybind11::object to_python(const nlohmann::json& j);

// A binding of f, which returns a JSON value, that returns its Python
// objects (f may release the GIL inside; the objects are made after it).
template <class... Args>
auto returning_python(nlohmann::json (*f)(Args...)) {
  return [f](Args... args) { return to_python(f(std::forward<Args>(args)...)); };
}

}  // namespace cubecal::python
