#include "cubecal/pipeline/turnon_json.hpp"

#include <string>

#include "detail/curve_json.hpp"

namespace cubecal::pipeline {

namespace {

nlohmann::json quantity_json(const Quantity& q, bool valid) {
  return {{"value", valid ? nlohmann::json(q.value) : nlohmann::json(nullptr)},
          {"sigma", valid ? nlohmann::json(q.sigma) : nlohmann::json(nullptr)},
          {"unit", q.unit}};
}

nlohmann::json term_json(const TermEstimate& t) {
  return {{"valid", t.valid}, {"value", t.value}, {"sigma", t.sigma}, {"tau_lo", t.tau_lo}, {"tau_hi", t.tau_hi}};
}

TermEstimate term_of(const nlohmann::json& j) {
  return {j.at("valid").get<bool>(), j.at("value").get<double>(), j.at("sigma").get<double>(),
          j.at("tau_lo").get<double>(), j.at("tau_hi").get<double>()};
}

nlohmann::json readoffs_json(const SlopeReadOffs& r) {
  return {{"Q", term_json(r.Q)},        {"N", term_json(r.N)},        {"B", term_json(r.B)},
          {"K", term_json(r.K)},        {"R", term_json(r.R)},        {"tau_min", r.tau_min},
          {"tau_min_lo", r.tau_min_lo}, {"tau_min_hi", r.tau_min_hi}, {"sigma_min", r.sigma_min}};
}

SlopeReadOffs readoffs_of(const nlohmann::json& j) {
  SlopeReadOffs r;
  r.Q = term_of(j.at("Q"));
  r.N = term_of(j.at("N"));
  r.B = term_of(j.at("B"));
  r.K = term_of(j.at("K"));
  r.R = term_of(j.at("R"));
  r.tau_min = j.at("tau_min").get<double>();
  r.tau_min_lo = j.at("tau_min_lo").get<double>();
  r.tau_min_hi = j.at("tau_min_hi").get<double>();
  r.sigma_min = j.at("sigma_min").get<double>();
  return r;
}

nlohmann::json unit_si_json(const Unit& u) {
  return {{"kind", std::string(to_string(u.kind))}, {"to_si", u.to_si}, {"si_name", u.si_name}};
}

Unit unit_of(const std::string& name, const nlohmann::json& si) {
  Unit u;
  u.name = name;
  const std::string kind = si.at("kind").get<std::string>();
  for (SensorKind k : {SensorKind::rate, SensorKind::field, SensorKind::acceleration, SensorKind::generic})
    if (to_string(k) == kind) u.kind = k;
  u.to_si = si.at("to_si").get<double>();
  u.si_name = si.at("si_name").get<std::string>();
  return u;
}

std::vector<StabilityPoint> adev_of(const nlohmann::json& j) {
  const auto tau = j.at("tau").get<std::vector<double>>(), dev = j.at("dev").get<std::vector<double>>(),
             lo = j.at("lo").get<std::vector<double>>(), hi = j.at("hi").get<std::vector<double>>(),
             edf = j.at("edf").get<std::vector<double>>();
  const auto m = j.at("m").get<std::vector<std::size_t>>(), n = j.at("n").get<std::vector<std::size_t>>();
  const auto alpha = j.at("alpha").get<std::vector<int>>();
  std::vector<StabilityPoint> v(tau.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = {m.at(i), tau[i], dev.at(i), n.at(i), lo.at(i), hi.at(i), edf.at(i), alpha.at(i)};
  return v;
}

}  // namespace

nlohmann::json to_json(const RunSummary& r) {
  nlohmann::json j{{"file", r.file}, {"samples", r.samples}, {"rate_hz", r.rate_hz}};
  for (const auto& c : r.channels) {
    const auto& ro = c.readoffs;
    j["channels"].push_back({{"name", c.name},
                             {"unit", c.unit.name},
                             {"unit_si", unit_si_json(c.unit)},
                             {"mean", c.mean},
                             {"stddev", c.stddev},
                             {"arw", quantity_json(display(ro.N, Term::N, c.unit), ro.N.valid)},
                             {"bias_instability", quantity_json(display(ro.B, Term::B, c.unit), ro.B.valid)},
                             {"time_constant_s", ro.B.valid ? nlohmann::json(ro.tau_min) : nlohmann::json(nullptr)},
                             {"readoffs", readoffs_json(ro)},
                             {"adev", detail::curve_json(c.adev, true, "m")}});
  }
  return j;
}

RunSummary run_summary_from_json(const nlohmann::json& j) {
  RunSummary r;
  r.file = j.at("file").get<std::string>();
  r.samples = j.at("samples").get<std::size_t>();
  r.rate_hz = j.at("rate_hz").get<double>();
  if (!j.contains("channels")) return r;
  for (const auto& c : j["channels"]) {
    RunChannel ch;
    ch.name = c.at("name").get<std::string>();
    ch.unit = unit_of(c.at("unit").get<std::string>(), c.at("unit_si"));
    ch.mean = c.at("mean").get<double>();
    ch.stddev = c.at("stddev").get<double>();
    ch.readoffs = readoffs_of(c.at("readoffs"));
    ch.adev = adev_of(c.at("adev"));
    r.channels.push_back(std::move(ch));
  }
  return r;
}

nlohmann::json to_json(const TurnOnResult& t) {
  nlohmann::json j;
  j["ci"] = t.ci;
  for (const auto& r : t.runs) j["runs"].push_back(to_json(r));
  for (std::size_t c = 0; c < t.names.size(); ++c)
    j["channels"].push_back({{"name", t.names[c]},
                             {"unit", t.units[c].name},
                             {"unit_si", unit_si_json(t.units[c])},
                             {"mean_bias", t.mean_bias[c]},
                             {"turn_on_bias", t.turn_on[c]},
                             {"turn_on_bias_lo", t.turn_on_interval[c].lo},
                             {"turn_on_bias_hi", t.turn_on_interval[c].hi}});
  return j;
}

nlohmann::json to_json(const std::vector<RunSummary>& compared) {
  nlohmann::json j;
  for (const auto& r : compared) j["runs"].push_back(to_json(r));
  return j;
}

TurnOnResult turn_on_result_from_json(const nlohmann::json& j) {
  TurnOnResult t;
  t.ci = j.at("ci").get<double>();
  if (j.contains("runs"))
    for (const nlohmann::json& run : j["runs"].get<std::vector<nlohmann::json>>())
      t.runs.push_back(run_summary_from_json(run));
  if (!j.contains("channels")) return t;
  for (const auto& c : j["channels"]) {
    t.names.push_back(c.at("name").get<std::string>());
    t.units.push_back(unit_of(c.at("unit").get<std::string>(), c.at("unit_si")));
    t.mean_bias.push_back(c.at("mean_bias").get<double>());
    t.turn_on.push_back(c.at("turn_on_bias").get<double>());
    t.turn_on_interval.push_back({c.at("turn_on_bias_lo").get<double>(), c.at("turn_on_bias_hi").get<double>()});
  }
  return t;
}

}  // namespace cubecal::pipeline
