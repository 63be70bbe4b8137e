#include "cubecal/pipeline/analysis_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/pipeline/analysis_json.hpp"

namespace cubecal::pipeline {

namespace {

using nlohmann::json;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

}  // namespace

std::string analysis_json(const AnalysisResult& r, const OutputContext& ctx) {
  json j = r;
  j["command"] = ctx.command;
  return j.dump(1) + "\n";
}

std::string dev_json(const DevResult& r, const DevJsonContext& ctx) {
  DevResult d = r;
  d.file = ctx.file;
  d.options.ci = ctx.ci;
  d.options.edf = ctx.edf_method == "simple" ? EdfMethod::simple : EdfMethod::greenhall;
  d.options.intervals = ctx.intervals;
  const json j = d;
  return j.dump(1) + "\n";
}

std::string adev_csv(const AnalysisResult& r) {
  std::string s = "channel,tau,n,dev,lo,hi,edf,alpha,fit_dev,model_dev,gauss_markov_dev\n";
  const double dt = 1.0 / r.rate_hz;
  for (const auto& c : r.channels)
    for (const auto& p : c.noise.adev) {
      const auto m = static_cast<std::size_t>(std::llround(p.tau / dt));
      s += c.name + "," + num(p.tau) + "," + std::to_string(p.n) + "," + num(p.dev) + "," + num(p.lo) + "," +
           num(p.hi) + "," + num(p.edf) + "," + std::to_string(p.alpha) + "," +
           num(noise_model_adev(c.noise.fit.c, p.tau)) + "," +
           (c.model.ok ? num(std::sqrt(avar(c.model.random_walk, m))) : "") + "," +
           (c.model.gm_ok ? num(std::sqrt(avar(c.model.gauss_markov, m))) : "") + "\n";
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
  struct Worst {
    double white = 0, walk = 0;
    bool any = false, walk_bound = false;
    std::string axis_white, axis_walk;
  };
  Worst gyro, accel;
  for (const auto& c : r.channels) {
    Worst* w = c.unit.kind == SensorKind::rate ? &gyro : c.unit.kind == SensorKind::acceleration ? &accel : nullptr;
    if (!w) continue;
    const auto& f = c.noise.fit;
    const auto& ro = c.noise.readoffs;
    const TermEstimate& N = f.N.valid ? f.N : ro.N;
    const double white = white_density(N, c.unit, true).value;
    double walk;
    bool bound = false;
    if (f.K.valid || ro.K.valid) {
      walk = random_walk_density(f.K.valid ? f.K : ro.K, c.unit, true).value;
    } else {
      // No +1/2 slope in the record: K is at most what the last point allows.
      const auto& last = c.noise.adev.back();
      walk = last.dev * std::sqrt(3.0 / last.tau) * c.unit.to_si;
      bound = true;
    }
    w->any = true;
    if (white > w->white) {
      w->white = white;
      w->axis_white = c.name;
    }
    if (walk > w->walk) {
      w->walk = walk;
      w->axis_walk = c.name;
      w->walk_bound = bound;
    }
  }
  if (!gyro.any) return {};
  std::string y = "# Kalibr / OpenVINS IMU noise model written by cubecal analyze\n";
  y += "# " + ctx.command + "\n";
  y += "# Noise densities from the white-noise term N, random walks from the rate random walk K\n";
  y += "# (continuous-time, SI units), worst axis of each sensor.\n";
  auto line = [&](const char* key, double v, const std::string& unit, const std::string& axis, bool bound) {
    y += std::string(key) + ": " + num(v) + "  # " + unit + ", axis " + axis +
         (bound ? " (upper bound: no +1/2 slope within the record)" : "") + "\n";
  };
  line("gyroscope_noise_density", gyro.white, "rad/s/sqrt(Hz)", gyro.axis_white, false);
  line("gyroscope_random_walk", gyro.walk, "rad/s^2/sqrt(Hz)", gyro.axis_walk, gyro.walk_bound);
  if (accel.any) {
    line("accelerometer_noise_density", accel.white, "m/s^2/sqrt(Hz)", accel.axis_white, false);
    line("accelerometer_random_walk", accel.walk, "m/s^3/sqrt(Hz)", accel.axis_walk, accel.walk_bound);
  }
  y += "update_rate: " + num(r.rate_hz) + "  # Hz\n";
  y += "rostopic: " + ctx.rostopic + "\n";
  return y;
}

}  // namespace cubecal::pipeline
