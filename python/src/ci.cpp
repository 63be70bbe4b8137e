// cubecal.ci's numerics: the library's equivalent degrees of freedom
// (Greenhall & Riley's algorithm with its pieces, SP 1065's simple and total
// forms), chi-squared intervals and the published noise identification
// (lag-1 autocorrelation, B1 and R(n)), under private names that
// python/cubecal/ci.py wraps in AllanTools' signatures.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

// The interval of every dev with its edf (arrays of one length), at ci.
py::tuple intervals(const Doubles& dev, const Doubles& edf, double ci) {
  const auto d = view(dev, "dev");
  const auto e = view(edf, "edf");
  if (d.size() != e.size()) throw ArgumentError("edf", "edf: one value per dev is expected");
  std::vector<double> lo(d.size()), hi(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    const Interval iv = chi2_interval(d[i], e[i], ci);
    lo[i] = iv.lo;
    hi[i] = iv.hi;
  }
  return py::make_tuple(to_array(std::move(lo)), to_array(std::move(hi)));
}

py::object lag1_id(const Doubles& x, std::size_t af, bool phase, int dmin, int dmax) {
  const auto r = lag1_noise_id(view(x, "x"), af, phase ? DataType::phase : DataType::freq, dmin, dmax);
  if (!r) return py::none();
  return py::make_tuple(r->alpha_int, r->alpha, r->d, r->rho);
}

py::tuple greenhall_case(int alpha, int d, std::size_t m, std::size_t n, bool overlapping, bool modified) {
  const GreenhallEdf g = edf_greenhall_case(alpha, d, m, n, overlapping ? 1 : m, modified);
  return py::make_tuple(g.edf, std::string(g.method));
}

py::tuple coeffs(greenhall::Coeffs c) { return py::make_tuple(c.a0, c.a1); }

void bind_greenhall_pieces(py::module_& m) {
  m.def("_ci_greenhall_sw", &greenhall::sw, py::arg("t"), py::arg("alpha"));
  m.def("_ci_greenhall_sx", &greenhall::sx, py::arg("t"), py::arg("F"), py::arg("alpha"));
  m.def("_ci_greenhall_sz", &greenhall::sz, py::arg("t"), py::arg("F"), py::arg("alpha"), py::arg("d"));
  m.def("_ci_greenhall_basic_sum", &greenhall::basic_sum, py::arg("J"), py::arg("M"), py::arg("S"), py::arg("F"),
        py::arg("alpha"), py::arg("d"));
  m.def("_ci_greenhall_eq13", &greenhall::edf_eq13, py::arg("alpha"), py::arg("d"), py::arg("m"), py::arg("S"),
        py::arg("F"), py::arg("N"));
  m.def(
      "_ci_greenhall_table1", [](int alpha, int d) { return coeffs(greenhall::table1(alpha, d)); }, py::arg("alpha"),
      py::arg("d"));
  m.def(
      "_ci_greenhall_table2", [](int alpha, int d) { return coeffs(greenhall::table2(alpha, d)); }, py::arg("alpha"),
      py::arg("d"));
  m.def(
      "_ci_greenhall_table3", [](int d) { return coeffs(greenhall::table3(d)); }, py::arg("d"));
}

}  // namespace

void bind_ci(py::module_& m) {
  m.def("_ci_edf_greenhall", &greenhall_case, py::arg("alpha"), py::arg("d"), py::arg("m"), py::arg("N"),
        py::arg("overlapping"), py::arg("modified"));
  m.def("_ci_edf_simple", &edf_simple, py::arg("alpha"), py::arg("m"), py::arg("N"));
  m.def("_ci_edf_totvar", &edf_totvar, py::arg("alpha"), py::arg("m"), py::arg("N"));
  m.def("_ci_edf_mtotvar_table", &edf_mtotvar_table, py::arg("alpha"), py::arg("m"), py::arg("N"));
  m.def("_ci_intervals", &intervals, py::arg("dev"), py::arg("edf"), py::arg("ci"));
  m.def(
      "_ci_lag1_acf", [](const Doubles& x) { return lag1_acf(view(x, "x")); }, py::arg("x"));
  m.def(
      "_ci_detrend", [](const Doubles& x, int deg) { return to_array(detrend(view(x, "x"), deg)); }, py::arg("x"),
      py::arg("deg"));
  m.def("_ci_lag1_noise_id", &lag1_id, py::arg("x"), py::arg("af"), py::arg("phase"), py::arg("dmin"), py::arg("dmax"));
  m.def(
      "_ci_b1_ratio", [](const Doubles& x, std::size_t af) { return b1_ratio(view(x, "x"), af); }, py::arg("x"),
      py::arg("af"));
  m.def("_ci_b1_expected", &b1_expected, py::arg("N"), py::arg("mu"));
  m.def(
      "_ci_rn_ratio", [](const Doubles& x, std::size_t af) { return rn_ratio(view(x, "x"), af); }, py::arg("x"),
      py::arg("af"));
  m.def("_ci_rn_expected", &rn_expected, py::arg("m"), py::arg("alpha"));
  bind_greenhall_pieces(m);
}

}  // namespace cubecal::python
