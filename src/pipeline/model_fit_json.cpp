#include "cubecal/pipeline/model_fit_json.hpp"

#include <cmath>
#include <string>

namespace cubecal::pipeline {

nlohmann::json to_json(const ModelChannel& c, double rate_hz, bool bootstrapped) {
  nlohmann::json terms = nlohmann::json::array();
  for (const ModelTerm& t : c.terms) {
    nlohmann::json params = {{"value", t.process.value}};
    if (t.kind == ProcessKind::gm) params["phi"] = t.process.phi;
    if (t.kind == ProcessKind::ma1) params["theta"] = t.process.theta;
    if (t.kind == ProcessKind::sin) params["omega"] = t.process.omega;
    nlohmann::json qs = nlohmann::json::array();
    for (const ModelQuantity& q : t.quantities) {
      const auto maybe = [&](double v) { return bootstrapped ? nlohmann::json(v) : nlohmann::json(nullptr); };
      // The sandwich sd: null where the fit does not determine it.
      const auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
      qs.push_back({{"name", q.name},
                    {"value", q.value},
                    {"unit", q.unit},
                    {"sd", maybe(q.sd)},
                    {"lo", maybe(q.interval.lo)},
                    {"hi", maybe(q.interval.hi)},
                    {"asymptotic_sd", finite(q.asymptotic_sd)},
                    {"display",
                     {{"value", q.display.value},
                      {"sigma", maybe(q.display.sigma)},
                      {"lo", maybe(q.display_interval.lo)},
                      {"hi", maybe(q.display_interval.hi)},
                      {"asymptotic_sd", finite(q.display_asymptotic_sd)},
                      {"unit", q.display.unit}}}});
    }
    terms.push_back({{"term", std::string(to_string(t.kind))}, {"parameters", params}, {"quantities", qs}});
  }
  std::vector<double> tau_s;
  for (double t : c.wv.tau) tau_s.push_back(t / rate_hz);
  std::vector<double> lo, hi;
  for (const Interval& i : c.wv.interval) {
    lo.push_back(i.lo);
    hi.push_back(i.hi);
  }
  nlohmann::json wv = {{"tau_samples", c.wv.tau}, {"tau_s", tau_s}, {"nu2", c.wv.nu2},         {"lo", lo}, {"hi", hi},
                       {"edf", c.wv.edf},         {"n", c.wv.n},    {"model", c.fit.nu2_model}};
  nlohmann::json candidates = nlohmann::json::array();
  for (const ModelCandidate& m : c.candidates)
    candidates.push_back({{"model", m.model},
                          {"parameters", m.parameters},
                          {"wic", m.score.wic},
                          {"loss", m.score.loss},
                          {"optimism", m.score.optimism},
                          {"replicates", m.score.replicates},
                          {"objective", m.objective}});
  nlohmann::json out = {{"name", c.name},
                        {"unit", c.unit.name.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.unit.name)},
                        {"model", c.model},
                        {"candidates", candidates},
                        {"failed", c.failed},
                        {"objective", c.fit.objective},
                        {"converged", c.fit.converged},
                        {"replicates", c.replicates},
                        {"terms", terms},
                        {"wavelet_variance", wv}};
  // The twin's search (ModelRequest "twin"): the spectrum's lines and the fidelity.
  if (c.fidelity) {
    nlohmann::json lines = nlohmann::json::array();
    for (const SpectralLine& l : c.lines)
      lines.push_back({{"frequency_hz", l.frequency_hz},
                       {"power", l.power},
                       {"amplitude", std::sqrt(2.0 * l.power)},
                       {"peak_ratio", l.peak_ratio},
                       {"width_hz", l.width_hz}});
    out["lines"] = lines;
    if (!c.lines_error.empty()) out["lines_error"] = c.lines_error;
    const TwinFidelity& f = *c.fidelity;
    out["fidelity"] = {{"scales", f.scales},
                       {"inside_95", f.inside},
                       {"share_inside", f.share_inside},
                       {"max_error", f.max_error},
                       {"max_error_tau_s", f.max_error_tau / rate_hz},
                       {"faithful", c.faithful}};
  }
  return out;
}

nlohmann::json to_json(const ModelResult& r) {
  nlohmann::json channels = nlohmann::json::array();
  for (const ModelChannel& c : r.channels) channels.push_back(to_json(c, r.rate_hz, r.bootstrap > 0));
  return {{"command", "model"},
          {"file", r.file},
          {"rate_hz", r.rate_hz},
          {"samples", r.samples},
          {"model", r.model},
          {"ci", r.ci},
          {"bootstrap", r.bootstrap},
          {"seed", r.seed},
          {"selection_replicates", r.selection_replicates},
          {"robust", r.robust},
          {"robust_efficiency", r.robust ? nlohmann::json(r.robust_efficiency) : nlohmann::json(nullptr)},
          {"channels", channels}};
}

}  // namespace cubecal::pipeline
