// cubecal._Realtime: the library's RealtimeDeviation (OADEV, OHDEV, TDEV
// updated sample by sample), behind cubecal.realtime's AllanTools-shaped
// classes (python/cubecal/realtime.py). A sample is one call; an array of
// samples is one call too, its loop in C++.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "errors.hpp"
#include "cubecal/stats/realtime_deviation.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

Stat realtime_stat(const std::string& name) {
  if (name == "oadev") return Stat::oadev;
  if (name == "ohdev") return Stat::ohdev;
  if (name == "tdev") return Stat::tdev;
  throw ArgumentError("stat", "stat: \"oadev\", \"ohdev\" or \"tdev\" is expected, not '" + name + "'");
}

// A finite sample, or an ArgumentError naming the keyword and its index in
// the record.
void check_finite(double v, std::size_t index, const std::string& keyword) {
  if (!std::isfinite(v))
    throw ArgumentError(keyword, keyword + ": sample " + std::to_string(index) +
                                     " of the record is not a finite number; leave it out or fill it in");
}

void add_phase(RealtimeDeviation& rt, double x) {
  check_finite(x, rt.samples(), "xnew");
  rt.add_phase(x);
}

// AllanTools' integration: the first frequency sample also puts the
// phase origin, 0.
void add_frequency(RealtimeDeviation& rt, double f, double step) {
  const std::size_t index = rt.samples() == 0 ? 0 : rt.samples() - 1;
  check_finite(f, index, "f");
  const double x = rt.last_phase() + f * step;
  if (!std::isfinite(x))
    throw ArgumentError(
        "f", "f: the phase integrated up to frequency sample " + std::to_string(index) + " overflows; scale the data");
  if (rt.samples() == 0) rt.add_phase(0.0);
  rt.add_phase(x);
}

py::array_t<double> deviations(const RealtimeDeviation& rt, double tau0) {
  std::vector<double> d(rt.factors().size());
  for (std::size_t j = 0; j < d.size(); ++j) d[j] = rt.deviation(j, tau0);
  return to_array(std::move(d));
}

py::array_t<std::int64_t> terms(const RealtimeDeviation& rt) {
  std::vector<std::int64_t> n(rt.factors().size());
  for (std::size_t j = 0; j < n.size(); ++j) n[j] = static_cast<std::int64_t>(rt.terms(j));
  return to_array(std::move(n));
}

py::array_t<std::int64_t> factors(const RealtimeDeviation& rt) {
  std::vector<std::int64_t> m(rt.factors().begin(), rt.factors().end());
  return to_array(std::move(m));
}

}  // namespace

void bind_realtime(py::module_& m) {
  py::class_<RealtimeDeviation>(m, "_Realtime",
                                "RealtimeDeviation: OADEV, OHDEV or TDEV updated sample by sample "
                                "(use cubecal.realtime)")
      .def(py::init([](const std::string& stat, const std::vector<std::size_t>& ms, bool keep_all) {
             for (std::size_t f : ms)
               if (f == 0)
                 throw ArgumentError("afs", "afs: every averaging factor must be a whole number of at least 1");
             return RealtimeDeviation(realtime_stat(stat), ms, keep_all);
           }),
           py::arg("stat"), py::arg("factors"), py::arg("keep_all"))
      .def("add_phase", &add_phase, py::arg("x"))
      .def(
          "add_phases",
          [](RealtimeDeviation& rt, const Doubles& x) {
            for (double v : view(x, "xnew")) add_phase(rt, v);
          },
          py::arg("x"))
      .def("add_frequency", &add_frequency, py::arg("f"), py::arg("step"))
      .def(
          "add_frequencies",
          [](RealtimeDeviation& rt, const Doubles& f, double step) {
            for (double v : view(f, "f")) add_frequency(rt, v, step);
          },
          py::arg("f"), py::arg("step"))
      .def(
          "add_factor",
          [](RealtimeDeviation& rt, std::size_t af) {
            if (af == 0) throw ArgumentError("afs", "afs: every averaging factor must be a whole number of at least 1");
            rt.add_factor(af);
          },
          py::arg("m"))
      .def_property_readonly("samples", &RealtimeDeviation::samples)
      .def_property_readonly("factors", &factors)
      .def_property_readonly("terms", &terms)
      .def("deviations", &deviations, py::arg("tau0"));
}

}  // namespace cubecal::python
