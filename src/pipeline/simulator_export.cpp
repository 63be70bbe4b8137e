// The projections of each IMU channel's twin onto the noise model a
// simulator can express (pipeline/simulator_export.hpp;
// docs/twin-exports.md): the target's structure fitted to the twin's
// theoretical Haar wavelet variance at the channel's scales, and what is
// left of the twin. The files are written by simulator_export_files.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/pipeline/simulator_export.hpp"

namespace cubecal::pipeline {

namespace {

// One IMU channel and its twin's curve at the scales of the channel's
// measured wavelet variance. The fits' target is the twin's expressible
// part: the terms a simulator has no place for are dropped, not imitated
// (an MA1 enters at its white level, its correlation of neighbours
// dropped; SIN, QN and DR dropped), so that a target's few terms go to the
// noise it can carry. The weights are the measured curve's chi-square
// spread about the whole twin, and the twin error is measured against the
// whole twin.
struct Axis {
  const ChannelAnalysis* channel = nullptr;
  const CompositeModel* twin = nullptr;
  CompositeModel expressible;  // WN (with the MA1's white level), RW, GM terms of the twin
  double dt = 0.0;
  WaveletVariance curve;         // nu2 = the expressible part's; tau, n, edf = the measured curve's
  std::vector<double> nu2_twin;  // the whole twin's
  std::vector<double> sd;        // nu2_twin sqrt(2 / edf)
};

CompositeModel expressible_part(const CompositeModel& twin) {
  CompositeModel m;
  double white = 0.0;
  for (const Process& p : twin.processes) {
    if (p.kind == ProcessKind::wn) white += p.value;
    if (p.kind == ProcessKind::ma1) white += p.value * (1.0 + p.theta) * (1.0 + p.theta);
  }
  if (white > 0.0) m.processes.push_back({ProcessKind::wn, white});
  for (const Process& p : twin.processes)
    if (p.kind == ProcessKind::rw || p.kind == ProcessKind::gm) m.processes.push_back(p);
  return m;
}

bool imu_channel(const ChannelAnalysis& c) {
  return c.unit.kind == SensorKind::rate || c.unit.kind == SensorKind::acceleration;
}

Axis axis_of(const ChannelAnalysis& c, double rate_hz, std::string_view target) {
  const std::string refusal = "channel " + c.name + " carries no composite noise model (its twin) to export to " +
                              std::string(target) + ": run analyze with the composite model (the twin)";
  if (!c.model.composite) throw UsageError(Field::estimators, refusal);
  const ModelChannel& m = *c.model.composite;
  if (m.fit.model.processes.empty() || m.wv.size() < 2 || m.wv.edf.size() != m.wv.size())
    throw UsageError(Field::estimators, refusal + " (its composite model has no fitted terms or no wavelet variance)");
  Axis a;
  a.channel = &c;
  a.twin = &m.fit.model;
  a.expressible = expressible_part(m.fit.model);
  a.dt = 1.0 / rate_hz;
  a.curve.tau = m.wv.tau;
  a.curve.n = m.wv.n;
  a.curve.edf = m.wv.edf;
  bool expressible = !a.expressible.processes.empty();
  for (std::size_t j = 0; j < m.wv.size(); ++j) {
    const double v = haar_wavelet_variance(m.fit.model, m.wv.tau[j]);
    if (!(v > 0.0) || !std::isfinite(v) || !(m.wv.edf[j] > 0.0))
      throw UsageError(Field::estimators, "channel " + c.name + ": its composite model " + model_name(m.fit.model) +
                                              " has no positive, finite wavelet variance at tau = " +
                                              std::to_string(static_cast<long long>(m.wv.tau[j])) +
                                              " samples: nothing to export");
    a.nu2_twin.push_back(v);
    a.sd.push_back(v * std::sqrt(2.0 / m.wv.edf[j]));
    const double e = expressible ? haar_wavelet_variance(a.expressible, m.wv.tau[j]) : 0.0;
    expressible = expressible && e > 0.0 && std::isfinite(e);
    a.curve.nu2.push_back(e);
  }
  // A twin of dropped terms only (a QN, a line): the whole twin is the
  // target, the closest the structure comes to it.
  if (!expressible) a.curve.nu2 = a.nu2_twin;
  a.curve.interval.clear();
  for (const double v : a.curve.nu2) a.curve.interval.push_back({v, v});
  if (a.curve.n.size() != a.curve.tau.size()) a.curve.n.assign(a.curve.tau.size(), 0);
  return a;
}

// The target's IMU channels, grouped by sensor (gyroscope, accelerometer),
// each in column order.
struct Groups {
  std::vector<Axis> gyro, accel;
};

Groups groups_of(const AnalysisResult& r, std::string_view target) {
  std::vector<Unit> units;
  for (const auto& c : r.channels) units.push_back(c.unit);
  require_imu_units(units);
  if (!(r.rate_hz > 0.0) || !std::isfinite(r.rate_hz))
    throw UsageError(Field::estimators, "the record has no sample rate to state the simulator's noise at");
  Groups g;
  for (const auto& c : r.channels) {
    if (!imu_channel(c)) continue;
    (c.unit.kind == SensorKind::rate ? g.gyro : g.accel).push_back(axis_of(c, r.rate_hz, target));
  }
  return g;
}

// Short numbers for the dropped terms' descriptions.
std::string g3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

double white_level(const CompositeModel& m) {
  double w = 0.0;
  for (const Process& p : m.processes) {
    if (p.kind == ProcessKind::wn) w += p.value;
    if (p.kind == ProcessKind::ma1) w += p.value * (1.0 + p.theta) * (1.0 + p.theta);
  }
  return w;
}

bool has(const CompositeModel& m, ProcessKind k) {
  return std::any_of(m.processes.begin(), m.processes.end(), [k](const Process& p) { return p.kind == k; });
}

// The twin's terms the structure has no place for, as people quote them.
std::vector<std::string> dropped_terms(const CompositeModel& twin, const CompositeModel& structure, double dt,
                                       const Unit& unit) {
  const std::string u = unit.name;
  const bool wn = has(structure, ProcessKind::wn), rw = has(structure, ProcessKind::rw),
             gm = has(structure, ProcessKind::gm);
  std::vector<std::string> d;
  for (const Process& p : twin.processes) {
    switch (p.kind) {
      case ProcessKind::wn:
        if (!wn) d.push_back("WN (N = " + g3(std::sqrt(p.value * dt)) + " " + u + " sqrt(s))");
        break;
      case ProcessKind::ma1: {
        const MovingAverageTerm t = moving_average_term(p, dt);
        if (wn)
          d.push_back("MA1's theta = " + g3(t.theta) + " (its correlation of neighbours; its white level N = " +
                      g3(t.n) + " " + u + " sqrt(s) is carried by WN)");
        else
          d.push_back("MA1 (N = " + g3(t.n) + " " + u + " sqrt(s), theta = " + g3(t.theta) + ")");
        break;
      }
      case ProcessKind::qn: d.push_back("QN (Q = " + g3(std::sqrt(p.value) * dt) + " " + u + " s)"); break;
      case ProcessKind::dr: d.push_back("DR (R = " + g3(p.value / dt) + " " + u + "/s)"); break;
      case ProcessKind::rw:
        if (!rw && !gm) d.push_back("RW (K = " + g3(std::sqrt(p.value / dt)) + " " + u + "/sqrt(s))");
        break;
      case ProcessKind::gm:
        if (!gm) {
          const GaussMarkovTerm t = gauss_markov_term(p, dt);
          d.push_back("GM (sigma_b = " + g3(t.sigma_b) + " " + u + ", T_c = " + g3(t.tau_c) + " s)");
        }
        break;
      case ProcessKind::sin: {
        const SineTerm t = sine_term(p, dt);
        d.push_back("SIN " + g3(t.frequency_hz) + " Hz (A = " + g3(t.amplitude) + " " + u + ")");
        break;
      }
    }
  }
  return d;
}

constexpr double kPhiMin = 1e-9;
constexpr double kPhiMax = 1.0 - 1e-12;

double clamp_phi(double phi) { return std::clamp(phi, kPhiMin, kPhiMax); }

// Starts of `structure` from the twin's matching terms: its white level (a
// WN, or an MA1's level at low frequencies), its random walk and, for the
// structure's Gauss-Markov term, each of the twin's in turn, its random walk
// as a correlation time beyond the record when the structure has no RW, and
// its white level as a correlation shorter than a sample when the structure
// has no WN. Terms the twin lacks start small, from the curve.
std::vector<CompositeModel> twin_starts(const CompositeModel& structure,
                                        const std::vector<const CompositeModel*>& twins, const WaveletVariance& curve) {
  const double t1 = curve.tau.front(), tJ = curve.tau.back();
  double white = 0.0, walk = 0.0;
  std::vector<Process> gms;
  for (const CompositeModel* t : twins) {
    white = std::max(white, white_level(*t));
    for (const Process& p : t->processes) {
      if (p.kind == ProcessKind::rw) walk = std::max(walk, p.value);
      if (p.kind == ProcessKind::gm) gms.push_back(p);
    }
  }
  const double nu_first = curve.nu2.front(), nu_last = curve.nu2.back();
  const bool s_wn = has(structure, ProcessKind::wn), s_rw = has(structure, ProcessKind::rw);
  if (!(white > 0.0)) white = (s_wn ? 0.5 : 1.0) * nu_first * t1;
  if (!(walk > 0.0)) walk = 1e-3 * nu_last * 12.0 * tJ / (tJ * tJ + 2.0);
  std::vector<Process> gm_starts = gms;
  if (!s_rw) gm_starts.push_back({ProcessKind::gm, walk, clamp_phi(std::exp(-1.0 / (100.0 * tJ)))});
  if (!s_wn) gm_starts.push_back({ProcessKind::gm, white, 0.05});
  if (gm_starts.empty()) {
    // A Gauss-Markov term's wavelet variance peaks near tau = 3.8 T_c at
    // about 0.22 of its stationary variance: one at the middle scale.
    const std::size_t j = curve.size() / 2;
    const double phi = clamp_phi(std::exp(-3.8 / curve.tau[j]));
    gm_starts.push_back({ProcessKind::gm, 1e-2 * curve.nu2[j] / 0.22 * (1.0 - phi * phi), phi});
  }
  std::vector<CompositeModel> starts;
  const bool s_gm = has(structure, ProcessKind::gm);
  const std::size_t variants = s_gm ? gm_starts.size() : 1;
  for (std::size_t v = 0; v < variants; ++v) {
    CompositeModel m = structure;
    for (Process& p : m.processes) {
      if (p.kind == ProcessKind::wn) p.value = white;
      if (p.kind == ProcessKind::rw) p.value = walk;
      if (p.kind == ProcessKind::gm) {
        p.value = std::max(gm_starts[v].value, 1e-300);
        p.phi = clamp_phi(gm_starts[v].phi);
      }
    }
    starts.push_back(std::move(m));
  }
  return starts;
}

GmwmFit fit_structure(const WaveletVariance& curve, const std::vector<double>& sd, const CompositeModel& structure,
                      std::vector<CompositeModel> starts) {
  GmwmOptions o;
  o.fixed_sd = sd;
  o.warm_starts = std::move(starts);
  return fit_gmwm(curve, structure, o);
}

// The projection's curve against the twin's on the axis's scales.
ExportProjection measured(const Axis& a, std::string target, const std::string& structure, CompositeModel model) {
  ExportProjection p;
  p.channel = a.channel->name;
  p.target = std::move(target);
  p.structure = structure;
  p.model = std::move(model);
  p.tau = a.curve.tau;
  p.nu2_twin = a.nu2_twin;
  for (std::size_t j = 0; j < p.tau.size(); ++j) {
    const double v = haar_wavelet_variance(p.model, p.tau[j]);
    p.nu2.push_back(v);
    const double e = std::abs(std::sqrt(v / p.nu2_twin[j]) - 1.0);
    if (!(e <= p.twin_error)) {  // NaN wins: a projection that is not finite is reported as such
      p.twin_error = e;
      p.twin_error_tau = p.tau[j];
    }
    const double tau_s = p.tau[j] * a.dt;
    if (tau_s <= 10.0 && !(e <= p.twin_error_10s)) p.twin_error_10s = e;
    if (tau_s <= 100.0 && !(e <= p.twin_error_100s)) p.twin_error_100s = e;
  }
  p.dropped = dropped_terms(*a.twin, p.model, a.dt, a.channel->unit);
  return p;
}

// One structure fitted to one axis's twin.
ExportProjection project_axis(const Axis& a, const std::string& target, const std::string& structure_name) {
  const CompositeModel structure = parse_composite_model(structure_name);
  const GmwmFit fit = fit_structure(a.curve, a.sd, structure, twin_starts(structure, {&a.expressible}, a.curve));
  return measured(a, target, structure_name, fit.model);
}

// One structure for every axis of a sensor (RotorS, PX4: one value per
// sensor), fitted to the axes' envelope: at each scale the largest of their
// expressible curves, weighted by the spread about the largest twin, so that
// no axis is simulated quieter than its twin's expressible part, the rule of
// the estimator files' one value per sensor. (A fit to all the axes' points
// at once would spend its terms on the axes' different white levels, which
// the chi-square weights make dominant.)
CompositeModel project_envelope(const std::vector<Axis>& axes, const std::string& structure_name) {
  const CompositeModel structure = parse_composite_model(structure_name);
  std::size_t J = axes.front().curve.size();
  for (const Axis& a : axes) J = std::min(J, a.curve.size());
  WaveletVariance env;
  std::vector<double> sd(J, 0.0);
  for (std::size_t j = 0; j < J; ++j) {
    env.tau.push_back(axes.front().curve.tau[j]);
    env.n.push_back(axes.front().curve.n[j]);
    double nu2 = 0.0, twin = 0.0, edf = axes.front().curve.edf[j];
    for (const Axis& a : axes) {
      nu2 = std::max(nu2, a.curve.nu2[j]);
      twin = std::max(twin, a.nu2_twin[j]);
      edf = std::min(edf, a.curve.edf[j]);
    }
    env.nu2.push_back(nu2);
    env.edf.push_back(edf);
    sd[j] = twin * std::sqrt(2.0 / edf);
  }
  for (const double v : env.nu2) env.interval.push_back({v, v});
  std::vector<const CompositeModel*> twins;
  for (const Axis& a : axes) twins.push_back(&a.expressible);
  return fit_structure(env, sd, structure, twin_starts(structure, twins, env)).model;
}

// White noise, random walk and a Gauss-Markov term of a given phi: linear
// in their three variances, fitted by non-negative least squares on the
// weighted curve (every subset of the three columns solved, the best
// feasible kept).
struct Linear3 {
  std::array<double, 3> value{};  // WN sigma2, RW gamma2, GM sigma2
  double cost = std::numeric_limits<double>::infinity();
};

Linear3 nnls3(const Axis& a, double phi) {
  const std::size_t J = a.curve.size();
  std::array<std::vector<double>, 3> col;
  const std::array<Process, 3> unit_terms{Process{ProcessKind::wn, 1.0}, Process{ProcessKind::rw, 1.0},
                                          Process{ProcessKind::gm, 1.0, phi}};
  std::array<double, 3> scale{};
  for (std::size_t k = 0; k < 3; ++k) {
    double ss = 0.0;
    for (std::size_t j = 0; j < J; ++j) {
      col[k].push_back(haar_wavelet_variance(unit_terms[k], a.curve.tau[j]) / a.sd[j]);
      ss += col[k].back() * col[k].back();
    }
    scale[k] = ss > 0.0 ? std::sqrt(ss) : 1.0;
    for (double& x : col[k]) x /= scale[k];
  }
  std::vector<double> y(J);
  for (std::size_t j = 0; j < J; ++j) y[j] = a.curve.nu2[j] / a.sd[j];
  Linear3 best;
  for (unsigned mask = 1; mask < 8; ++mask) {
    std::vector<std::size_t> S;
    for (std::size_t k = 0; k < 3; ++k)
      if (mask & (1u << k)) S.push_back(k);
    const std::size_t n = S.size();
    // Normal equations [A | b], Gaussian elimination with partial pivoting.
    std::array<std::array<double, 4>, 3> M{};
    for (std::size_t r = 0; r < n; ++r) {
      for (std::size_t c = 0; c < n; ++c)
        for (std::size_t j = 0; j < J; ++j) M[r][c] += col[S[r]][j] * col[S[c]][j];
      for (std::size_t j = 0; j < J; ++j) M[r][n] += col[S[r]][j] * y[j];
    }
    bool singular = false;
    for (std::size_t p = 0; p < n && !singular; ++p) {
      std::size_t piv = p;
      for (std::size_t r = p + 1; r < n; ++r)
        if (std::abs(M[r][p]) > std::abs(M[piv][p])) piv = r;
      std::swap(M[p], M[piv]);
      if (!(std::abs(M[p][p]) > 1e-14)) singular = true;
      for (std::size_t r = p + 1; r < n && !singular; ++r) {
        const double f = M[r][p] / M[p][p];
        for (std::size_t c = p; c <= n; ++c) M[r][c] -= f * M[p][c];
      }
    }
    if (singular) continue;
    std::array<double, 3> x{};
    for (std::size_t p = n; p-- > 0;) {
      double s = M[p][n];
      for (std::size_t c = p + 1; c < n; ++c) s -= M[p][c] * x[c];
      x[p] = s / M[p][p];
    }
    if (std::any_of(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n), [](double v) { return !(v >= 0.0); }))
      continue;
    double cost = 0.0;
    for (std::size_t j = 0; j < J; ++j) {
      double m = 0.0;
      for (std::size_t p = 0; p < n; ++p) m += x[p] * col[S[p]][j];
      cost += (y[j] - m) * (y[j] - m);
    }
    if (cost < best.cost) {
      best.cost = cost;
      best.value = {};
      for (std::size_t p = 0; p < n; ++p) best.value[S[p]] = x[p] / scale[S[p]];
    }
  }
  return best;
}

// MATLAB's imuSensor (R2023b and later) filters every axis's bias
// instability noise through one BiasInstabilityCoefficients filter: WN, RW
// and a Gauss-Markov term whose phi the axes of a sensor share. The joint
// fit: the variances of each axis by nnls3 for a phi, the phi that
// minimises the sum of the axes' weighted squares, searched over a grid of
// a = -ln(phi) from 1e-11 to 20 per sample (the axes' own GMWM fits among
// the candidates) and refined by golden section.
std::vector<CompositeModel> project_shared_phi(const std::vector<Axis>& axes) {
  const auto total = [&](double log_a) {
    const double phi = clamp_phi(std::exp(-std::exp(log_a)));
    double s = 0.0;
    for (const Axis& a : axes) s += nnls3(a, phi).cost;
    return s;
  };
  std::vector<double> grid;
  const double lo = std::log(1e-11), hi = std::log(20.0);
  for (int i = 0; i <= 240; ++i) grid.push_back(lo + (hi - lo) * i / 240.0);
  for (const Axis& a : axes) {
    const ExportProjection own = project_axis(a, "matlab", "WN+RW+GM");
    for (const Process& p : own.model.processes)
      if (p.kind == ProcessKind::gm) grid.push_back(std::log(-std::log(clamp_phi(p.phi))));
  }
  std::sort(grid.begin(), grid.end());
  std::size_t best = 0;
  std::vector<double> cost(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    cost[i] = total(grid[i]);
    if (cost[i] < cost[best]) best = i;
  }
  double x0 = grid[best > 0 ? best - 1 : 0], x1 = grid[std::min(best + 1, grid.size() - 1)];
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = x1 - g * (x1 - x0), d = x0 + g * (x1 - x0);
  double fc = total(c), fd = total(d);
  for (int it = 0; it < 80 && x1 - x0 > 1e-10; ++it) {
    if (fc < fd) {
      x1 = d;
      d = c;
      fd = fc;
      c = x1 - g * (x1 - x0);
      fc = total(c);
    } else {
      x0 = c;
      c = d;
      fc = fd;
      d = x0 + g * (x1 - x0);
      fd = total(d);
    }
  }
  double log_a = grid[best];
  if (std::min(fc, fd) < cost[best]) log_a = fc < fd ? c : d;
  const double phi = clamp_phi(std::exp(-std::exp(log_a)));
  std::vector<CompositeModel> models;
  for (const Axis& a : axes) {
    const Linear3 l = nnls3(a, phi);
    CompositeModel m = parse_composite_model("WN+RW+GM");
    for (Process& p : m.processes) {
      if (p.kind == ProcessKind::wn) p.value = l.value[0];
      if (p.kind == ProcessKind::rw) p.value = l.value[1];
      if (p.kind == ProcessKind::gm) {
        p.value = l.value[2];
        p.phi = phi;
      }
    }
    models.push_back(std::move(m));
  }
  return models;
}

}  // namespace

bool is_simulator(Estimator e) noexcept {
  switch (e) {
    case Estimator::gazebo:
    case Estimator::rotors:
    case Estimator::navego:
    case Estimator::matlab:
    case Estimator::basilisk: return true;
    case Estimator::kalibr:
    case Estimator::openvins:
    case Estimator::vins:
    case Estimator::kf_gins: return false;
  }
  return false;
}

std::vector<ExportProjection> simulator_projections(Estimator e, const AnalysisResult& r) {
  if (!is_simulator(e))
    throw std::invalid_argument("simulator_projections: " + std::string(estimator_name(e)) + " is not a simulator");
  const std::string target(estimator_name(e));
  const Groups g = groups_of(r, target);
  std::vector<ExportProjection> out;
  // In column order, whatever the sensor (a channel's own order kept).
  const auto in_column_order = [&](std::vector<ExportProjection> v) {
    const auto column = [&](const ExportProjection& p) {
      for (std::size_t i = 0; i < r.channels.size(); ++i)
        if (r.channels[i].name == p.channel) return i;
      return r.channels.size();
    };
    std::stable_sort(v.begin(), v.end(),
                     [&](const ExportProjection& a, const ExportProjection& b) { return column(a) < column(b); });
    return v;
  };
  for (const std::vector<Axis>* axes : {&g.gyro, &g.accel}) {
    if (axes->empty()) continue;
    switch (e) {
      case Estimator::gazebo:
        for (const Axis& a : *axes) out.push_back(project_axis(a, target, "WN+GM"));
        break;
      case Estimator::navego:
        for (const Axis& a : *axes) out.push_back(project_axis(a, target, "WN+RW+GM"));
        break;
      case Estimator::basilisk:
        // One first-order process per axis: white (A = 0), a random walk
        // (A = 1) or a Gauss-Markov term (0 < A < 1), the closest kept.
        for (const Axis& a : *axes) {
          ExportProjection best;
          bool first = true;
          for (const char* s : {"WN", "RW", "GM"}) {
            ExportProjection p = project_axis(a, target, s);
            if (first || p.twin_error < best.twin_error) best = std::move(p);
            first = false;
          }
          out.push_back(std::move(best));
        }
        break;
      case Estimator::rotors: {
        const CompositeModel joint = project_envelope(*axes, "WN+GM");
        for (const Axis& a : *axes) out.push_back(measured(a, target, "WN+GM", joint));
        break;
      }
      case Estimator::matlab: {
        const std::vector<CompositeModel> shared = project_shared_phi(*axes);
        for (std::size_t i = 0; i < axes->size(); ++i) {
          out.push_back(measured((*axes)[i], target, "WN+RW+GM", shared[i]));
          out.push_back(project_axis((*axes)[i], target + "-pre-R2023b", "WN+RW"));
        }
        break;
      }
      case Estimator::kalibr:
      case Estimator::openvins:
      case Estimator::vins:
      case Estimator::kf_gins: break;
    }
  }
  return in_column_order(std::move(out));
}

}  // namespace cubecal::pipeline
