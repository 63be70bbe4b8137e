// cubecal._cubecal: the library's calls on NumPy arrays. The public
// interface is the pure-Python package around it (python/cubecal/).
#include <pybind11/pybind11.h>

#include "errors.hpp"
#include "module.hpp"

PYBIND11_MODULE(_cubecal, m) {
  m.doc() = "cubecal's C++ library on NumPy arrays (use the cubecal package, not this module)";
  m.attr("__version__") = CUBECAL_VERSION;
  cubecal::python::bind_errors(m);
  cubecal::python::bind_stats(m);
  cubecal::python::bind_analyze(m);
  cubecal::python::bind_simulate(m);
  cubecal::python::bind_read(m);
  cubecal::python::bind_calibrate(m);
  cubecal::python::bind_spectral(m);
  cubecal::python::bind_model(m);
  cubecal::python::bind_noise(m);
  cubecal::python::bind_realtime(m);
  cubecal::python::bind_allantools_kernels(m);
  cubecal::python::bind_ci(m);
  cubecal::python::bind_plan(m);
}
