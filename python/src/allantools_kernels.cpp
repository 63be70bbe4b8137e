// The kernels behind AllanTools' calls that are not Stable32 statistics
// (cubecal/_allantools.py: pdev, gcodev, calc_htotdev_freq): the library's
// stats/kernels.hpp at each averaging factor, the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "cubecal/stats/kernels.hpp"
#include "errors.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

using Factors = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

std::vector<std::size_t> factor_list(const Factors& factors) {
  if (factors.ndim() != 1) throw ArgumentError("taus", "factors: a 1-D array is expected");
  std::vector<std::size_t> ms;
  for (py::ssize_t i = 0; i < factors.size(); ++i) {
    if (factors.data()[i] < 1) throw ArgumentError("taus", "taus: every averaging factor must be at least 1");
    ms.push_back(static_cast<std::size_t>(factors.data()[i]));
  }
  return ms;
}

std::span<const double> checked(const Doubles& a, const std::string& keyword, std::size_t column) {
  const std::span<const double> x = view(a, keyword);
  io::check_samples(x, "<arrays>", column, keyword);
  return x;
}

py::tuple terms_to_arrays(const std::vector<VarianceTerm>& t) {
  std::vector<double> var(t.size());
  std::vector<std::int64_t> n(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    var[i] = t[i].var;
    n[i] = static_cast<std::int64_t>(t[i].n);
  }
  return py::make_tuple(to_array(std::move(var)), to_array(std::move(n)));
}

// (PVAR, n) of phase x at each factor; n == 0 where the record is too short.
py::tuple parabolic(const Doubles& phase, double rate, const Factors& factors) {
  io::check_rate(rate);
  const std::span<const double> x = checked(phase, "data", 1);
  const std::vector<std::size_t> ms = factor_list(factors);
  std::vector<VarianceTerm> t(ms.size());
  {
    py::gil_scoped_release free;
    for (std::size_t i = 0; i < ms.size(); ++i) t[i] = pvar(x, ms[i], 1.0 / rate);
  }
  return terms_to_arrays(t);
}

// (Groslambert covariance, n) of two phase records of one length at each factor.
py::tuple covariance(const Doubles& phase_1, const Doubles& phase_2, double rate, const Factors& factors) {
  io::check_rate(rate);
  const std::span<const double> x1 = checked(phase_1, "data_1", 1);
  const std::span<const double> x2 = checked(phase_2, "data_2", 2);
  if (x1.size() != x2.size())
    throw ArgumentError("data_2", "data_1 and data_2 must have the same length (" + std::to_string(x1.size()) +
                                      " and " + std::to_string(x2.size()) + " samples)");
  const std::vector<std::size_t> ms = factor_list(factors);
  std::vector<VarianceTerm> t(ms.size());
  {
    py::gil_scoped_release free;
    for (std::size_t i = 0; i < ms.size(); ++i) t[i] = allan_covariance(x1, x2, ms[i], 1.0 / rate);
  }
  return terms_to_arrays(t);
}

// (HTOT^2, n) of fractional frequency y at each factor, m = 1 included.
py::tuple htot_frequency(const Doubles& freq, const Factors& factors) {
  const std::span<const double> y = checked(freq, "freq", 1);
  const std::vector<std::size_t> ms = factor_list(factors);
  std::vector<VarianceTerm> t(ms.size());
  {
    py::gil_scoped_release free;
    for (std::size_t i = 0; i < ms.size(); ++i) t[i] = htotvar_frequency(y, ms[i]);
  }
  return terms_to_arrays(t);
}

}  // namespace

void bind_allantools_kernels(py::module_& m) {
  m.def("_pvar", &parabolic, py::arg("phase"), py::arg("rate"), py::arg("factors"),
        "Parabolic variance and term count of phase data at each averaging factor (n == 0: too short).");
  m.def("_allan_covariance", &covariance, py::arg("phase_1"), py::arg("phase_2"), py::arg("rate"), py::arg("factors"),
        "Groslambert covariance (signed) and term count of two phase records at each averaging factor.");
  m.def("_htotvar_frequency", &htot_frequency, py::arg("freq"), py::arg("factors"),
        "Hadamard total variance (units of freq^2) and term count at each averaging factor, m = 1 included.");
}

}  // namespace cubecal::python
