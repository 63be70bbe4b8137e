// The pieces of the extension module cubecal._cubecal, one per face of the
// library; module.cpp puts them together.
#pragma once
#include <pybind11/pybind11.h>

namespace cubecal::python {

void bind_stats(pybind11::module_& m);
void bind_analyze(pybind11::module_& m);
void bind_simulate(pybind11::module_& m);
void bind_read(pybind11::module_& m);
void bind_calibrate(pybind11::module_& m);
void bind_spectral(pybind11::module_& m);
void bind_model(pybind11::module_& m);
void bind_noise(pybind11::module_& m);
void bind_realtime(pybind11::module_& m);
void bind_allantools_kernels(pybind11::module_& m);
void bind_ci(pybind11::module_& m);
void bind_plan(pybind11::module_& m);

}  // namespace cubecal::python
