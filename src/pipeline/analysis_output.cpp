#include "cubecal/pipeline/analysis_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace cubecal::pipeline {

namespace {

using nlohmann::json;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

json quantity(const Quantity& q, bool valid) {
  json j;
  j["value"] = valid ? json(q.value) : json(nullptr);
  j["sigma"] = valid ? json(q.sigma) : json(nullptr);
  j["unit"] = q.unit;
  return j;
}

json term(const TermEstimate& t, Term which, const Unit& u) {
  json j = quantity(display(t, which, u), t.valid);
  if (t.valid) j["tau_range_s"] = {t.tau_lo, t.tau_hi};
  return j;
}

// Parallel arrays of a curve; the interval fields only when computed.
json adev_json(const std::vector<StabilityPoint>& pts, bool intervals = true) {
  std::vector<double> tau, dev, lo, hi, edf;
  std::vector<std::size_t> n, af;
  std::vector<int> alpha;
  for (const auto& p : pts) {
    af.push_back(p.m);
    tau.push_back(p.tau);
    dev.push_back(p.dev);
    lo.push_back(p.lo);
    hi.push_back(p.hi);
    n.push_back(p.n);
    edf.push_back(p.edf);
    alpha.push_back(p.alpha);
  }
  json j{{"af", af}, {"tau", tau}, {"dev", dev}, {"n", n}};
  if (intervals) {
    j["lo"] = lo;
    j["hi"] = hi;
    j["edf"] = edf;
    j["alpha"] = alpha;
  }
  return j;
}

json noise_json(const NoiseAnalysis& n, const Unit& u) {
  json j;
  const SlopeReadOffs& r = n.readoffs;
  j["method"] = "slope read-offs (IEEE 952): N at tau = 1 s, B = sigma_min / 0.664, K at tau = 3 s";
  j["arw"] = term(r.N, Term::N, u);
  j["bias_instability"] = term(r.B, Term::B, u);
  // T only where the curve has a minimum inside the record.
  j["time_constant_s"] = r.B.valid ? json(r.tau_min) : json(nullptr);
  j["time_constant_range_s"] = r.B.valid ? json({r.tau_min_lo, r.tau_min_hi}) : json(nullptr);
  j["sigma_min"] = {{"value", r.sigma_min}, {"unit", u.name}};
  j["rate_random_walk"] = term(r.K, Term::K, u);
  j["quantization"] = term(r.Q, Term::Q, u);
  j["rate_ramp"] = term(r.R, Term::R, u);
  const NoiseFit& f = n.fit;
  json fit;
  fit["method"] = "weighted non-negative least squares of sigma^2(tau) = sum C_k tau^k, k = -2..2";
  fit["quantization"] = term(f.Q, Term::Q, u);
  fit["arw"] = term(f.N, Term::N, u);
  fit["bias_instability"] = term(f.B, Term::B, u);
  fit["rate_random_walk"] = term(f.K, Term::K, u);
  fit["rate_ramp"] = term(f.R, Term::R, u);
  fit["coefficients"] = f.c;
  fit["coefficients_sigma"] = f.c_sigma;
  fit["chi2"] = f.chi2;
  fit["dof"] = f.dof;
  fit["rms_rel_residual"] = f.rms_rel_residual;
  j["fit"] = fit;
  // Densities from the fit when it found the term, else from the read-off.
  const TermEstimate& N = f.N.valid ? f.N : r.N;
  const TermEstimate& K = f.K.valid ? f.K : r.K;
  j["densities"] = {{"white", quantity(white_density(N, u, false), N.valid)},
                    {"random_walk", quantity(random_walk_density(K, u, false), K.valid)},
                    {"white_si", quantity(white_density(N, u, true), N.valid)},
                    {"random_walk_si", quantity(random_walk_density(K, u, true), K.valid)}};
  return j;
}

}  // namespace

std::string analysis_json(const AnalysisResult& r, const OutputContext& ctx) {
  json j;
  j["input"] = {{"file", r.file},       {"samples", r.samples},   {"rate_hz", r.rate_hz},
                {"duration_s", r.duration_s}, {"segments", r.segments}};
  j["command"] = ctx.command;
  json chans = json::array();
  for (const auto& c : r.channels) {
    json ch;
    ch["name"] = c.name;
    ch["unit"] = c.unit.name;
    ch["kind"] = to_string(c.unit.kind);
    ch["mean"] = c.mean;
    ch["stddev"] = c.stddev;
    ch["adev"] = adev_json(c.noise.adev);
    ch["noise"] = noise_json(c.noise, c.unit);
    json m;
    m["unit"] = c.unit.name;
    m["samples"] = c.model.samples;
    if (c.model.ok) {
      m["sigma_n"] = c.model.random_walk.sigma_n;
      m["sigma_mu"] = c.model.random_walk.sigma_mu;
      m["sigma_mu_unit"] = c.unit.name + "/s";
      m["lsb"] = c.model.random_walk.lsb;
      m["residual_rms_log"] = c.model.random_walk_residual.rms_log;
    } else {
      m["sigma_n"] = nullptr;
      m["sigma_mu"] = nullptr;
      m["error"] = c.model.error;
    }
    if (c.model.gm_ok) {
      m["gauss_markov"] = {{"sigma", c.model.gauss_markov.sigma_b},
                           {"tau_s", c.model.gauss_markov.tau_c},
                           {"sigma_n", c.model.gauss_markov.sigma_n},
                           {"residual_rms_log", c.model.gauss_markov_residual.rms_log}};
    } else {
      m["gauss_markov"] = nullptr;
      m["gauss_markov_error"] = c.model.gm_error;
    }
    if (c.model.ok && c.model.gm_ok)
      m["better_fit"] = c.model.gauss_markov_residual.rms_log < c.model.random_walk_residual.rms_log
                            ? "gauss_markov"
                            : "random_walk";
    ch["model"] = m;
    ch["drift"] = {{"window_s", static_cast<double>(c.drift.window) / r.rate_hz},
                   {"fixed_bias", c.drift.mean},
                   {"points", c.drift.t.size()},
                   {"file", "drift.csv"}};
    if (c.temperature) {
      const auto& t = *c.temperature;
      json tj;
      tj["sensor"] = r.temp_name;
      tj["t_ref"] = t.fit.t_ref;
      tj["offset"] = t.fit.coeff.empty() ? 0.0 : t.fit.coeff[0];
      std::vector<double> coeff(t.fit.coeff.begin() + 1, t.fit.coeff.end());
      std::vector<double> sig(t.fit.coeff_sigma.begin() + 1, t.fit.coeff_sigma.end());
      tj["coeff"] = coeff;
      tj["coeff_sigma"] = sig;
      tj["unit"] = c.unit.name + "/degC";
      std::vector<std::string> units;
      for (std::size_t p = 1; p <= coeff.size(); ++p)
        units.push_back(c.unit.name + (p == 1 ? "/degC" : "/degC^" + std::to_string(p)));
      tj["coeff_units"] = units;
      tj["r2"] = t.fit.r2;
      tj["residual_rms"] = t.fit.residual_rms;
      tj["compensated"] = noise_json(t.compensated, c.unit);
      tj["compensated"]["adev"] = adev_json(t.compensated.adev);
      ch["temperature"] = tj;
    }
    chans.push_back(std::move(ch));
  }
  j["channels"] = std::move(chans);
  std::string cov_unit;
  if (!r.channels.empty()) cov_unit = "(" + r.channels[0].unit.name + ")^2";
  j["covariance"] = {{"channels", r.cov_names}, {"matrix", r.covariance}, {"samples", r.cov_samples},
                     {"unit", cov_unit}};
  return j.dump(1) + "\n";
}

std::string dev_json(const DevResult& r, const DevJsonContext& ctx) {
  json j;
  j["stat"] = to_string(r.stat);
  j["type"] = to_string(r.type);
  j["rate_hz"] = r.rate_hz;
  j["file"] = ctx.file;
  j["samples"] = r.samples;
  j["segments"] = r.segments;
  j["ci"] = ctx.intervals ? json(ctx.ci) : json(nullptr);
  j["edf_method"] = ctx.edf_method;
  json cols = json::array();
  for (const auto& ch : r.channels) {
    json c = adev_json(ch.points, ctx.intervals);
    c["name"] = ch.name;
    cols.push_back(std::move(c));
  }
  j["columns"] = std::move(cols);
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
