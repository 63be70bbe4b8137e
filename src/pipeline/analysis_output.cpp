#include "cubecal/pipeline/analysis_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/simulator_export.hpp"
#include "cubecal/pipeline/json_text.hpp"

namespace cubecal::pipeline {

namespace {

using nlohmann::json;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

}  // namespace

json to_json(const AnalysisResult& r, const OutputContext& ctx) {
  json j = to_json(r);
  j["command"] = ctx.command;
  json names = json::array();
  for (const Estimator e : ctx.estimators) names.push_back(std::string(estimator_name(e)));
  j["estimator_files"] = {{"for", std::move(names)}, {"noise_factor", ctx.inflate}};
  // What each simulator export keeps of the twin (simulator_export.hpp).
  json exports = json::array();
  for (const Estimator e : ctx.estimators) {
    if (!is_simulator(e)) continue;
    for (const ExportProjection& p : simulator_projections(e, r))
      exports.push_back({{"target", p.target},
                         {"channel", p.channel},
                         {"structure", p.structure},
                         {"twin_error", p.twin_error},
                         {"twin_error_tau_s", p.twin_error_tau / r.rate_hz},
                         {"twin_error_10s", p.twin_error_10s},
                         {"twin_error_100s", p.twin_error_100s},
                         {"dropped", p.dropped}});
  }
  if (!exports.empty()) j["estimator_files"]["simulator_projections"] = std::move(exports);
  return j;
}

std::string analysis_json(const AnalysisResult& r, const OutputContext& ctx) {
  return json_text(to_json(r, ctx), 1) + "\n";
}

std::string dev_json(const DevResult& r, const DevJsonContext& ctx) {
  DevResult d = r;
  d.file = ctx.file;
  d.options.ci = ctx.ci;
  d.options.edf = ctx.edf_method == "simple" ? EdfMethod::simple : EdfMethod::greenhall;
  d.options.intervals = ctx.intervals;
  const json j = to_json(d);
  return json_text(j, 1) + "\n";
}

std::string adev_csv(const AnalysisResult& r) {
  // The composite model's column only with analyze --composite.
  const bool composite = r.composite.has_value();
  std::string s = std::string("channel,tau,n,dev,lo,hi,edf,alpha,fit_dev,model_dev,gauss_markov_dev") +
                  (composite ? ",composite_dev\n" : "\n");
  const double dt = 1.0 / r.rate_hz;
  for (const auto& c : r.channels)
    for (const auto& p : c.noise.adev) {
      const auto m = static_cast<std::size_t>(std::llround(p.tau / dt));
      s += c.name + "," + num(p.tau) + "," + std::to_string(p.n) + "," + num(p.dev) + "," + num(p.interval.lo) + "," +
           num(p.interval.hi) + "," + num(p.edf) + "," + std::to_string(p.alpha) + "," +
           num(noise_model_adev(c.noise.fit.c, p.tau)) + "," +
           (c.model.ok ? num(std::sqrt(avar(c.model.random_walk, m))) : "") + "," +
           (c.model.gm_ok ? num(std::sqrt(avar(c.model.gauss_markov, m))) : "");
      if (composite) {
        s += ',';
        if (c.model.composite) s += num(std::sqrt(avar(c.model.composite->fit.model, m)));
      }
      s += "\n";
    }
  return s;
}

std::string drift_csv(const AnalysisResult& r) {
  std::string s = "channel,t,drift\n";
  for (const auto& c : r.channels)
    for (std::size_t i = 0; i < c.drift.t.size(); ++i)
      s += c.name + "," + num(c.drift.t[i]) + "," + num(c.drift.drift[i]) + "\n";
  return s;
}

bool read_drift_csv(const std::string& path, const std::vector<std::size_t>& points, AnalysisResult& r) {
  if (points.size() != r.channels.size()) return false;
  io::TableOptions o;
  o.columns = {"t", "drift"};
  const io::Table t = io::read_table(path, o);
  if (!t.has_header || t.rows() != std::accumulate(points.begin(), points.end(), std::size_t{0})) return false;
  std::size_t row = 0;
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    auto& d = r.channels[c].drift;
    const auto first = static_cast<std::ptrdiff_t>(row), last = static_cast<std::ptrdiff_t>(row + points[c]);
    d.t.assign(t.data[0].begin() + first, t.data[0].begin() + last);
    d.drift.assign(t.data[1].begin() + first, t.data[1].begin() + last);
    row += points[c];
  }
  return true;
}

std::string kalibr_yaml(const AnalysisResult& r, const OutputContext& ctx) {
  const bool rate = std::any_of(r.channels.begin(), r.channels.end(),
                                [](const ChannelAnalysis& c) { return c.unit.kind == SensorKind::rate; });
  if (!rate) return {};
  return estimator_config(Estimator::kalibr, r, {ctx.command, ctx.rostopic, ctx.inflate}).text;
}

std::vector<EstimatorFile> analysis_files(const AnalysisResult& r, const OutputContext& ctx) {
  const auto asked = [&](Estimator e) {
    return std::find(ctx.estimators.begin(), ctx.estimators.end(), e) != ctx.estimators.end();
  };
  const EstimatorContext ec{ctx.command, ctx.rostopic, ctx.inflate};
  std::vector<EstimatorFile> files{{kAnalysisFiles[0], analysis_json(r, ctx), {}},
                                   {kAnalysisFiles[1], adev_csv(r), {}},
                                   {kAnalysisFiles[2], drift_csv(r), {}}};
  if (asked(Estimator::kalibr))
    files.push_back(estimator_config(Estimator::kalibr, r, ec));
  else if (std::string y = kalibr_yaml(r, ctx); !y.empty())
    files.push_back({kAnalysisFiles[3], std::move(y), {}});
  // Every other estimator and simulator asked for, once each, in the order asked.
  std::vector<Estimator> done;
  for (const Estimator e : ctx.estimators)
    if (e != Estimator::kalibr && std::find(done.begin(), done.end(), e) == done.end()) {
      files.push_back(estimator_config(e, r, ec));
      done.push_back(e);
    }
  return files;
}

std::vector<std::string> analysis_file_names(const std::vector<Estimator>& estimators) {
  std::vector<std::string> names(std::begin(kAnalysisFiles), std::end(kAnalysisFiles));
  for (const Estimator e : estimators)
    if (e != Estimator::kalibr) names.emplace_back(estimator_file(e));
  return names;
}

}  // namespace cubecal::pipeline
