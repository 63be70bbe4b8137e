// cubecal._psd and cubecal._davar: `cubecal psd` and `cubecal davar` on a
// file (read as the CLI reads it) or on arrays, returning the JSON the CLI
// writes with --format json as Python objects with NumPy arrays
// (json_value.hpp), which the package wraps as typed results.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "array_series.hpp"
#include "arrays.hpp"
#include "common.hpp"
#include "json_value.hpp"
#include "cubecal/error.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/davar_pipeline.hpp"
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/pipeline/psd_json.hpp"
#include "module.hpp"
#include "units.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

struct PsdArgs {
  std::string window = "hann";
  std::size_t segment = 0;
  double fmin = 0.0;
  double overlap = 0.5;
  std::string detrend = "constant";
  std::size_t bins_per_decade = 0;
  bool fit = true;
  double fit_min = 0.0;
  double fit_max = 0.0;
  std::vector<std::string> units;
  unsigned threads = 0;
};

nlohmann::json psd(const std::optional<std::string>& path, const ReadArgs& read, const std::vector<Doubles>& channels,
                   const std::vector<std::string>& names, double rate, const PsdArgs& a) {
  pipeline::PsdRequest req;
  const auto window = parse_window(a.window);
  if (!window)
    throw UsageError(Field::window, "window must be hann, hamming, blackman or rectangular, not '" + a.window + "'");
  const auto detrend = parse_detrend(a.detrend);
  if (!detrend) throw UsageError(Field::detrend, "detrend must be none, constant or linear, not '" + a.detrend + "'");
  req.welch.window = *window;
  req.welch.detrend = *detrend;
  req.welch.segment_length = a.segment;
  req.welch.min_frequency_hz = a.fmin;
  req.welch.overlap = a.overlap;
  req.bins_per_decade = a.bins_per_decade;
  req.fit = a.fit;
  req.fit_options.min_frequency_hz = a.fit_min;
  req.fit_options.max_frequency_hz = a.fit_max;
  req.units = named_units(a.units);
  req.threads = a.threads;
  py::gil_scoped_release free;
  const io::Series s = call_record(path, read, channels, names, rate);
  if (req.units.empty()) req.units = announced_units_or_none(s);  // as the CLI: else none (densities in u^2/Hz)
  return pipeline::to_json(pipeline::run_psd(s, req));
}

struct DavarArgs {
  std::string type = "freq";
  std::string window;  // "1h", "3600s" or a number of samples; empty: a tenth of the record
  std::string step;    // empty: a tenth of the window
  py::object taus = py::str("log:10");
  bool intervals = true;
  double ci = 0.683;
  std::optional<int> alpha;
  unsigned threads = 0;
};

nlohmann::json davar(const std::optional<std::string>& path, const ReadArgs& read, const std::vector<Doubles>& channels,
                     const std::vector<std::string>& names, double rate, const DavarArgs& a) {
  pipeline::DavarRequest req;
  req.type = data_type_arg(a.type);
  if (!a.window.empty()) req.window = pipeline::parse_davar_span(a.window, Field::window);
  if (!a.step.empty()) req.step = pipeline::parse_davar_span(a.step, Field::step);
  req.grid = taus_arg(a.taus);
  if (!(a.ci > 0.0 && a.ci < 1.0)) throw UsageError(Field::ci, "ci must be between 0 and 1");
  req.intervals.enabled = a.intervals;
  req.intervals.ci = a.ci;
  req.intervals.alpha = a.alpha;
  req.threads = a.threads;
  py::gil_scoped_release free;
  const io::Series s = call_record(path, read, channels, names, rate, true);  // gaps="skip" as davar --gaps skip
  return pipeline::to_json(pipeline::run_davar(s, req));
}

}  // namespace

void bind_spectral(py::module_& m) {
  py::class_<PsdArgs>(m, "_PsdArgs")
      .def(py::init<>())
      .def_readwrite("window", &PsdArgs::window)
      .def_readwrite("segment", &PsdArgs::segment)
      .def_readwrite("fmin", &PsdArgs::fmin)
      .def_readwrite("overlap", &PsdArgs::overlap)
      .def_readwrite("detrend", &PsdArgs::detrend)
      .def_readwrite("bins_per_decade", &PsdArgs::bins_per_decade)
      .def_readwrite("fit", &PsdArgs::fit)
      .def_readwrite("fit_min", &PsdArgs::fit_min)
      .def_readwrite("fit_max", &PsdArgs::fit_max)
      .def_readwrite("units", &PsdArgs::units)
      .def_readwrite("threads", &PsdArgs::threads);
  py::class_<DavarArgs>(m, "_DavarArgs")
      .def(py::init<>())
      .def_readwrite("type", &DavarArgs::type)
      .def_readwrite("window", &DavarArgs::window)
      .def_readwrite("step", &DavarArgs::step)
      .def_readwrite("taus", &DavarArgs::taus)
      .def_readwrite("intervals", &DavarArgs::intervals)
      .def_readwrite("ci", &DavarArgs::ci)
      .def_readwrite("alpha", &DavarArgs::alpha)
      .def_readwrite("threads", &DavarArgs::threads);
  m.def("_psd", returning_python(&psd), py::arg("path"), py::arg("read"), py::arg("channels"), py::arg("names"),
        py::arg("rate"), py::arg("args"), "`cubecal psd --format json` of a file or of arrays");
  m.def("_davar", returning_python(&davar), py::arg("path"), py::arg("read"), py::arg("channels"), py::arg("names"),
        py::arg("rate"), py::arg("args"), "`cubecal davar --format json` of a file or of arrays");
}

}  // namespace cubecal::python
