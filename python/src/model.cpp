// cubecal._model: `cubecal model` (the GMWM fit of a composite noise model)
// on a file or on arrays; its JSON is the command's.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "array_series.hpp"
#include "arrays.hpp"
#include "common.hpp"
#include "json_value.hpp"
#include "cubecal/error.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "module.hpp"
#include "units.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

struct ModelArgs {
  std::string model;
  std::vector<std::string> units;
  std::size_t bootstrap = 0;
  std::size_t wic_replicates = 50;
  std::uint64_t seed = 1;
  double ci = 0.95;
  std::size_t starts = 32;
  bool robust = false;
  double efficiency = 0.6;
  unsigned threads = 0;
};

nlohmann::json model(const std::optional<std::string>& path, const ReadArgs& read, const std::vector<Doubles>& channels,
                     const std::vector<std::string>& names, double rate, const ModelArgs& a) {
  pipeline::ModelRequest req;
  req.model = a.model;
  (void)parse_candidate_models(a.model);  // a typo fails before the reading
  req.selection_replicates = a.wic_replicates;
  req.units = named_units(a.units);
  if (a.starts < 1) throw UsageError(Field::starts, "give at least one starting point");
  req.bootstrap = a.bootstrap;
  req.seed = a.seed;
  req.ci = a.ci;
  req.gmwm.starts = a.starts;
  req.robust = a.robust;
  req.robust_efficiency = a.efficiency;
  req.threads = a.threads;
  py::gil_scoped_release free;
  const io::Series s = call_record(path, read, channels, names, rate);
  if (req.units.empty()) req.units = announced_units_or_none(s);  // as the CLI: else none (terms in u)
  return pipeline::to_json(pipeline::run_model(s, req));
}

}  // namespace

void bind_model(py::module_& m) {
  py::class_<ModelArgs>(m, "_ModelArgs")
      .def(py::init<>())
      .def_readwrite("model", &ModelArgs::model)
      .def_readwrite("units", &ModelArgs::units)
      .def_readwrite("bootstrap", &ModelArgs::bootstrap)
      .def_readwrite("wic_replicates", &ModelArgs::wic_replicates)
      .def_readwrite("seed", &ModelArgs::seed)
      .def_readwrite("ci", &ModelArgs::ci)
      .def_readwrite("starts", &ModelArgs::starts)
      .def_readwrite("robust", &ModelArgs::robust)
      .def_readwrite("efficiency", &ModelArgs::efficiency)
      .def_readwrite("threads", &ModelArgs::threads);
  m.def("_model", returning_python(&model), py::arg("path"), py::arg("read"), py::arg("channels"), py::arg("names"),
        py::arg("rate"), py::arg("args"), "`cubecal model --format json` of a file or of arrays");
}

}  // namespace cubecal::python
