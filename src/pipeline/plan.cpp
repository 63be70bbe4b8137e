// `cubecal plan`: the sensor models of a request (presets, an analysis, a
// model result, a datasheet) and the plan of each channel's terms
// (noise/record_plan.hpp: plan_precision, plan_duration), with each term's
// precision against record length for the plot.
#include "cubecal/pipeline/plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/sim/model_allan_variance.hpp"
#include "cubecal/sim/presets.hpp"

namespace cubecal::pipeline {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_unset(const PlanRequest& r) {
  if (r.source != PlanSource::none)
    throw UsageError(Field::model, "one model source at a time: a preset, an analysis or model file, or a datasheet");
}

double rate_or(std::optional<double> rate_hz, double fallback) {
  const double rate = rate_hz.value_or(fallback);
  if (!(rate > 0.0) || !std::isfinite(rate)) throw UsageError(Field::rate, "the sampling rate must be positive");
  return rate;
}

Term display_term(PlanTerm t) {
  switch (t) {
    case PlanTerm::Q: return Term::Q;
    case PlanTerm::N: return Term::N;
    case PlanTerm::B: return Term::B;
    case PlanTerm::K: return Term::K;
    default: return Term::R;
  }
}

// The term's value in the unit quoted for the sensor (T in s).
Quantity display_value(const TermPrecision& t, const Unit& unit) {
  if (t.term == PlanTerm::T) return {t.value, 0.0, "s"};
  TermEstimate e;
  e.valid = std::isfinite(t.value);
  e.value = t.value;
  return display(e, display_term(t.term), unit);
}

// One channel's data unit: a model's unit name as parse_unit knows it, or as it is ("u" for none).
Unit unit_named(const std::string& name) {
  if (const auto u = parse_unit(name)) return *u;
  const std::string n = name.empty() ? std::string("u") : name;
  return Unit{n, SensorKind::generic, 1.0, n};
}

// Record lengths of the curves: log-spaced over 10 min .. 30 d, widened to
// show every planned length (and the asked one) with room on either side;
// never below 100 sample periods, never past the longest plan.
std::vector<double> curve_lengths(const std::vector<double>& planned, double dt, const PlanOptions& o,
                                  std::size_t points) {
  double lo = 600.0, hi = 30.0 * 86400.0;
  for (const double d : planned)
    if (std::isfinite(d) && d > 0.0) {
      lo = std::min(lo, d / 3.0);
      hi = std::max(hi, d * 3.0);
    }
  lo = std::max(lo, 100.0 * dt);
  hi = std::min(hi, o.max_duration_s);
  if (!(hi > lo)) hi = lo * 10.0;
  std::vector<double> v(points);
  for (std::size_t i = 0; i < points; ++i)
    v[i] = lo * std::pow(hi / lo, static_cast<double>(i) / static_cast<double>(points - 1));
  return v;
}

// A channel's model, as the core plans it.
struct ChannelModel {
  std::string name;
  Unit unit;
  PlanModel model;
};

std::vector<ChannelModel> channel_models(const PlanRequest& r) {
  const double dt = 1.0 / r.rate_hz;
  std::vector<ChannelModel> out;
  if (r.datasheet) {
    out.push_back({"datasheet", r.datasheet->unit, plan_model(r.datasheet->terms, dt)});
    return out;
  }
  for (const TriadModel& t : r.triads)
    for (std::size_t a = 0; a < 3; ++a) {
      if (t.axis_names[a].empty()) continue;  // a last partial triad keeps only its channels
      try {
        out.push_back({t.axis_names[a], unit_named(t.unit), plan_model(t, a, dt)});
      } catch (const std::invalid_argument& e) {
        throw UsageError(Field::model, r.source_name + ": channel " + t.axis_names[a] +
                                           " has a model the plan cannot take (" + e.what() + ")");
      }
    }
  return out;
}

PlanRow target_row(const TargetPlan& t, const Unit& unit) {
  PlanRow row;
  row.at = t.at;
  row.target = t.target.precision;
  row.duration_s = t.duration_s;
  row.display = display_value(t.at, unit);
  return row;
}

PlanRow duration_row(const TermPrecision& t, double duration_s, const Unit& unit) {
  PlanRow row;
  row.at = t;
  row.duration_s = duration_s;
  row.display = display_value(t, unit);
  return row;
}

std::vector<PlanTerm> terms_of(const std::vector<PlanTarget>& targets) {
  std::vector<PlanTerm> terms;
  for (const PlanTarget& t : targets)
    if (std::find(terms.begin(), terms.end(), t.term) == terms.end()) terms.push_back(t.term);
  if (terms.empty()) terms = {PlanTerm::N, PlanTerm::B, PlanTerm::K, PlanTerm::T};
  return terms;
}

PlanChannel plan_channel(const ChannelModel& c, const PlanRequest& r, const std::vector<PlanTarget>& targets,
                         std::optional<double> duration_s, const PlanOptions& options) {
  PlanChannel ch;
  ch.name = c.name;
  ch.unit = c.unit;
  std::vector<double> planned;
  if (!targets.empty())
    for (const TargetPlan& t : plan_duration(c.model, targets, options)) {
      ch.targets.push_back(target_row(t, c.unit));
      planned.push_back(t.duration_s);
    }
  const std::vector<PlanTerm> terms = terms_of(targets);
  if (duration_s) {
    for (const TermPrecision& t : plan_precision(c.model, *duration_s, terms, options))
      ch.at_duration.push_back(duration_row(t, *duration_s, c.unit));
    planned.push_back(*duration_s);
  }
  for (const PlanTerm t : terms) ch.curves.push_back({t, {}, {}});
  for (const double d : curve_lengths(planned, 1.0 / r.rate_hz, options, r.curve_points)) {
    const auto at = plan_precision(c.model, d, terms, options);
    for (std::size_t k = 0; k < terms.size(); ++k) {
      ch.curves[k].duration_s.push_back(d);
      ch.curves[k].precision.push_back(at[k].reason == PlanReason::none ? at[k].precision : kNaN);
    }
  }
  return ch;
}

}  // namespace

std::string_view to_string(PlanSource s) noexcept {
  switch (s) {
    case PlanSource::none: return "";
    case PlanSource::preset: return "preset";
    case PlanSource::twin: return "twin";
    case PlanSource::random_walk: return "random-walk";
    case PlanSource::model: return "model";
    case PlanSource::datasheet: return "datasheet";
  }
  return "";
}

void PlanRequest::validate() const {
  if (source == PlanSource::none || (triads.empty() && !datasheet))
    throw UsageError(Field::model, "no sensor model: give a preset, an analysis.json or model file, or a datasheet");
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw UsageError(Field::rate, "the sampling rate must be positive");
  if (!(ci > 0.0 && ci < 1.0)) throw UsageError(Field::ci, "the confidence must lie between 0 and 1 (0.683: 1 sigma)");
  if (duration_s && (!(*duration_s > 0.0) || !std::isfinite(*duration_s)))
    throw UsageError(Field::duration, "the record length must be positive");
  if (duration_s && *duration_s < 3.0 / rate_hz)
    throw UsageError(Field::duration, "the record length must hold at least three samples");
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const double p = targets[i].precision;
    const std::string name(to_string(targets[i].term));
    if (!(p > 0.0 && p < 1.0))
      throw UsageError(Field::target,
                       name + ": a precision above 0 % and below 100 % is expected (e.g. " + name + ":10%)");
    for (std::size_t j = 0; j < i; ++j)
      if (targets[j].term == targets[i].term) throw UsageError(Field::target, name + " is targeted twice");
  }
  if (curve_points < 2) throw UsageError("a precision curve needs at least 2 record lengths");
}

void set_plan_presets(PlanRequest& r, const std::vector<std::string>& names, std::optional<double> rate_hz) {
  check_unset(r);
  if (names.empty()) throw UsageError(Field::model, "no preset named");
  r.rate_hz = rate_or(rate_hz, kPresetRateHz);
  std::vector<TriadModel> triads;
  for (const std::string& name : names) {
    try {
      triads.push_back(model_at_rate(preset(name), kPresetRateHz, r.rate_hz));
    } catch (const std::invalid_argument&) {
      std::string known;
      for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
      throw UsageError(Field::model, "unknown preset '" + name + "' (known: " + known + ")");
    }
  }
  r.triads = std::move(triads);
  r.source = PlanSource::preset;
  for (const std::string& name : names) r.source_name += (r.source_name.empty() ? "" : ",") + name;
}

void set_plan_analysis(PlanRequest& r, const AnalysisResult& analysis, const std::string& label,
                       std::optional<double> rate_hz) {
  check_unset(r);
  const double rate = rate_or(rate_hz, analysis.rate_hz);
  const bool twin = !analysis.channels.empty() &&
                    std::all_of(analysis.channels.begin(), analysis.channels.end(),
                                [](const ChannelAnalysis& ch) { return ch.model.composite.has_value(); });
  if (twin) {
    r.triads = models_from_composite(analysis, label, rate);
    r.source = PlanSource::twin;
    r.source_note = "the twin (composite model) of each channel";
  } else {
    r.triads = models_from_analysis(analysis, label, false, rate);
    r.source = PlanSource::random_walk;
    r.source_note =
        "the random-walk model of each channel (the paper's): the analysis holds no twin (" +
        (analysis.composite_skipped.empty() ? std::string("analyze it again to fit one") : analysis.composite_skipped) +
        ")";
  }
  r.rate_hz = rate;
  r.source_name = label;
}

void set_plan_model_result(PlanRequest& r, const ModelResult& model, const std::string& label,
                           std::optional<double> rate_hz) {
  check_unset(r);
  const double rate = rate_or(rate_hz, model.rate_hz);
  r.triads = models_from_composite(model, label, rate);
  r.rate_hz = rate;
  r.source = PlanSource::model;
  r.source_name = label;
  r.source_note = "the composite model of each channel (" + model.model + ")";
}

void set_plan_model_file(PlanRequest& r, const std::string& path, std::optional<double> rate_hz) {
  check_unset(r);
  std::ifstream in(path);
  if (!in) throw UsageError(Field::model, "cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, false);
  if (j.is_object() && j.contains("command") && j["command"] == "model")
    set_plan_model_result(r, model_result_from_json(j, path), path, rate_hz);
  else
    set_plan_analysis(r, parse_analysis_json(ss.str(), path).result, path, rate_hz);
}

void set_plan_datasheet(PlanRequest& r, std::string_view text, std::optional<double> rate_hz) {
  check_unset(r);
  if (!rate_hz)
    throw UsageError(Field::rate,
                     "a datasheet needs the sensor's sampling rate: give {rate} HZ (the plan's first tau is 1/rate)");
  Datasheet d = parse_datasheet(text);
  r.rate_hz = rate_or(rate_hz, 0.0);
  r.source_name = d.text;
  r.source_note = "terms in " + d.unit.name + " and s";
  r.datasheet = std::move(d);
  r.source = PlanSource::datasheet;
}

std::vector<PlanTarget> default_plan_targets() {
  return {{PlanTerm::B, 0.10}, {PlanTerm::N, 0.01}, {PlanTerm::K, 0.20}, {PlanTerm::T, 0.30}};
}

PlanResult run_plan(const PlanRequest& request) {
  request.validate();
  PlanResult res;
  res.source = request.source;
  res.source_name = request.source_name;
  res.source_note = request.source_note;
  res.rate_hz = request.rate_hz;
  res.ci = request.ci;
  res.defaults = request.targets.empty() && !request.duration_s;
  res.targets = res.defaults ? default_plan_targets() : request.targets;
  res.duration_s = res.defaults ? std::optional<double>(kDefaultPlanDurationS) : request.duration_s;
  PlanOptions options;
  options.ci = request.ci;
  options.grid = request.grid;
  for (const ChannelModel& c : channel_models(request))
    res.channels.push_back(plan_channel(c, request, res.targets, res.duration_s, options));
  return res;
}

std::vector<PlanTerm> planned_terms(const PlanResult& r) { return terms_of(r.targets); }

std::string duration_words(double s) {
  if (!std::isfinite(s)) return "-";
  if (s < 120.0) return fmt::format("{:.0f} s", s);
  if (s < 3600.0) return fmt::format("{:.0f} min", s / 60.0);
  if (s < 100.0 * 3600.0) {  // "72 h", as a test bench's length is said
    const long minutes = std::lround(s / 60.0);
    const long h = minutes / 60, m = minutes % 60;
    return m == 0 ? fmt::format("{} h", h) : fmt::format("{} h {} min", h, m);
  }
  const double days = s / 86400.0;
  if (days < 10.0) return fmt::format("{:.1f} d", days);
  if (days < 365.25) return fmt::format("{:.0f} d", days);
  return fmt::format("{:.1f} years", days / 365.25);
}

std::string percent_words(double p) {
  if (!std::isfinite(p)) return "-";
  return 100.0 * p >= 99.5 ? fmt::format("{:.0f} %", 100.0 * p) : fmt::format("{:.2g} %", 100.0 * p);
}

}  // namespace cubecal::pipeline
