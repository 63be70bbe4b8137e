// cubecal._analyze_file / _analyze_arrays: `cubecal analyze` on a file or on
// arrays, returning the typed AnalysisResult in a handle (_Analysis) that
// gives the content of analysis.json, writes the files of `analyze --out`, and
// feeds cubecal.simulate.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "common.hpp"
#include "json_value.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"
#include "cubecal/io/output_path.hpp"
#include "cubecal/noise/unit_from_name.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "module.hpp"
#include "units.hpp"
#include "analysis_handle.hpp"
#include "array_series.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

struct AnalyzeArgs {
  std::vector<std::string> units;  // one for all, one per channel, or none (from the names)
  py::object taus = py::str("log:10");
  double ci = 0.683;
  std::size_t temp_order = 1;
  double drift_window = 0.0;
  std::size_t cov_samples = 0;
  std::size_t max_samples = 0;
  std::vector<double> model_lsb;
  unsigned threads = 0;
  bool psd = false;       // the spectral view (analyze --psd)
  std::string composite;  // the composite model (analyze --composite MODEL); empty: the twin; "none": none
  std::size_t composite_bootstrap = 0;
};

// The units of the channels: as given, else as the record announces them.
std::vector<Unit> channel_units(const std::vector<std::string>& given, const io::Series& s) {
  std::vector<Unit> units;
  if (!given.empty()) {
    for (const auto& name : given) {
      const auto u = parse_unit(name);
      if (!u) throw UsageError(Field::unit, "unknown unit '" + name + "' (use " + known_units() + ")");
      units.push_back(*u);
    }
    return units;
  }
  return announced_units(s);
}

pipeline::AnalyzeRequest request(const AnalyzeArgs& a) {
  pipeline::AnalyzeRequest req;
  req.grid = taus_arg(a.taus);
  if (!(a.ci > 0.0 && a.ci < 1.0)) throw UsageError(Field::ci, "ci must be between 0 and 1");
  req.ci = a.ci;
  req.temp_order = a.temp_order;
  req.drift_window_s = a.drift_window;
  req.cov_samples = a.cov_samples;
  req.max_samples = a.max_samples;
  for (const double x : a.model_lsb)
    if (!(x >= 0.0) || !std::isfinite(x)) throw ArgumentError("model_lsb", "model_lsb: counts per unit, 0 or more");
  req.lsb = a.model_lsb;
  req.threads = a.threads;
  req.psd = a.psd;
  if (a.composite == "none") {
    req.composite.reset();
  } else if (!a.composite.empty()) {
    pipeline::ModelRequest m;
    m.model = a.composite;
    // A selection scores its candidates by the WIC's asymptotic optimism:
    // seconds, where the bootstrap's takes a minute per channel of a 72 h
    // record (`cubecal model --wic-replicates` has the bootstrap).
    m.selection_replicates = 0;
    if (!pipeline::is_twin(m.model)) (void)parse_candidate_models(m.model);  // a typo fails before the reading
    m.bootstrap = a.composite_bootstrap;
    req.composite = std::move(m);
    req.composite_required = true;
  }
  return req;
}

AnalysisHandle analyze_file(const std::string& path, ReadArgs read, const AnalyzeArgs& a,
                            const std::string& temperature) {
  pipeline::AnalyzeRequest req = request(a);
  if (!temperature.empty()) {
    read.extra.insert(read.extra.begin(), temperature);
    req.temp_index = 0;
  }
  io::SeriesOptions so = series_options(read);
  // The quantizer follows lsb column by column, as the CLI's --lsb does.
  if (req.lsb.empty())
    for (const double x : read.lsb)
      if (x != 1.0) {
        for (const double y : read.lsb) req.lsb.push_back(y == 1.0 ? 0.0 : y);
        break;
      }
  so.keep_time = false;
  auto result = std::make_shared<pipeline::AnalysisResult>();
  {
    py::gil_scoped_release free;
    const io::Series s = io::read_series(path, so);
    req.units = channel_units(a.units, s);
    *result = pipeline::run_analyze(s, req);
  }
  return AnalysisHandle{result};
}

AnalysisHandle analyze_arrays(const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
                              const AnalyzeArgs& a, const std::optional<Doubles>& temperature,
                              const std::string& temp_name, const std::string& label) {
  pipeline::AnalyzeRequest req = request(a);
  io::Series s = array_series(channels, names, rate, temperature, temp_name, label);
  if (temperature) req.temp_index = 0;
  req.units = channel_units(a.units, s);
  auto result = std::make_shared<pipeline::AnalysisResult>();
  {
    py::gil_scoped_release free;
    *result = pipeline::run_analyze(s, req);
  }
  return AnalysisHandle{result};
}

// analysis.json's content as Python objects with NumPy arrays.
py::object analysis_document(const AnalysisHandle& h, const std::string& command) {
  return to_python_arrays(pipeline::to_json(*h.result, pipeline::OutputContext{command}));
}

// The files of `analyze --out DIR`, each written whole through an io::AtomicFile;
// an existing file is refused unless force.
std::vector<std::string> write_files(const AnalysisHandle& h, const std::string& dir, bool force,
                                     const std::string& command) {
  namespace fs = std::filesystem;
  const auto files = pipeline::analysis_files(*h.result, pipeline::OutputContext{command});
  std::vector<std::string> names;
  for (const auto& f : files) names.push_back(f.name);
  io::prepare_output_dir(dir, force, names);
  std::vector<std::string> written;
  for (const auto& f : files) {
    const fs::path path = fs::path(dir) / f.name;
    io::write_file(path.string(), f.text, Field::out);
    written.push_back(path.string());
  }
  return written;
}

}  // namespace

void bind_analyze(py::module_& m) {
  py::class_<AnalysisHandle>(m, "_Analysis")
      .def("document", &analysis_document, py::arg("command"), "analysis.json's content")
      .def("write", &write_files, py::arg("dir"), py::arg("force"), py::arg("command"),
           "Writes the files of `analyze --out DIR`; returns their paths.");
  py::class_<AnalyzeArgs>(m, "_AnalyzeArgs")
      .def(py::init<>())
      .def_readwrite("units", &AnalyzeArgs::units)
      .def_readwrite("taus", &AnalyzeArgs::taus)
      .def_readwrite("ci", &AnalyzeArgs::ci)
      .def_readwrite("temp_order", &AnalyzeArgs::temp_order)
      .def_readwrite("drift_window", &AnalyzeArgs::drift_window)
      .def_readwrite("cov_samples", &AnalyzeArgs::cov_samples)
      .def_readwrite("max_samples", &AnalyzeArgs::max_samples)
      .def_readwrite("model_lsb", &AnalyzeArgs::model_lsb)
      .def_readwrite("threads", &AnalyzeArgs::threads)
      .def_readwrite("psd", &AnalyzeArgs::psd)
      .def_readwrite("composite", &AnalyzeArgs::composite)
      .def_readwrite("composite_bootstrap", &AnalyzeArgs::composite_bootstrap);
  m.def("_analyze_file", &analyze_file, py::arg("path"), py::arg("read"), py::arg("args"), py::arg("temperature"));
  m.def("_analyze_arrays", &analyze_arrays, py::arg("channels"), py::arg("names"), py::arg("rate"), py::arg("args"),
        py::arg("temperature"), py::arg("temp_name"), py::arg("label"));
}

}  // namespace cubecal::python
