// The simulator files of pipeline/simulator_export.hpp: each projection
// (simulator_export.cpp) in the target's own parameters, with the target's
// noise equations, the mapping and every channel's twin error and dropped
// terms in the file's comments. docs/twin-exports.md cites each target's
// source for the equations.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "detail/config_numbers.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/simulator_export.hpp"

namespace cubecal::pipeline {

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kStandardGravity = 9.80665;  // m/s^2, NaveGo's G (imu_si_errors.m)

using detail::config_number;
using detail::config_plain;
std::string num(double v) { return config_number(v); }
std::string plain(double v) { return config_plain(v); }

std::string g3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

// A projection's three shapes in SI units, inflated: per-sample variances
// of the white noise and the random walk's steps, the Gauss-Markov term's
// innovation variance and phi, with its correlation time and stationary
// standard deviation.
struct Si {
  double wn = 0.0, rw = 0.0, gm = 0.0, phi = 0.0;
  bool has_wn = false, has_rw = false, has_gm = false;
  double a = 0.0;  // -ln(phi), per sample
  double one_minus_phi = 0.0;
  double tc = 0.0;          // s
  double stationary = 0.0;  // the Gauss-Markov term's standard deviation
};

Si si_of(const CompositeModel& m, double to_si, double inflate, double dt) {
  const double f = to_si * to_si * inflate * inflate;
  Si s;
  for (const Process& p : m.processes) {
    if (p.kind == ProcessKind::wn) {
      s.wn += p.value * f;
      s.has_wn = true;
    }
    if (p.kind == ProcessKind::rw) {
      s.rw += p.value * f;
      s.has_rw = true;
    }
    if (p.kind == ProcessKind::gm) {
      s.gm = p.value * f;
      s.phi = p.phi;
      s.has_gm = true;
    }
  }
  if (s.has_gm) {
    s.a = -std::log(s.phi);
    s.one_minus_phi = -std::expm1(-s.a);
    s.tc = dt / s.a;
    s.stationary = std::sqrt(s.gm / -std::expm1(-2.0 * s.a));
  }
  return s;
}

// phi as a number a reader evaluates: near 1 as "1.0 - x" (x = 1 - phi to
// its ten digits, which phi itself would not keep).
std::string phi_text(const Si& v, const std::string& one) {
  if (v.phi < 0.5) return num(v.phi);
  return one + " - " + num(v.one_minus_phi);
}

// One IMU channel's projection (the first of the channel's when the target
// has several) and its unit.
struct Channel {
  const ChannelAnalysis* analysis = nullptr;
  const ExportProjection* projection = nullptr;
  const ExportProjection* fallback = nullptr;  // matlab: the pre-R2023b one
};

struct Sensor {
  std::vector<Channel> axes;  // in column order
  bool gyro = true;
};

// The three axes x, y, z of a sensor: its channels in column order; with
// fewer than three, the last one repeated; with more, the first three.
std::vector<const Channel*> xyz(const Sensor& s) {
  std::vector<const Channel*> v;
  for (std::size_t i = 0; i < 3 && !s.axes.empty(); ++i) v.push_back(&s.axes[std::min(i, s.axes.size() - 1)]);
  return v;
}

std::string axes_note(const Sensor& s, const std::string& sensor) {
  if (s.axes.empty()) return "";
  std::string names;
  for (const auto* c : xyz(s)) names += (names.empty() ? "" : ", ") + c->analysis->name;
  std::string n = sensor + " axes x, y, z: " + names;
  if (s.axes.size() < 3)
    n += " (the record has " + std::to_string(s.axes.size()) + " " + sensor + " channel" +
         (s.axes.size() == 1 ? "" : "s") + ": the last repeated)";
  if (s.axes.size() > 3) {
    n += " (the record has " + std::to_string(s.axes.size()) + ": the first three; left out:";
    for (std::size_t i = 3; i < s.axes.size(); ++i) n += " " + s.axes[i].analysis->name;
    n += ")";
  }
  return n;
}

std::string twin_terms(const CompositeModel& m, double dt, const std::string& u) {
  std::string s;
  for (const Process& p : m.processes) {
    std::string t;
    switch (p.kind) {
      case ProcessKind::wn: t = "WN N = " + g3(std::sqrt(p.value * dt)) + " " + u + " sqrt(s)"; break;
      case ProcessKind::qn: t = "QN Q = " + g3(std::sqrt(p.value) * dt) + " " + u + " s"; break;
      case ProcessKind::rw: t = "RW K = " + g3(std::sqrt(p.value / dt)) + " " + u + "/sqrt(s)"; break;
      case ProcessKind::dr: t = "DR R = " + g3(p.value / dt) + " " + u + "/s"; break;
      case ProcessKind::gm: {
        const GaussMarkovTerm g = gauss_markov_term(p, dt);
        t = "GM sigma_b = " + g3(g.sigma_b) + " " + u + ", T_c = " + g3(g.tau_c) + " s";
        break;
      }
      case ProcessKind::ma1: {
        const MovingAverageTerm a = moving_average_term(p, dt);
        t = "MA1 N = " + g3(a.n) + " " + u + " sqrt(s), theta = " + g3(a.theta);
        break;
      }
      case ProcessKind::sin: {
        const SineTerm l = sine_term(p, dt);
        t = "SIN A = " + g3(l.amplitude) + " " + u + ", f = " + g3(l.frequency_hz) + " Hz";
        break;
      }
    }
    s += (s.empty() ? "" : "; ") + t;
  }
  return s;
}

// The comment lines of one channel's projection.
std::vector<std::string> channel_lines(const ExportProjection& p, const ChannelAnalysis& c, double dt,
                                       const std::string& label = "") {
  const std::string u = c.unit.name;
  const std::string who = c.name + (label.empty() ? "" : " (" + label + ")");
  std::vector<std::string> l;
  l.push_back(c.name + " [" + u + "]: twin " + model_name(c.model.composite->fit.model) + ": " +
              twin_terms(c.model.composite->fit.model, dt, u));
  std::string proj;
  for (const Process& q : p.model.processes) {
    std::string t = std::string(to_string(q.kind)) + " " + num(q.value);
    if (q.kind == ProcessKind::gm) t += " phi " + num(q.phi);
    proj += (proj.empty() ? "" : ", ") + t;
  }
  l.push_back(who + ": projection " + p.structure + ", per sample in (" + u + ")^2: " + proj + " = " +
              twin_terms(p.model, dt, u));
  char b[160];
  std::snprintf(b, sizeof b, " (%.3g %%), largest at tau = %.6g s, over %zu scales", 100.0 * p.twin_error,
                p.twin_error_tau * dt, p.tau.size());
  l.push_back(who + ": twin error " + num(p.twin_error) + b);
  if (!p.dropped.empty()) {
    std::string d;
    for (const auto& t : p.dropped) d += (d.empty() ? "" : "; ") + t;
    l.push_back(who + ": dropped: " + d);
  }
  return l;
}

// Comment rendering: "# ", "% " or one XML comment (which may not hold "--").
std::string comment(const std::vector<std::string>& lines, const std::string& prefix) {
  std::string s;
  for (const auto& l : lines) s += (l.empty() ? prefix.substr(0, prefix.find_last_not_of(' ') + 1) : prefix + l) + "\n";
  return s;
}

std::string xml_comment(const std::vector<std::string>& lines, const std::string& indent = "") {
  std::string s = indent + "<!--\n";
  for (std::string l : lines) {
    for (std::size_t at; (at = l.find("--")) != std::string::npos;) l.replace(at, 2, "- -");
    s += indent + "  " + l + "\n";
  }
  return s + indent + "-->\n";
}

struct Context {
  const AnalysisResult* r = nullptr;
  const EstimatorContext* ctx = nullptr;
  Sensor gyro, accel;
  double dt = 0.0;
  std::string missing;
};

std::vector<std::string> header(const std::string& title, const Context& x, const std::string& structure,
                                const std::string& target) {
  const AnalysisResult& r = *x.r;
  char b[200];
  std::snprintf(b, sizeof b, "record: %zu samples at %.9g Hz (%.3g h), dt = %.9g s", r.samples, r.rate_hz,
                r.duration_s / 3600.0, x.dt);
  std::vector<std::string> h{title + " written by cubecal analyze", "command: " + x.ctx->command, "file: " + r.file, b,
                             ""};
  const auto& any = !x.gyro.axes.empty() ? x.gyro.axes.front() : x.accel.axes.front();
  const std::size_t J = any.projection->tau.size();
  h.push_back("Each IMU channel's twin (its composite noise model, analysis.json model.composite) projected onto");
  h.push_back("what " + target + " can express, " + structure + ": the GMWM fit of that structure to the");
  h.push_back("theoretical Haar wavelet variance of the twin's expressible part (WN, an MA1 at its white level, RW,");
  h.push_back("the Gauss-Markov terms) at the channel's " + std::to_string(J) +
              " scales (tau = 2 .. 2^J samples), weighted by the measured curve's");
  h.push_back("chi-square spread nu2_twin sqrt(2/edf), started from the twin's matching terms. The terms with no");
  h.push_back("place (SIN lines, an MA1's correlation of neighbours, QN, DR) are listed as dropped. Twin error: max");
  h.push_back("over the scales of |sqrt(nu2_projection / nu2_twin) - 1| against the whole twin, the largest relative");
  h.push_back("error of the simulated Allan deviation against the twin's (AVAR(m) = 2 WV(2m)); the weights are");
  h.push_back("loosest at the largest scales, where it is often largest. docs/twin-exports.md derives the");
  h.push_back("equations below from the target's source.");
  h.push_back("Inflation: every standard deviation and density below is the projection's x " + plain(x.ctx->inflate) +
              (x.ctx->inflate == 1.0 ? " (not inflated)" : "") + "; the twin errors are the projection's.");
  return h;
}

std::vector<std::string> channels_block(const Context& x, bool fallback = false) {
  std::vector<std::string> l;
  for (const Sensor* s : {&x.gyro, &x.accel}) {
    if (s->axes.empty()) continue;
    l.push_back("");
    l.push_back(axes_note(*s, s->gyro ? "gyroscope" : "accelerometer"));
    for (const Channel& c : s->axes) {
      for (auto& line : channel_lines(*c.projection, *c.analysis, x.dt)) l.push_back(line);
      if (fallback && c.fallback) {
        const auto more = channel_lines(*c.fallback, *c.analysis, x.dt, c.fallback->target);
        l.insert(l.end(), more.begin() + 1, more.end());  // the twin's line once
      }
    }
  }
  if (!x.missing.empty()) {
    l.push_back("");
    l.push_back(
        x.missing + " terms absent: the record has no " +
        (x.missing == "gyroscope" ? std::string("rate (deg/s, rad/s)") : std::string("acceleration (g, m/s^2)")) +
        " channel; add them from a record of the " + x.missing + " before use.");
  }
  return l;
}

// ---------------------------------------------------------------- gazebo

std::string gazebo(const Context& x) {
  std::vector<std::string> h = header("gz-sensors IMU noise (an SDF <sensor type=\"imu\">)", x, "WN+GM", "gz-sensors");
  const std::vector<std::string> eq{
      "",
      "gz-sensors' Gaussian noise model (src/GaussianNoiseModel.cc, ApplyImpl) adds to every axis at each",
      "sensor update, dt apart (ImuSensor::Update: the update_rate):",
      "  bias <- phi_d bias + N(0, sigma_bd^2),  phi_d = exp(-dt/T),  sigma_bd^2 = -sigma_b^2 (T/2) expm1(-2 dt/T)",
      "  output = input + bias + N(mean, stddev^2)   (then rounded to precision when precision is not 0)",
      "with sigma_b = dynamic_bias_stddev, T = dynamic_bias_correlation_time and the bias started from",
      "N(bias_mean, bias_stddev^2) with a random sign (Load). stddev is a per-sample standard deviation, not",
      "a density: it holds at update_rate = the record's rate only. dynamic_bias_stddev drives the bias: its",
      "stationary standard deviation is dynamic_bias_stddev sqrt(T/2).",
      "Mapping from the projection WN+GM (per sample: white sigma2_w; Gauss-Markov sigma2_g, phi):",
      "  stddev = sqrt(sigma2_w), dynamic_bias_correlation_time T = -dt / ln(phi),",
      "  dynamic_bias_stddev = sqrt(sigma2_g / (1 - phi^2)) sqrt(2 / T).",
      "The twin's random walk and its further Gauss-Markov terms have only the one term to go to (a random",
      "walk as a T beyond the record); the fit decides, and the twin error says what is left.",
      "mean, bias_mean, bias_stddev: 0 (one static record does not measure the turn-on bias; cubecal turnon",
      "does, over power cycles: put its sigma in bias_stddev). precision: 0 (a rounding of every output is",
      "not the twin's QN, a differenced quantization, which is dropped).",
      "Units: rad/s (angular_velocity), m/s^2 (linear_acceleration)."};
  h.insert(h.end(), eq.begin(), eq.end());
  for (auto& l : channels_block(x)) h.push_back(l);
  std::string s = xml_comment(h);
  s += "<sensor name=\"imu_sensor\" type=\"imu\">\n";
  s += "  <always_on>1</always_on>\n";
  s += "  <update_rate>" + plain(x.r->rate_hz) +
       "</update_rate>  <!-- [Hz] the record's rate: stddev is per sample -->\n";
  s += "  <imu>\n";
  for (const Sensor* sensor : {&x.gyro, &x.accel}) {
    const std::string block = sensor->gyro ? "angular_velocity" : "linear_acceleration";
    if (sensor->axes.empty()) {
      s += "    <!-- " + block + ": the record has no " + (sensor->gyro ? "gyroscope" : "accelerometer") +
           " channel; its noise is left out (none) -->\n";
      continue;
    }
    s += "    <" + block + ">\n";
    const char* names[] = {"x", "y", "z"};
    const auto axes = xyz(*sensor);
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const Channel& c = *axes[i];
      const Si v = si_of(c.projection->model, c.analysis->unit.to_si, x.ctx->inflate, x.dt);
      const std::string u = sensor->gyro ? "rad/s" : "m/s^2";
      s += "      <" + std::string(names[i]) + ">  <!-- " + c.analysis->name + ", twin error " +
           g3(100.0 * c.projection->twin_error) + " % -->\n";
      s += "        <noise type=\"gaussian\">\n";
      s += "          <mean>0.0</mean>\n";
      s += "          <stddev>" + num(std::sqrt(v.wn)) + "</stddev>  <!-- [" + u + "] per sample -->\n";
      s += "          <bias_mean>0.0</bias_mean>\n";
      s += "          <bias_stddev>0.0</bias_stddev>\n";
      s += "          <dynamic_bias_stddev>" + num(v.stationary * std::sqrt(2.0 / v.tc)) +
           "</dynamic_bias_stddev>  <!-- [" + u + "/sqrt(s)] stationary " + num(v.stationary) + " " + u + " -->\n";
      s += "          <dynamic_bias_correlation_time>" + num(v.tc) + "</dynamic_bias_correlation_time>  <!-- [s] -->\n";
      s += "          <precision>0.0</precision>\n";
      s += "        </noise>\n";
      s += "      </" + std::string(names[i]) + ">\n";
    }
    s += "    </" + block + ">\n";
  }
  s += "  </imu>\n</sensor>\n";
  return s;
}

// ---------------------------------------------------------------- rotors

std::string rotors(const Context& x) {
  std::vector<std::string> h =
      header("RotorS / PX4 sitl_gazebo gazebo_imu_plugin noise (an SDF <plugin>)", x, "WN+GM", "the plugin");
  const std::vector<std::string> eq{
      "",
      "The plugin (RotorS rotors_gazebo_plugins/src/gazebo_imu_plugin.cpp, GazeboImuPlugin::AddNoise; PX4",
      "PX4-SITL_gazebo-classic src/gazebo_imu_plugin.cpp, addNoise) adds to each axis at every physics step,",
      "dt apart:",
      "  bias <- exp(-dt/T) bias + sqrt(-sigma_b^2 (T/2) (exp(-2 dt/T) - 1)) N(0,1)",
      "  output = input + bias + noise_density / sqrt(dt) N(0,1)",
      "with sigma_b = the random walk element, T = the bias correlation time; RotorS adds a constant turn-on",
      "bias N(0, turn_on_bias_sigma^2) besides, PX4 starts the bias from it. Every parameter is continuous-time",
      "(densities): the same noise at any physics rate. One value per sensor: the projection is the fit of",
      "WN+GM to the envelope of the sensor's axes (at each scale the largest of their curves: no axis",
      "simulated quieter than its twin, as the estimator files' one value per sensor); each axis's twin error",
      "below.",
      "Mapping from the projection WN+GM (per sample: white sigma2_w; Gauss-Markov sigma2_g, phi):",
      "  NoiseDensity = sqrt(sigma2_w dt), BiasCorrelationTime T = -dt / ln(phi),",
      "  random walk = sqrt(sigma2_g / (1 - phi^2)) sqrt(2 / T) (it drives the Gauss-Markov bias, a random",
      "  walk only over times short of T; the twin's random walk is carried by a long T).",
      "Element names: RotorS reads gyroscopeBiasRandomWalk, PX4 gyroscopeRandomWalk (accelerometerRandomWalk",
      "in both): both are written; plugin file librotors_gazebo_imu_plugin.so (RotorS) or",
      "libgazebo_imu_plugin.so (PX4). TurnOnBiasSigma: 0 (one static record does not measure it; cubecal",
      "turnon does). Units: rad/s (gyroscope), m/s^2 (accelerometer)."};
  h.insert(h.end(), eq.begin(), eq.end());
  for (auto& l : channels_block(x)) h.push_back(l);
  std::string s = xml_comment(h);
  s += "<plugin name=\"imu_plugin\" filename=\"libgazebo_imu_plugin.so\">\n";
  s += "  <robotNamespace></robotNamespace>\n";
  s += "  <linkName>imu_link</linkName>\n";
  s += "  <imuTopic>" + x.ctx->rostopic + "</imuTopic>\n";
  for (const Sensor* sensor : {&x.gyro, &x.accel}) {
    const std::string n = sensor->gyro ? "gyroscope" : "accelerometer";
    const std::string u = sensor->gyro ? "rad/s" : "m/s^2";
    std::vector<std::pair<std::string, std::string>> el;
    if (!sensor->axes.empty()) {
      const Channel& c = sensor->axes.front();
      const Si v = si_of(c.projection->model, c.analysis->unit.to_si, x.ctx->inflate, x.dt);
      const double walk = v.stationary * std::sqrt(2.0 / v.tc);
      el.push_back({n + "NoiseDensity", num(std::sqrt(v.wn * x.dt)) + "|" + u + "/sqrt(Hz)"});
      if (sensor->gyro) {
        el.push_back({"gyroscopeRandomWalk", num(walk) + "|" + u + "/s/sqrt(Hz), PX4"});
        el.push_back({"gyroscopeBiasRandomWalk", num(walk) + "|" + u + "/s/sqrt(Hz), RotorS"});
      } else {
        el.push_back({"accelerometerRandomWalk", num(walk) + "|" + u + "/s/sqrt(Hz)"});
      }
      el.push_back({n + "BiasCorrelationTime", num(v.tc) + "|s"});
      el.push_back({n + "TurnOnBiasSigma", "0.0|" + u + ", not measured"});
      for (const auto& [k, v2] : el) {
        const auto bar = v2.find('|');
        s += "  <" + k + ">" + v2.substr(0, bar) + "</" + k + ">  <!-- [" + v2.substr(bar + 1) + "] -->\n";
      }
    } else {
      s += "  <!-- " + n +
           ": the record has no such channel. Without these elements the plugin uses its\n"
           "       built-in defaults (RotorS: ADIS16448, PX4: IIM42653), not this sensor's noise:\n";
      for (const char* k : {"NoiseDensity", "RandomWalk", "BiasCorrelationTime", "TurnOnBiasSigma"})
        s += "  <" + n + k + "></" + n + k + ">\n";
      s += "  -->\n";
    }
  }
  s += "</plugin>\n";
  return s;
}

// ---------------------------------------------------------------- navego

// "[a b c]" (NaveGo's rows) or "[a, b, c]" (MATLAB's).
std::string bracketed(const std::vector<double>& v, const char* separator) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) s += separator;
    s += num(v[i]);
  }
  return s + "]";
}

std::string vector3(const std::vector<double>& v) { return bracketed(v, " "); }

std::string navego(const Context& x) {
  std::vector<std::string> h =
      header("NaveGo IMU error profile (a MATLAB/Octave script)", x, "WN+RW+GM", "NaveGo's simulation");
  const std::vector<std::string> eq{
      "",
      "NaveGo simulates each axis (simulation/gyro_gen.m, acc_gen.m) at freq Hz, dt = 1/freq, as the sum of",
      "  white noise   g_std randn, g_std = arw_si / sqrt(dt) (conversions/imu_si_errors.m)",
      "  dynamic bias  noise_b_dyn.m (Aggarwal eq. 3.33): b(1) = gb_dyn,",
      "                b(k) = exp(-dt/gb_corr) b(k-1) + gb_dyn sqrt(1 - exp(-2 dt/gb_corr)) randn",
      "                (gb_dyn its stationary standard deviation; gb_corr = Inf on every axis: white noise of gb_dyn)",
      "  rate random walk  noise_rrw.m: r(k) = r(k-1) + arrw_si dt randn",
      "  static bias   noise_b_sta.m: gb_sta plus a uniform 10 % of it, a constant",
      "with the SI values imu_si_errors(imu, dt) makes of the fields below: arw_si = arw/60 pi/180,",
      "vrw_si = vrw/60, arrw_si = arrw/60 pi/180, vrrw_si = vrrw/60, gb_dyn pi/180, ab_dyn 1e-3 G.",
      "Mapping from the projection WN+RW+GM (per sample: sigma2_w; gamma2; sigma2_g, phi), SI first:",
      "  arw = sqrt(sigma2_w dt) 60 180/pi [deg/sqrt(h)], vrw = sqrt(sigma2_w dt) 60 [m/s/sqrt(h)];",
      "  arrw = sqrt(gamma2) / dt 60 180/pi, vrrw = sqrt(gamma2) / dt 60: noise_rrw steps by arrw_si dt, not",
      "  arrw_si sqrt(dt), so these hold at this freq only (the rate random walk K = arrw_si sqrt(dt));",
      "  gb_dyn = sqrt(sigma2_g / (1 - phi^2)) 180/pi [deg/s], ab_dyn = the same / (1e-3 G) [mg],",
      "  gb_corr = ab_corr = -dt / ln(phi) [s].",
      "gb_sta, ab_sta: 0 (one static record does not measure a turn-on bias; a constant has no Allan",
      "variance). gb_psd, ab_psd (the filter's dynamic-bias root-PSD gb_dyn/sqrt(gb_corr), its Q only) are",
      "computed by imu_si_errors from these; NaveGo before 2020 called them gpsd, apsd (gb_drift sqrt(gb_corr))",
      "and gb_dyn gb_drift."};
  h.insert(h.end(), eq.begin(), eq.end());
  for (auto& l : channels_block(x)) h.push_back(l);
  std::string s = comment(h, "% ");
  s += "\n";
  std::vector<double> white[2], walk[2], dyn[2], corr[2];
  for (int k = 0; k < 2; ++k) {
    const Sensor& sensor = k == 0 ? x.gyro : x.accel;
    const double white_unit = k == 0 ? 60.0 * kRadToDeg : 60.0;
    const double dyn_unit = k == 0 ? kRadToDeg : 1.0 / (1e-3 * kStandardGravity);
    for (const Channel* c : xyz(sensor)) {
      const Si v = si_of(c->projection->model, c->analysis->unit.to_si, x.ctx->inflate, x.dt);
      white[k].push_back(std::sqrt(v.wn * x.dt) * white_unit);
      walk[k].push_back(std::sqrt(v.rw) / x.dt * white_unit);
      dyn[k].push_back(v.stationary * dyn_unit);
      corr[k].push_back(v.tc);
    }
  }
  const auto field = [](const std::string& key) {
    std::string l = "cubecal_imu." + key;
    l.resize(std::max<std::size_t>(l.size(), 20), ' ');
    return l;
  };
  const auto line = [&](const std::string& key, int k, const std::vector<double>& v, const std::string& unit) {
    const std::string l = field(key);
    if (v.empty())
      return l + " = " + (key.find("corr") != std::string::npos ? "[Inf Inf Inf]" : "[0 0 0]") + ";  % [" + unit +
             "] no " + (k == 0 ? "gyroscope" : "accelerometer") + " channel in the record\n";
    return l + " = " + vector3(v) + ";  % [" + unit + "]\n";
  };
  s += line("arw", 0, white[0], "deg/root-hour");
  s += line("arrw", 0, walk[0], "deg/root-hour/s");
  s += line("vrw", 1, white[1], "m/s/root-hour");
  s += line("vrrw", 1, walk[1], "m/s/root-hour/s");
  s += field("gb_sta") + " = [0 0 0];  % [deg/s] not measured\n";
  s += field("ab_sta") + " = [0 0 0];  % [mg] not measured\n";
  s += line("gb_dyn", 0, dyn[0], "deg/s");
  s += line("ab_dyn", 1, dyn[1], "mg");
  s += line("gb_corr", 0, corr[0], "s");
  s += line("ab_corr", 1, corr[1], "s");
  s += field("freq") + " = " + plain(x.r->rate_hz) + ";  % [Hz] the record's rate: arrw, vrrw hold at it only\n";
  s += "\n% NaveGo's SI profile, as its examples make it (imu_si_errors does not copy freq).\n";
  s += "imu = imu_si_errors(cubecal_imu, 1 / cubecal_imu.freq);\n";
  s += "imu.freq = cubecal_imu.freq;\n";
  return s;
}

// ---------------------------------------------------------------- matlab

std::string matlab_vector(const std::vector<double>& v) { return bracketed(v, ", "); }

std::string matlab(const Context& x) {
  std::vector<std::string> h =
      header("MATLAB imuSensor parameters (gyroparams, accelparams; a script)", x, "WN+RW+GM", "imuSensor");
  const std::vector<std::string> eq{
      "",
      "imuSensor (MATLAB's source is closed: its documentation, Algorithms section, and the code Simulink",
      "Coder generates for it) adds to each axis at SampleRate Fs, with w1, w2, w3 independent N(0,1):",
      "  white        NoiseDensity sqrt(BW) w1,   BW = Fs/2 for NoiseType \"double-sided\" (the default), Fs for",
      "               \"single-sided\"",
      "  random walk  r <- r + RandomWalk / sqrt(BW) w2",
      "  bias         BiasInstability w3 filtered by BiasInstabilityCoefficients (Numerator, Denominator;",
      "               default 1 / [1 -0.5]): one filter for the three axes of a sensor",
      "Mapping from the projection WN+RW+GM (per sample: sigma2_w; gamma2; sigma2_g, phi), NoiseType left at",
      "\"double-sided\" (the numbers hold at this Fs only):",
      "  NoiseDensity = sqrt(sigma2_w / (Fs/2)) (sqrt(2) N), RandomWalk = sqrt(gamma2 Fs/2) (K / sqrt(2));",
      "  R2023b and later (BiasInstabilityCoefficients settable): BiasInstability = sqrt(sigma2_g / (1 - phi^2))",
      "  (the bias's standard deviation), Numerator = sqrt(1 - phi^2), Denominator = [1, -phi], one phi per",
      "  sensor: fitted to its axes jointly (each axis's variances by non-negative least squares on its",
      "  curve, the phi that minimises their sum).",
      "  Earlier releases fix the filter at 1 / [1 -0.5]: the projection WN+RW (matlab-pre-R2023b below),",
      "  BiasInstability 0.",
      "ConstantBias, AxesMisalignment, Resolution, MeasurementRange, temperature terms: left at their",
      "defaults (not measured here). Units: rad/s (gyroscope), m/s^2 (accelerometer)."};
  h.insert(h.end(), eq.begin(), eq.end());
  for (auto& l : channels_block(x, true)) h.push_back(l);
  std::string s = comment(h, "% ");
  s += "\nFs = " + plain(x.r->rate_hz) + ";  % [Hz] the imuSensor SampleRate these numbers hold at\n";
  const double bw = x.r->rate_hz / 2.0;
  // One sensor's name-value list: NoiseDensity, RandomWalk and, with the
  // filter, BiasInstability and BiasInstabilityCoefficients.
  const auto params = [&](const Sensor& sensor, bool with_filter) {
    std::vector<double> nd, rw, bi;
    double numerator = 1.0;
    std::string phi = "0.5";
    for (const Channel* c : xyz(sensor)) {
      const ExportProjection& p = with_filter ? *c->projection : *c->fallback;
      const Si v = si_of(p.model, c->analysis->unit.to_si, x.ctx->inflate, x.dt);
      nd.push_back(std::sqrt(v.wn / bw));
      rw.push_back(std::sqrt(v.rw * bw));
      bi.push_back(v.stationary);
      if (v.has_gm) {
        numerator = std::sqrt(-std::expm1(-2.0 * v.a));
        phi = v.phi < 0.5 ? num(v.phi) : "(1 - " + num(v.one_minus_phi) + ")";
      }
    }
    const std::string u = sensor.gyro ? "rad/s" : "m/s^2";
    std::string t = "    'NoiseDensity', " + matlab_vector(nd) + ", ...  % [(" + u + ")/sqrt(Hz)] double-sided\n";
    t += "    'RandomWalk', " + matlab_vector(rw) + "";
    if (!with_filter) return t + ");  % [(" + u + ")*sqrt(Hz)]\n";
    t += ", ...  % [(" + u + ")*sqrt(Hz)]\n";
    t += "    'BiasInstability', " + matlab_vector(bi) + ", ...  % [" + u + "] the bias's standard deviation\n";
    t += "    'BiasInstabilityCoefficients', struct('Numerator', " + num(numerator) + ", 'Denominator', [1, -" + phi +
         "]));\n";
    return t;
  };
  const auto sensor_call = [&](const Sensor& sensor, bool with_filter) {
    const std::string var = sensor.gyro ? "gyro" : "accel";
    const std::string ctor = sensor.gyro ? "gyroparams" : "accelparams";
    if (sensor.axes.empty())
      return "    " + var + " = " + ctor + ";  % ideal: the record has no " +
             (sensor.gyro ? std::string("gyroscope") : std::string("accelerometer")) + " channel\n";
    std::string t = "    " + var + " = " + ctor + "( ...\n";
    std::string body = params(sensor, with_filter);
    // Indent the name-value lines one level more.
    std::string indented;
    for (std::size_t at = 0; at < body.size();) {
      const std::size_t nl = body.find('\n', at);
      indented += "    " + body.substr(at, nl - at + 1);
      at = nl + 1;
    }
    return t + indented;
  };
  s += "if isprop(gyroparams, 'BiasInstabilityCoefficients')\n";
  s += "    % R2023b and later: the projection WN+RW+GM (target matlab).\n";
  s += sensor_call(x.gyro, true);
  s += sensor_call(x.accel, true);
  s += "else\n";
  s += "    % Earlier releases: the projection WN+RW (target matlab-pre-R2023b).\n";
  s += sensor_call(x.gyro, false);
  s += sensor_call(x.accel, false);
  s += "end\n";
  s += "imu = imuSensor('accel-gyro', 'SampleRate', Fs, 'Gyroscope', gyro, 'Accelerometer', accel);\n";
  return s;
}

// ---------------------------------------------------------------- basilisk

std::string basilisk(const Context& x) {
  std::vector<std::string> h =
      header("Basilisk imuSensor noise (a Python snippet)", x,
             "one first-order process per axis (WN, RW or GM, the closest)", "Basilisk's imuSensor");
  const std::vector<std::string> eq{
      "",
      "Basilisk's imuSensor (src/simulation/sensors/imuSensor/imuSensor.cpp: computeSensorErrors,",
      "applySensorErrors) adds to each axis, at each update of its task, the state of a GaussMarkov model",
      "(src/architecture/utilities/gauss_markov.cpp, computeNextState):",
      "  x <- AMatrix x + PMatrix w,  w ~ N(0, I),  clipped to +-bound where a bound is set (> 0)",
      "  omega_out = omega + x + senRotBias  (accel_out likewise with the Accel matrices)",
      "and nothing beside it: per axis one first-order process, A = 0 white noise of standard deviation P,",
      "A = 1 a random walk of step P, 0 < A < 1 a Gauss-Markov term of innovation P. Each axis takes the",
      "one of the three whose fit to its twin leaves the smallest twin error.",
      "PMatrix is the per-update standard deviation (the module header's example multiplies a noise std by",
      "1.5: not here); the task rate must be the record's (IMU_RATE_HZ). Bounds (setErrorBoundsGyro,",
      "setWalkBoundsGyro) are left unset, unbounded: a bound truncates the process. Both error models are",
      "seeded with the one RNGSeed: gyroscope and accelerometer draw the same normals.",
      "Units: rad/s (gyroscope), m/s^2 (accelerometer)."};
  h.insert(h.end(), eq.begin(), eq.end());
  for (auto& l : channels_block(x)) h.push_back(l);
  std::string s = comment(h, "# ");
  s += "\nimport numpy as np\n\n";
  s += "IMU_RATE_HZ = " + plain(x.r->rate_hz) + "  # the imuSensor task rate these matrices hold at\n\n\n";
  s += "def configure_imu_noise(imu):\n";
  s += "    \"\"\"Set the noise of an imuSensor.ImuSensor() to the projections above.\"\"\"\n";
  for (const Sensor* sensor : {&x.gyro, &x.accel}) {
    const std::string n = sensor->gyro ? "Gyro" : "Accel";
    const std::string u = sensor->gyro ? "rad/s" : "m/s^2";
    if (sensor->axes.empty()) {
      s += "    imu.PMatrix" + n + " = np.zeros((3, 3))  # no " + (sensor->gyro ? "gyroscope" : "accelerometer") +
           " channel in the record: no noise\n";
      s += "    imu.AMatrix" + n + " = np.zeros((3, 3))\n";
      continue;
    }
    std::string P = "np.diag([", A = "np.diag([", kinds;
    bool first = true;
    for (const Channel* c : xyz(*sensor)) {
      const Si v = si_of(c->projection->model, c->analysis->unit.to_si, x.ctx->inflate, x.dt);
      std::string p, a;
      if (v.has_gm) {
        p = num(std::sqrt(v.gm));
        a = phi_text(v, "1.0");
      } else if (v.has_rw) {
        p = num(std::sqrt(v.rw));
        a = "1.0";
      } else {
        p = num(std::sqrt(v.wn));
        a = "0.0";
      }
      P += (first ? "" : ", ") + p;
      A += (first ? "" : ", ") + a;
      kinds += (first ? "" : ", ") + c->analysis->name + " " + c->projection->structure;
      first = false;
    }
    s += "    imu.PMatrix" + n + " = " + P + "])  # [" + u + "] per update; " + kinds + "\n";
    s += "    imu.AMatrix" + n + " = " + A + "])\n";
  }
  return s;
}

}  // namespace

EstimatorFile simulator_config(Estimator e, const AnalysisResult& r, const EstimatorContext& ctx) {
  if (!(ctx.inflate >= 1.0) || !std::isfinite(ctx.inflate))
    throw UsageError(Field::inflate, plain(ctx.inflate) + " is not a factor >= 1");
  const std::vector<ExportProjection> projections = simulator_projections(e, r);
  Context x;
  x.r = &r;
  x.ctx = &ctx;
  x.dt = 1.0 / r.rate_hz;
  x.accel.gyro = false;
  for (const auto& c : r.channels) {
    if (c.unit.kind != SensorKind::rate && c.unit.kind != SensorKind::acceleration) continue;
    Channel ch;
    ch.analysis = &c;
    for (const auto& p : projections)
      if (p.channel == c.name) (ch.projection ? ch.fallback : ch.projection) = &p;
    (c.unit.kind == SensorKind::rate ? x.gyro : x.accel).axes.push_back(ch);
  }
  x.missing = x.gyro.axes.empty() ? "gyroscope" : x.accel.axes.empty() ? "accelerometer" : "";
  EstimatorFile f{std::string(estimator_file(e)), {}, x.missing};
  switch (e) {
    case Estimator::gazebo: f.text = gazebo(x); break;
    case Estimator::rotors: f.text = rotors(x); break;
    case Estimator::navego: f.text = navego(x); break;
    case Estimator::matlab: f.text = matlab(x); break;
    case Estimator::basilisk: f.text = basilisk(x); break;
    case Estimator::kalibr:
    case Estimator::openvins:
    case Estimator::vins:
    case Estimator::kf_gins:
      throw std::invalid_argument("simulator_config: " + std::string(estimator_name(e)) + " is not a simulator");
  }
  return f;
}

}  // namespace cubecal::pipeline
