// NumPy arrays in and out of the library without copies where the layout
// allows: a C-contiguous float64 array is read in place (any other dtype or
// layout is converted once by NumPy), and a result vector becomes the
// buffer of the array returned (moved, not copied).
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "errors.hpp"

namespace cubecal::python {

namespace py = pybind11;

// forcecast: ints and float32 are accepted and converted; a contiguous
// float64 array passes through untouched.
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A 1-D view of the array given for the argument `keyword`; an
// ArgumentError (cubecal.UsageError naming it) for another shape.
inline std::span<const double> view(const Doubles& a, const std::string& keyword) {
  if (a.ndim() != 1)
    throw ArgumentError(keyword,
                        keyword + ": a 1-D array is expected, got " + std::to_string(a.ndim()) + " dimensions");
  return {a.data(), static_cast<std::size_t>(a.shape(0))};
}

// The vector's storage as a NumPy array that owns it.
template <class T>
py::array_t<T> to_array(std::vector<T>&& v) {
  auto* owner = new std::vector<T>(std::move(v));
  py::capsule free_when_done(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(owner->size())}, {static_cast<py::ssize_t>(sizeof(T))}, owner->data(),
                        free_when_done);
}

}  // namespace cubecal::python
