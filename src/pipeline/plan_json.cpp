#include "cubecal/pipeline/plan_json.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace cubecal::pipeline {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json text_or_null(std::string_view s) {
  return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(std::string(s));
}

nlohmann::json row_json(const PlanChannel& ch, const PlanRow& row) {
  const TermPrecision& at = row.at;
  const bool planned = at.reason == PlanReason::none;
  return {{"channel", ch.name},
          {"term", std::string(to_string(at.term))},
          {"kind", row.target ? "target" : "duration"},
          {"precision", row.target ? number(*row.target) : number(planned ? at.precision : kNaN)},
          {"duration_s", number(row.duration_s)},
          {"achieved", number(planned ? at.precision : kNaN)},
          {"value", number(row.display.value)},
          {"unit", row.display.unit},
          {"tau_lo", number(at.tau_lo > 0.0 ? at.tau_lo : kNaN)},
          {"tau_hi", number(at.tau_hi > 0.0 ? at.tau_hi : kNaN)},
          {"reason", text_or_null(to_string(at.reason))},
          {"why", text_or_null(planned ? std::string_view() : std::string_view(at.why))}};
}

}  // namespace

nlohmann::json to_json(const PlanResult& r) {
  nlohmann::json rows = nlohmann::json::array();
  for (const PlanChannel& ch : r.channels) {
    for (const PlanRow& row : ch.targets) rows.push_back(row_json(ch, row));
    for (const PlanRow& row : ch.at_duration) rows.push_back(row_json(ch, row));
  }
  return rows;
}

nlohmann::json plan_document(const PlanResult& r) {
  nlohmann::json j{{"command", "plan"},
                   {"source", std::string(to_string(r.source))},
                   {"source_name", r.source_name},
                   {"source_note", r.source_note},
                   {"rate_hz", r.rate_hz},
                   {"ci", r.ci},
                   {"defaults", r.defaults},
                   {"duration_s", r.duration_s ? number(*r.duration_s) : nlohmann::json(nullptr)}};
  j["targets"] = nlohmann::json::array();
  for (const PlanTarget& t : r.targets)
    j["targets"].push_back({{"term", std::string(to_string(t.term))}, {"precision", t.precision}});
  j["channels"] = nlohmann::json::array();
  j["curves"] = nlohmann::json::array();
  for (const PlanChannel& ch : r.channels) {
    j["channels"].push_back({{"name", ch.name}, {"unit", ch.unit.name}});
    for (const PlanCurve& c : ch.curves) {
      nlohmann::json precision = nlohmann::json::array();
      for (const double p : c.precision) precision.push_back(number(p));
      j["curves"].push_back({{"channel", ch.name},
                             {"term", std::string(to_string(c.term))},
                             {"duration_s", c.duration_s},
                             {"precision", std::move(precision)}});
    }
  }
  j["rows"] = to_json(r);
  return j;
}

}  // namespace cubecal::pipeline
