// cubecal._plan: `cubecal plan` from presets, an analysis (the typed result
// of cubecal.analyze or an analysis.json), a cubecal model result (its JSON
// file or document) or datasheet terms; its JSON is the whole result
// (pipeline/plan_json.hpp's plan_document).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis_handle.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/plan.hpp"
#include "cubecal/pipeline/plan_json.hpp"
#include "json_value.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

struct PlanArgs {
  std::vector<std::string> presets;
  std::optional<AnalysisHandle> analysis;
  std::string model_file;  // an analysis.json or the JSON of `cubecal model`
  std::string model_json;  // a cubecal.model result's document, as JSON text
  std::string datasheet;
  std::optional<double> rate;  // none: the model's (a preset's: 10 Hz)
  std::string target;          // "B:10%,N:1%"; empty: none
  std::optional<double> duration;
  double ci = 0.683;
  std::string taus = "log:10";
};

void set_source(pipeline::PlanRequest& req, const PlanArgs& a) {
  const int sources = (a.presets.empty() ? 0 : 1) + (a.analysis ? 1 : 0) + (a.model_file.empty() ? 0 : 1) +
                      (a.model_json.empty() ? 0 : 1) + (a.datasheet.empty() ? 0 : 1);
  if (sources == 0)
    throw UsageError(Field::model,
                     "no sensor model: give {model} (a preset name, an Analysis, a cubecal.model result or the path "
                     "of an analysis.json) or {datasheet} with {rate}",
                     UsageError::Named::in_text);
  if (sources > 1)
    throw UsageError(Field::model, "give one sensor model: {model} or {datasheet}, not both",
                     UsageError::Named::in_text);
  if (!a.presets.empty())
    pipeline::set_plan_presets(req, a.presets, a.rate);
  else if (a.analysis)
    pipeline::set_plan_analysis(req, *a.analysis->result, "the analysis", a.rate);
  else if (!a.model_file.empty())
    pipeline::set_plan_model_file(req, a.model_file, a.rate);
  else if (!a.model_json.empty())
    pipeline::set_plan_model_result(
        req, pipeline::model_result_from_json(nlohmann::json::parse(a.model_json), "the model"), "the model", a.rate);
  else
    pipeline::set_plan_datasheet(req, a.datasheet, a.rate);
}

nlohmann::json plan(const PlanArgs& a) {
  pipeline::PlanRequest req;
  if (!a.target.empty()) req.targets = parse_plan_targets(a.target);
  req.duration_s = a.duration;
  req.ci = a.ci;
  try {
    req.grid = parse_tau_grid(a.taus);
  } catch (const std::invalid_argument& e) {
    throw UsageError(Field::taus, e.what());
  }
  set_source(req, a);
  py::gil_scoped_release free;
  return pipeline::plan_document(pipeline::run_plan(req));
}

}  // namespace

void bind_plan(py::module_& m) {
  py::class_<PlanArgs>(m, "_PlanArgs")
      .def(py::init<>())
      .def_readwrite("presets", &PlanArgs::presets)
      .def_readwrite("analysis", &PlanArgs::analysis)
      .def_readwrite("model_file", &PlanArgs::model_file)
      .def_readwrite("model_json", &PlanArgs::model_json)
      .def_readwrite("datasheet", &PlanArgs::datasheet)
      .def_readwrite("rate", &PlanArgs::rate)
      .def_readwrite("target", &PlanArgs::target)
      .def_readwrite("duration", &PlanArgs::duration)
      .def_readwrite("ci", &PlanArgs::ci)
      .def_readwrite("taus", &PlanArgs::taus);
  m.def("_plan", returning_python(&plan), py::arg("args"), "`cubecal plan`'s whole result (plan_document)");
}

}  // namespace cubecal::python
