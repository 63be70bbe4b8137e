// Reading back the JSON form of a `cubecal model` result
// (model_fit_json.hpp): a whole `model --format json` document, or one
// channel of it (analysis.json's channels[i].model.composite).
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "detail/json_node.hpp"

namespace cubecal::pipeline {

namespace {

using Node = detail::JsonNode;
constexpr const char* kWhat = "a composite model written by cubecal";

// A number the writer leaves null without a bootstrap: 0 then, as in the result.
double or_zero(const Node& n, const char* key) { return n.has(key) ? n.num(key) : 0.0; }

std::vector<std::size_t> counts(const Node& a) {
  std::vector<std::size_t> v(a.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = a.at(i).count();
  return v;
}

ProcessKind kind_of(const Node& t) {
  const std::string name = t.str();
  for (const ProcessKind k : {ProcessKind::wn, ProcessKind::qn, ProcessKind::rw, ProcessKind::dr, ProcessKind::gm,
                              ProcessKind::ma1, ProcessKind::sin})
    if (to_string(k) == name) return k;
  t.fail("unknown term '" + name + "' (known: WN, QN, RW, DR, GM, MA1, SIN)");
}

ModelQuantity read_quantity(const Node& q) {
  ModelQuantity m;
  m.name = q.at("name").str();
  m.value = q.num("value");
  m.unit = q.at("unit").str();
  m.sd = or_zero(q, "sd");
  m.interval = {or_zero(q, "lo"), or_zero(q, "hi")};
  // The sandwich sd: null (NaN) where the fit does not determine it, and in files before it.
  m.asymptotic_sd = q.num_or("asymptotic_sd", std::numeric_limits<double>::quiet_NaN());
  const Node d = q.at("display");
  m.display.value = d.num("value");
  m.display.sigma = or_zero(d, "sigma");
  m.display.unit = d.at("unit").str();
  m.display_interval = {or_zero(d, "lo"), or_zero(d, "hi")};
  m.display_asymptotic_sd = d.num_or("asymptotic_sd", std::numeric_limits<double>::quiet_NaN());
  return m;
}

ModelTerm read_term(const Node& t) {
  ModelTerm term;
  term.kind = kind_of(t.at("term"));
  const Node p = t.at("parameters");
  term.process.kind = term.kind;
  term.process.value = p.num("value");
  if (term.kind == ProcessKind::gm) {
    term.process.phi = p.num("phi");
    if (!(term.process.phi > 0.0 && term.process.phi < 1.0)) p.at("phi").fail("not a lag-one correlation in (0, 1)");
  }
  if (term.kind == ProcessKind::ma1) {
    term.process.theta = p.num("theta");
    if (!(std::abs(term.process.theta) < 1.0)) p.at("theta").fail("not a moving-average coefficient in (-1, 1)");
  }
  if (term.kind == ProcessKind::sin) {
    term.process.omega = p.num("omega");
    if (!(term.process.omega > 0.0 && term.process.omega < std::numbers::pi))
      p.at("omega").fail("not a line's angular frequency in (0, pi) rad per sample");
    if (!(term.process.value >= 0.0)) p.at("value").fail("not a squared amplitude >= 0");
  }
  const Node qs = t.at("quantities");
  for (std::size_t i = 0; i < qs.size(); ++i) term.quantities.push_back(read_quantity(qs.at(i)));
  return term;
}

ModelCandidate read_candidate(const Node& c) {
  ModelCandidate m;
  m.model = c.at("model").str();
  m.parameters = c.at("parameters").count();
  m.score.wic = c.num("wic");
  m.score.loss = c.num("loss");
  m.score.optimism = c.num("optimism");
  m.score.replicates = c.at("replicates").count();
  m.objective = c.num("objective");
  return m;
}

ModelChannel read_channel(const Node& c) {
  ModelChannel ch;
  ch.name = c.at("name").str();
  if (c.has("unit")) {
    const std::string unit = c.at("unit").str();
    const auto u = parse_unit(unit);
    if (!u) c.at("unit").fail("unknown unit '" + unit + "' (known: " + known_units() + ")");
    ch.unit = *u;
  }
  const Node terms = c.at("terms");
  if (terms.size() == 0) terms.fail("no term");
  for (std::size_t i = 0; i < terms.size(); ++i) {
    ch.terms.push_back(read_term(terms.at(i)));
    ch.fit.model.processes.push_back(ch.terms.back().process);
  }
  ch.model = c.has("model") ? c.at("model").str() : model_name(ch.fit.model);
  if (c.has("candidates")) {
    const Node cs = c.at("candidates");
    for (std::size_t i = 0; i < cs.size(); ++i) ch.candidates.push_back(read_candidate(cs.at(i)));
  }
  if (c.has("failed")) {
    const Node f = c.at("failed");
    for (std::size_t i = 0; i < f.size(); ++i) ch.failed.push_back(f.at(i).str());
  }
  ch.fit.objective = c.num("objective");
  ch.fit.converged = c.at("converged").boolean();
  ch.replicates = c.at("replicates").count();
  const Node wv = c.at("wavelet_variance");
  ch.wv.tau = wv.at("tau_samples").nums();
  ch.wv.nu2 = wv.at("nu2").nums();
  const std::vector<double> lo = wv.at("lo").nums(), hi = wv.at("hi").nums();
  ch.wv.edf = wv.at("edf").nums();
  ch.wv.n = counts(wv.at("n"));
  ch.fit.nu2_model = wv.at("model").nums();
  const std::size_t k = ch.wv.tau.size();
  if (ch.wv.nu2.size() != k || lo.size() != k || hi.size() != k || ch.wv.edf.size() != k || ch.wv.n.size() != k ||
      ch.fit.nu2_model.size() != k)
    wv.fail("tau_samples, nu2, lo, hi, edf, n and model differ in length");
  for (std::size_t j = 0; j < k; ++j) ch.wv.interval.push_back({lo[j], hi[j]});
  if (c.has("fidelity")) {
    const Node f = c.at("fidelity");
    TwinFidelity t;
    t.scales = f.at("scales").count();
    t.inside = f.at("inside_95").count();
    t.share_inside = f.num("share_inside");
    t.max_error = f.num("max_error");
    // Seconds back to samples by the scales' own ratio (tau_samples / tau_s: the rate).
    const std::vector<double> tau_s = wv.at("tau_s").nums();
    t.max_error_tau =
        f.num("max_error_tau_s") * (k > 0 && tau_s.front() > 0.0 ? ch.wv.tau.front() / tau_s.front() : 1.0);
    ch.fidelity = t;
    ch.faithful = f.at("faithful").boolean();
    if (c.has("lines")) {
      const Node ls = c.at("lines");
      for (std::size_t i = 0; i < ls.size(); ++i) {
        const Node l = ls.at(i);
        ch.lines.push_back({l.num("frequency_hz"), l.num("power"), l.num("peak_ratio"), l.num("width_hz")});
      }
    }
    if (c.has("lines_error")) ch.lines_error = c.at("lines_error").str();
  }
  return ch;
}

}  // namespace

ModelChannel model_channel_from_json(const nlohmann::json& j, const std::string& where, const std::string& path) {
  return read_channel(Node(j, path, where, kWhat));
}

ModelResult model_result_from_json(const nlohmann::json& j, const std::string& where) {
  const Node root(j, "", where, kWhat);
  if (!j.is_object() || !j.contains("command") || j["command"] != "model")
    root.fail("not a `cubecal model {format} json` result (its \"command\" is \"model\")");
  ModelResult r;
  r.file = root.at("file").str();
  r.rate_hz = root.num("rate_hz");
  if (!(r.rate_hz > 0.0)) root.at("rate_hz").fail("not positive");
  r.samples = root.at("samples").count();
  r.model = root.at("model").str();
  r.selection_replicates = root.has("selection_replicates") ? root.at("selection_replicates").count() : 0;
  r.ci = root.num("ci");
  r.bootstrap = root.at("bootstrap").count();
  r.seed = root.at("seed").count();
  r.robust = root.has("robust") && root.at("robust").boolean();
  if (r.robust) r.robust_efficiency = root.num("robust_efficiency");
  r.robust = root.has("robust") && root.at("robust").boolean();
  r.robust_efficiency = root.num_or("robust_efficiency", 0.6);
  const Node chans = root.at("channels");
  for (std::size_t c = 0; c < chans.size(); ++c) r.channels.push_back(read_channel(chans.at(c)));
  return r;
}

}  // namespace cubecal::pipeline
