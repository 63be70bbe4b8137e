// cubecal._simulate: `cubecal simulate` into NumPy arrays, from presets, an
// analysis (the typed result of cubecal.analyze, or an analysis.json file)
// or both, with the CLI's rules for the rate and the temperature profile.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "analysis_handle.hpp"
#include "arrays.hpp"
#include "cubecal/error.hpp"
#include "errors.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/sim/presets.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

struct SimulateArgs {
  std::vector<std::string> presets;
  std::optional<AnalysisHandle> analysis;
  std::string model_file;  // analysis.json, or a `cubecal model` result's JSON
  // The noise model taken from an analysis: "random-walk" (empty: the
  // default), "gauss-markov" or "composite"; a model result's is composite.
  std::string bias;
  double rate = 0.0;         // 0: the analysis's rate, else 10 Hz
  double duration = 3600.0;  // seconds
  std::uint64_t seed = 1;
  // const:T, sine:MEAN,AMPLITUDE[,PERIOD_S] as the CLI's --temp, or values.
  std::string temperature = "sine:25,5";
  std::optional<Doubles> temperature_values;
  std::optional<Doubles> true_t;  // true-input profile: times and three rates
  std::vector<Doubles> true_w;
  std::vector<double> flicker;  // bias instability as flicker FM: one for all triads or one per triad
};

std::vector<double> numbers(const std::string& list, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(x))
      throw ArgumentError("temperature", what + ": '" + item + "' is not a number");
    v.push_back(x);
  }
  return v;
}

TemperatureProfile temperature(const SimulateArgs& a) {
  TemperatureProfile p;
  if (a.temperature_values) {
    const std::span<const double> v = view(*a.temperature_values, "temperature");
    for (const double x : v)
      if (!std::isfinite(x)) throw ArgumentError("temperature", "temperature values must be finite");
    p.kind = TemperatureProfile::Kind::series;
    p.values.assign(v.begin(), v.end());
    return p;
  }
  const std::string& spec = a.temperature;
  if (spec.rfind("const:", 0) == 0) {
    const auto v = numbers(spec.substr(6), "const:T");
    if (v.size() != 1) throw ArgumentError("temperature", "const:T takes one temperature in degC");
    p.mean = v[0];
    return p;
  }
  if (spec.rfind("sine:", 0) == 0) {
    const auto v = numbers(spec.substr(5), "sine:MEAN,AMPLITUDE[,PERIOD_S]");
    if (v.size() < 2 || v.size() > 3) throw ArgumentError("temperature", "sine:MEAN,AMPLITUDE[,PERIOD_S]");
    p.kind = TemperatureProfile::Kind::sinusoid;
    p.mean = v[0];
    p.amplitude = v[1];
    if (v.size() == 3) {
      if (!(v[2] > 0)) throw ArgumentError("temperature", "sine: the period must be positive");
      p.period_s = v[2];
    }
    return p;
  }
  throw ArgumentError(
      "temperature",
      "temperature must be \"const:T\", \"sine:MEAN,AMPLITUDE[,PERIOD_S]\" or an array, not '" + spec + "'");
}

// An analysis.json, or the JSON of `cubecal model` (its "command" is "model").
void read_model_file(const std::string& path, std::optional<pipeline::AnalysisResult>& analysis,
                     std::optional<pipeline::ModelResult>& model) {
  std::ifstream in(path);
  if (!in) throw UsageError(Field::model, "cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, false);
  if (j.is_object() && j.contains("command") && j["command"] == "model")
    model = pipeline::model_result_from_json(j, path);
  else
    analysis = pipeline::parse_analysis_json(ss.str(), path).result;
}

py::tuple simulate(const SimulateArgs& a) {
  pipeline::SimulateRequest req;
  if (a.rate != 0.0) io::check_rate(a.rate);
  const bool rate_given = a.rate != 0.0;
  req.rate_hz = rate_given ? a.rate : 10.0;
  // The model's sigma_n and sigma_mu hold per sample at the rate it was
  // measured at: without a rate (and without presets) simulate at that rate.
  std::optional<pipeline::AnalysisResult> from_file;
  std::optional<pipeline::ModelResult> composite_file;
  if (!a.model_file.empty()) read_model_file(a.model_file, from_file, composite_file);
  const pipeline::AnalysisResult* model = a.analysis ? a.analysis->result.get() : from_file ? &*from_file : nullptr;
  if (!rate_given && a.presets.empty() && model != nullptr) req.rate_hz = model->rate_hz;
  if (!rate_given && a.presets.empty() && composite_file) req.rate_hz = composite_file->rate_hz;
  for (const auto& name : a.presets) {
    try {
      req.triads.push_back(pipeline::model_at_rate(preset(name), kPresetRateHz, req.rate_hz));
    } catch (const std::invalid_argument&) {
      std::string known;
      for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
      throw UsageError(Field::model, "unknown preset '" + name + "' (known: " + known + ")");
    }
  }
  if (!a.bias.empty() && a.bias != "random-walk" && a.bias != "gauss-markov" && a.bias != "composite" &&
      a.bias != "twin")
    throw UsageError(Field::bias, "bias must be \"twin\", \"random-walk\", \"gauss-markov\" or \"composite\"");
  if (model != nullptr) {
    const std::string label = a.analysis ? std::string("the analysis") : a.model_file;
    // The twin by default, where every channel has one; else the paper's model.
    const bool has_twin =
        !model->channels.empty() && std::all_of(model->channels.begin(), model->channels.end(),
                                                [](const auto& ch) { return ch.model.composite.has_value(); });
    const bool twin = a.bias == "composite" || a.bias == "twin" || (a.bias.empty() && has_twin);
    for (auto& t : twin ? pipeline::models_from_composite(*model, label, req.rate_hz)
                        : pipeline::models_from_analysis(*model, label, a.bias == "gauss-markov", req.rate_hz))
      req.triads.push_back(std::move(t));
  }
  if (composite_file) {
    if (!a.bias.empty() && a.bias != "composite" && a.bias != "twin")
      throw UsageError(Field::bias, a.model_file +
                                        " is a cubecal model result, which holds composite models only "
                                        "(bias=\"composite\", or leave bias out)");
    for (auto& t : pipeline::models_from_composite(*composite_file, a.model_file, req.rate_hz))
      req.triads.push_back(std::move(t));
  }
  if (req.triads.empty()) throw UsageError(Field::model, "nothing to simulate: give a preset or an analysis");
  if (!a.flicker.empty()) {
    if (a.flicker.size() != 1 && a.flicker.size() != req.triads.size())
      throw UsageError(Field::flicker, "flicker: one bias instability B for all triads or one per triad (" +
                                           std::to_string(req.triads.size()) + ")");
    for (std::size_t k = 0; k < req.triads.size(); ++k) {
      const double b = a.flicker.size() == 1 ? a.flicker[0] : a.flicker[k];
      if (!(b >= 0.0) || !std::isfinite(b)) throw UsageError(Field::flicker, "flicker: B must be a finite number >= 0");
      for (auto& axis : req.triads[k].axes) axis.power_law.push_back(flicker_term(b));
    }
  }
  if (!(a.duration > 0.0) || !std::isfinite(a.duration))
    throw UsageError(Field::duration, "duration must be a positive number of seconds");
  req.duration_s = a.duration;
  req.seed = a.seed;
  req.temperature = temperature(a);
  if (a.true_t) {
    if (a.true_w.size() != 3) throw ArgumentError("true_input", "a true-input profile is (t, wx, wy, wz)");
    const auto t = view(*a.true_t, "true_input");
    req.true_input.t.assign(t.begin(), t.end());
    for (int k = 0; k < 3; ++k) {
      const auto w = view(a.true_w[static_cast<std::size_t>(k)], "true_input");
      if (w.size() != t.size()) throw ArgumentError("true_input", "t and each rate must have the same length");
      req.true_input.w[static_cast<std::size_t>(k)].assign(w.begin(), w.end());
    }
  }
  const double samples = req.duration_s * req.rate_hz;
  if (samples > 1e10)
    throw UsageError(Field::duration, "more than 1e10 samples asked for: shorten duration or lower rate");
  if (pipeline::sample_count(req) < 1) throw UsageError(Field::duration, "duration shorter than one sample period");
  pipeline::SimulatedRecord rec;
  {
    py::gil_scoped_release free;
    rec = pipeline::simulate(req);
  }
  py::list arrays;
  for (auto& c : rec.channels) arrays.append(to_array(std::move(c)));
  return py::make_tuple(rec.names, arrays, rec.rate_hz);
}

}  // namespace

void bind_simulate(py::module_& m) {
  py::class_<SimulateArgs>(m, "_SimulateArgs")
      .def(py::init<>())
      .def_readwrite("presets", &SimulateArgs::presets)
      .def_readwrite("analysis", &SimulateArgs::analysis)
      .def_readwrite("model_file", &SimulateArgs::model_file)
      .def_readwrite("bias", &SimulateArgs::bias)
      .def_readwrite("rate", &SimulateArgs::rate)
      .def_readwrite("duration", &SimulateArgs::duration)
      .def_readwrite("seed", &SimulateArgs::seed)
      .def_readwrite("temperature", &SimulateArgs::temperature)
      .def_readwrite("temperature_values", &SimulateArgs::temperature_values)
      .def_readwrite("true_t", &SimulateArgs::true_t)
      .def_readwrite("true_w", &SimulateArgs::true_w)
      .def_readwrite("flicker", &SimulateArgs::flicker);
  m.def("_simulate", &simulate, py::arg("args"), "(names, arrays, rate_hz) of a simulated record");
  m.def("_preset_names", &preset_names);
  m.def("_parse_duration", &pipeline::parse_duration, py::arg("text"));
}

}  // namespace cubecal::python
