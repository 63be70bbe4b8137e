#include "cubecal/pipeline/estimator_config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "cubecal/error.hpp"
#include "detail/config_numbers.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/pipeline/simulator_export.hpp"

namespace cubecal::pipeline {

namespace {

constexpr std::array<std::string_view, 9> kNames{"kalibr", "openvins", "vins",   "kf-gins", "gazebo",
                                                 "rotors", "navego",   "matlab", "basilisk"};
constexpr std::array<std::string_view, 9> kFiles{"imu.yaml",
                                                 "kalibr_imu_chain.yaml",
                                                 "vins_imu.yaml",
                                                 "kf-gins_imunoise.yaml",
                                                 "gazebo_imu_noise.sdf",
                                                 "rotors_imu_plugin.sdf",
                                                 "navego_imu.m",
                                                 "matlab_imu.m",
                                                 "basilisk_imu.py"};
constexpr double kStandardGravity = 9.80665;  // m/s^2
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kMilliGal = 1e-5;  // m/s^2

using detail::config_number;
using detail::config_plain;
std::string num(double v) { return config_number(v); }
std::string plain(double v) { return config_plain(v); }

AxisNoise axis_noise(const ChannelAnalysis& c, const std::string& file) {
  const auto& curve = c.noise.adev;
  const bool constant = std::none_of(curve.begin(), curve.end(), [](const StabilityPoint& p) { return p.dev > 0.0; });
  if (constant)
    throw InputError(file, 0, 0,
                     "channel " + c.name +
                         ": the Allan deviation is zero at every tau (a constant record), so "
                         "there is no noise to write into an estimator file",
                     "check {columns}, or leave out {estimators}");
  const ReportedTerms t = reported_terms(c.noise.readoffs, c.noise.fit, to_allan_curve(curve));
  const double si = c.unit.to_si;
  AxisNoise a;
  a.channel = c.name;
  a.mean = c.mean * si;
  a.white = t.N.value() * si;
  a.white_source = t.N.source;
  a.white_tau_lo = t.N.estimate.tau_lo;
  a.white_tau_hi = t.N.estimate.tau_hi;
  a.walk = t.K.value() * si;
  a.walk_source = t.K.source;
  if (t.K.bound() && t.K_candidate.valid) {
    a.walk_estimate = t.K_candidate.value * si;
    a.walk_estimate_sigma = t.K_candidate.sigma * si;
    a.walk_estimate_source = t.K_candidate_source;
  }
  // Not the Gauss-Markov model fit: on a record without a minimum it runs to
  // the shortest correlation time it allows (2 dt), a number no filter can use.
  a.bias_std = t.B.value() * si;
  a.bias_tc = c.noise.readoffs.tau_min;
  a.bias_source = t.B.source;
  return a;
}

// The largest value of one term over the axes, with its axis and source.
struct Pick {
  double value = 0.0;
  const AxisNoise* axis = nullptr;
  TermSource source = TermSource::fit;
};

template <class Value, class Source>
Pick largest(const std::vector<AxisNoise>& axes, Value value, Source source) {
  Pick p;
  for (const auto& a : axes)
    if (!p.axis || value(a) > p.value) {
      p.value = value(a);
      p.axis = &a;
      p.source = source(a);
    }
  return p;
}

Pick largest_white(const std::vector<AxisNoise>& axes) {
  return largest(
      axes, [](const AxisNoise& a) { return a.white; }, [](const AxisNoise& a) { return a.white_source; });
}
Pick largest_walk(const std::vector<AxisNoise>& axes) {
  return largest(
      axes, [](const AxisNoise& a) { return a.walk; }, [](const AxisNoise& a) { return a.walk_source; });
}

std::string source_note(const Pick& p, const std::string& unit, bool walk) {
  switch (p.source) {
    case TermSource::fit: return walk ? "five-term fit, significant (> 2 sigma)" : "five-term fit";
    case TermSource::read_off:
      if (walk) return "slope read-off, significant (> 2 sigma)";
      if (p.axis->white_tau_lo <= 1.0 && 1.0 <= p.axis->white_tau_hi)
        return "slope read-off: the -1/2 line at tau = 1 s, read over " + plain(p.axis->white_tau_lo) + ".." +
               plain(p.axis->white_tau_hi) + " s";
      return "slope read-off: the -1/2 line of the white arm at " + plain(p.axis->white_tau_lo) + ".." +
             plain(p.axis->white_tau_hi) + " s, extended to tau = 1 s (the curve is not white at 1 s)";
    case TermSource::upper_bound:
      if (!walk) return "UPPER BOUND: no -1/2 slope (white noise) identified, min over tau of sigma(tau)*sqrt(tau)";
      if (p.axis->walk_estimate_sigma > 0.0)
        return "UPPER BOUND: K not significant (" +
               std::string(p.axis->walk_estimate_source == TermSource::fit ? "five-term fit " : "slope read-off ") +
               num(p.axis->walk_estimate) + " +- " + num(p.axis->walk_estimate_sigma) + " [" + unit +
               "], not above 2 sigma), min over tau of sigma(tau)*sqrt(3/tau)";
      return "UPPER BOUND: no +1/2 slope (rate random walk) within the record, min over tau of "
             "sigma(tau)*sqrt(3/tau)";
  }
  return "";
}

// " # [unit] axis gx, five-term fit; measured 1.2e-4 x inflate 2"
std::string note(const Pick& p, const std::string& unit, bool walk, double inflate) {
  std::string s = "  # [" + unit + "] axis " + p.axis->channel + ", " + source_note(p, unit, walk);
  if (inflate != 1.0) s += "; measured " + num(p.value) + " x inflate " + plain(inflate);
  return s;
}

std::string header(std::string_view title, const AnalysisResult& r, const EstimatorContext& ctx) {
  std::string h;
  h += "# " + std::string(title) + " written by cubecal analyze\n";
  h += "# command: " + ctx.command + "\n";
  char b[200];
  std::snprintf(b, sizeof b, "# record: %zu samples at %.9g Hz (%.3g h)\n", r.samples, r.rate_hz,
                r.duration_s / 3600.0);
  h += "# file: " + r.file + "\n" + b;
  h += "#\n"
       "# Continuous-time model (Kalibr wiki \"IMU Noise Model\"): each axis measures\n"
       "#   y(t) = x(t) + b(t) + n(t),  n white: E[n(t) n(s)] = sigma_w^2 delta(t - s),\n"
       "#   db/dt = n_b(t),             n_b white: E[n_b(t) n_b(s)] = sigma_bw^2 delta(t - s).\n"
       "# Their Allan variances are sigma_w^2 / tau and sigma_bw^2 tau / 3, so the noise density\n"
       "# sigma_w is the IEEE Std 952 random walk N (angle or velocity random walk) and the\n"
       "# random walk sigma_bw is the rate random walk K. Discrete-time equivalents at the\n"
       "# sample rate r: sigma_w * sqrt(r) per sample and sigma_bw / sqrt(r) per step.\n"
       "# One value per sensor: the largest over its axes (conservative); each line names it.\n"
       "# Sources: N is the slope read-off, the -1/2 line read at tau = 1 s (IEEE Std 952),\n"
       "# the same N as the console table, analysis.json and the report. K is the weighted\n"
       "# five-term fit's, else the read-off's, only when significant (value > 2 sigma). A term\n"
       "# not identified, or K not significant, is written as the upper bound the curve allows,\n"
       "# marked UPPER BOUND (never 0).\n";
  h += "# Inflation: every density and random walk below is the measured value x " + plain(ctx.inflate) +
       face_words(" ({inflate}") + (ctx.inflate == 1.0 ? ": not inflated" : "") + ").\n";
  return h;
}

std::string absent(const std::string& sensor, const std::string& kind, std::string_view estimator) {
  return "# " + sensor + " terms absent: the record has no " + kind + " channel. " + std::string(estimator) +
         " needs them:\n# add them from a record of the " + sensor + " (or its datasheet) before use.\n";
}

struct Sensors {
  ImuNoise noise;
  bool gyro = false, accel = false;
  std::string missing;
};

Sensors sensors(const AnalysisResult& r, const EstimatorContext& ctx) {
  if (!(ctx.inflate >= 1.0) || !std::isfinite(ctx.inflate))
    throw UsageError(Field::inflate, plain(ctx.inflate) + " is not a factor >= 1");
  Sensors s;
  s.noise = imu_noise(r);
  std::vector<Unit> units;
  for (const auto& c : r.channels) units.push_back(c.unit);
  require_imu_units(units);
  s.gyro = !s.noise.gyroscope.empty();
  s.accel = !s.noise.accelerometer.empty();
  s.missing = !s.gyro ? "gyroscope" : !s.accel ? "accelerometer" : "";
  return s;
}

// Kalibr imu.yaml and OpenVINS kalibr_imu_chain.yaml share the four keys.
std::string kalibr_keys(const Sensors& s, const EstimatorContext& ctx, const std::string& indent,
                        std::string_view estimator) {
  std::string y;
  const double k = ctx.inflate;
  auto line = [&](const char* key, const Pick& p, const std::string& unit, bool walk) {
    y += indent + key + ": " + num(p.value * k) + note(p, unit, walk, k) + "\n";
  };
  // A sensor's two densities, or their keys commented out with the reason.
  auto sensor = [&](bool present, const std::string& name, const auto& terms, const char* kinds, const char* white_unit,
                    const char* walk_unit) {
    const std::string white = name + "_noise_density", walk = name + "_random_walk";
    if (present) {
      line(white.c_str(), largest_white(terms), white_unit, false);
      line(walk.c_str(), largest_walk(terms), walk_unit, true);
      return;
    }
    y += absent(name, kinds, estimator);
    y += "#" + indent + white + ":  # [" + white_unit + "]\n";
    y += "#" + indent + walk + ":    # [" + walk_unit + "]\n";
  };
  sensor(s.accel, "accelerometer", s.noise.accelerometer, "acceleration (g, m/s^2)", "m/s^2/sqrt(Hz)",
         "m/s^3/sqrt(Hz)");
  sensor(s.gyro, "gyroscope", s.noise.gyroscope, "rate (deg/s, rad/s)", "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)");
  return y;
}

std::string kalibr(const AnalysisResult& r, const Sensors& s, const EstimatorContext& ctx) {
  std::string y = header("Kalibr IMU configuration (imu.yaml, kalibr_calibrate_imu_camera --imu)", r, ctx);
  y += kalibr_keys(s, ctx, "", "Kalibr");
  y += "rostopic: " + ctx.rostopic + "\n";
  y += "update_rate: " + plain(r.rate_hz) + "  # [Hz] the record's sample rate\n";
  return y;
}

std::string openvins(const AnalysisResult& r, const Sensors& s, const EstimatorContext& ctx) {
  // OpenVINS reads this file through OpenCV's FileStorage, which wants the
  // directive on the first line.
  std::string y = "%YAML:1.0\n";
  y += header("OpenVINS IMU configuration (kalibr_imu_chain.yaml, relative_config_imu)", r, ctx);
  y += "# T_i_b: identity (imu0 is the body frame); time_offset: 0 (not measured by cubecal).\n"
       "# Tw, R_IMUtoGYRO, Ta, R_IMUtoACC, Tg are left out: OpenVINS takes identity / zero, i.e.\n"
       "# a calibrated IMU (cubecal calibrate multiposition / rate-table estimate them).\n";
  y += "\nimu0:\n";
  y += "  T_i_b:\n"
       "    - [1.0, 0.0, 0.0, 0.0]\n"
       "    - [0.0, 1.0, 0.0, 0.0]\n"
       "    - [0.0, 0.0, 1.0, 0.0]\n"
       "    - [0.0, 0.0, 0.0, 1.0]\n";
  y += kalibr_keys(s, ctx, "  ", "OpenVINS");
  y += "  rostopic: " + ctx.rostopic + "\n";
  y += "  time_offset: 0.0  # [s]\n";
  y += "  update_rate: " + plain(r.rate_hz) + "  # [Hz] the record's sample rate\n";
  y += "  model: \"kalibr\"\n";
  return y;
}

std::string vins(const AnalysisResult& r, const Sensors& s, const EstimatorContext& ctx) {
  std::string y = header("VINS-Mono / VINS-Fusion IMU parameters (the \"imu parameters\" block)", r, ctx);
  const double rate = r.rate_hz;
  y += face_words(
      "# Copy these keys into the VINS config (an OpenCV %YAML:1.0 file).\n"
      "# acc_n, gyr_n are the continuous-time noise densities sigma_w and acc_w, gyr_w the\n"
      "# continuous-time bias random walks sigma_bw, the same numbers Kalibr takes. VINS's\n"
      "# comments call them \"standard deviations\" and its pre-integration (integration_base.h)\n"
      "# multiplies their squares by dt^2 per IMU step; the published configs (acc_n 0.1,\n"
      "# gyr_n 0.01, acc_w 0.001, gyr_w 1e-4) are 10-100x what a static Allan analysis gives, to\n"
      "# cover motion, vibration and temperature. Inflate with {inflate} K rather than editing\n"
      "# by hand; the per-sample (discrete) equivalents are in each line's comment.\n");
  const double k = ctx.inflate;
  auto line = [&](const char* key, const Pick& p, const std::string& unit, bool walk) {
    const double v = p.value * k;
    y += std::string(key) + ": " + num(v) + note(p, unit, walk, k) + "; discrete " +
         num(walk ? v / std::sqrt(rate) : v * std::sqrt(rate)) + "\n";
  };
  if (s.accel) {
    line("acc_n", largest_white(s.noise.accelerometer), "m/s^2/sqrt(Hz)", false);
  } else {
    y += absent("accelerometer", "acceleration (g, m/s^2)", "VINS");
    y += "#acc_n:  # [m/s^2/sqrt(Hz)]\n";
  }
  if (s.gyro)
    line("gyr_n", largest_white(s.noise.gyroscope), "rad/s/sqrt(Hz)", false);
  else {
    y += absent("gyroscope", "rate (deg/s, rad/s)", "VINS");
    y += "#gyr_n:  # [rad/s/sqrt(Hz)]\n";
  }
  if (s.accel)
    line("acc_w", largest_walk(s.noise.accelerometer), "m/s^3/sqrt(Hz)", true);
  else
    y += "#acc_w:  # [m/s^3/sqrt(Hz)]\n";
  if (s.gyro)
    line("gyr_w", largest_walk(s.noise.gyroscope), "rad/s^2/sqrt(Hz)", true);
  else
    y += "#gyr_w:  # [rad/s^2/sqrt(Hz)]\n";
  const auto& acc = s.noise.accelerometer;
  if (acc.size() == 3) {
    const double g = std::sqrt(acc[0].mean * acc[0].mean + acc[1].mean * acc[1].mean + acc[2].mean * acc[2].mean);
    y += "g_norm: " + plain(g) + "  # [m/s^2] norm of the mean of " + acc[0].channel + ", " + acc[1].channel + ", " +
         acc[2].channel + " (static record; includes the accelerometer biases)\n";
  } else {
    y += "g_norm: " + plain(kStandardGravity) +
         "  # [m/s^2] standard gravity: the record has no three-axis accelerometer; use your local value\n";
  }
  return y;
}

// KF-GINS: three values per key (x, y, z of the IMU), bias as a first-order
// Gauss-Markov process with one correlation time for every bias.
std::string kf_gins(const AnalysisResult& r, const Sensors& s, const EstimatorContext& ctx) {
  std::string y = header("KF-GINS IMU noise parameters (the imunoise block of kf-gins.yaml)", r, ctx);
  y += "# KF-GINS reads arw [deg/sqrt(h)], vrw [m/s/sqrt(h)]: the noise densities sigma_w of\n"
       "# gyroscope and accelerometer (arw = sigma_w[rad/s/sqrt(Hz)] * 180/pi * 60,\n"
       "# vrw = sigma_w[m/s^2/sqrt(Hz)] * 60), and models each bias as a first-order\n"
       "# Gauss-Markov process of standard deviation gbstd [deg/h] (gyro), abstd [mGal]\n"
       "# (accelerometer, 1 mGal = 1e-5 m/s^2) and correlation time corrtime [h], driven with\n"
       "# 2 std^2 / corrtime. Biases: the bias instability B (slope read-off) with the time T of\n"
       "# the curve's minimum as corrtime; when the curve has no minimum within the record, the\n"
       "# lowest sigma / 0.664 with its tau, at the end of the record (UPPER BOUND: B lies below\n"
       "# it and, for a curve still falling, the correlation time beyond it).\n"
       "# corrtime is one value in KF-GINS: the shortest of the axes (the largest driving noise).\n"
       "# Axes: x, y, z in column order when the record has three channels of the sensor; else\n"
       "# the largest value on all three. KF-GINS's axes are forward, right, down: match columns.\n"
       "# gsstd, asstd (scale-factor instability) are not measured by a static record: keep the\n"
       "# values of your kf-gins.yaml.\n";
  const double k = ctx.inflate;
  auto triple = [&](const std::vector<AxisNoise>& axes, auto value, double factor) {
    std::array<double, 3> v{};
    if (axes.size() == 3) {
      for (std::size_t i = 0; i < 3; ++i) v[i] = value(axes[i]) * factor;
    } else {
      double m = 0.0;
      for (const auto& a : axes) m = std::max(m, value(a) * factor);
      v = {m, m, m};
    }
    std::string t = "[";
    for (std::size_t i = 0; i < 3; ++i) {
      t += num(v[i]);
      t += i < 2 ? ", " : "]";
    }
    return t;
  };
  auto names = [](const std::vector<AxisNoise>& axes) {
    std::string n;
    for (const auto& a : axes) n += (n.empty() ? "" : ", ") + a.channel;
    return (axes.size() == 3 ? "axes " : "largest of ") + n;
  };
  auto sources = [](const std::vector<AxisNoise>& axes, auto source) {
    std::string n;
    for (const auto& a : axes) {
      const std::string t(to_string(source(a)));
      if (n.find(t) == std::string::npos) n += (n.empty() ? "" : ", ") + t;
    }
    return n;
  };
  const auto white = [](const AxisNoise& a) { return a.white; };
  const auto white_src = [](const AxisNoise& a) { return a.white_source; };
  const auto bias = [](const AxisNoise& a) { return a.bias_std; };
  const auto bias_src = [](const AxisNoise& a) { return a.bias_source; };
  const std::string inflated = k != 1.0 ? " x inflate " + plain(k) : "";
  y += "imunoise:\n";
  if (s.gyro)
    y += "  arw: " + triple(s.noise.gyroscope, white, kRadToDeg * 60.0 * k) + "  # [deg/sqrt(h)] " +
         names(s.noise.gyroscope) + "; " + sources(s.noise.gyroscope, white_src) + inflated + "\n";
  else
    y += absent("gyroscope", "rate (deg/s, rad/s)", "KF-GINS") + "#  arw:  # [deg/sqrt(h)]\n";
  if (s.accel)
    y += "  vrw: " + triple(s.noise.accelerometer, white, 60.0 * k) + "  # [m/s/sqrt(h)] " +
         names(s.noise.accelerometer) + "; " + sources(s.noise.accelerometer, white_src) + inflated + "\n";
  else
    y += absent("accelerometer", "acceleration (g, m/s^2)", "KF-GINS") + "#  vrw:  # [m/s/sqrt(h)]\n";
  if (s.gyro)
    y += "  gbstd: " + triple(s.noise.gyroscope, bias, kRadToDeg * 3600.0 * k) + "  # [deg/h] " +
         names(s.noise.gyroscope) + "; " + sources(s.noise.gyroscope, bias_src) + inflated + "\n";
  else
    y += "#  gbstd:  # [deg/h]\n";
  if (s.accel)
    y += "  abstd: " + triple(s.noise.accelerometer, bias, k / kMilliGal) + "  # [mGal] " +
         names(s.noise.accelerometer) + "; " + sources(s.noise.accelerometer, bias_src) + inflated + "\n";
  else
    y += "#  abstd:  # [mGal]\n";
  y += "#  gsstd: [ , , ]  # [ppm] not measured: keep your value\n";
  y += "#  asstd: [ , , ]  # [ppm] not measured: keep your value\n";
  const AxisNoise* shortest = nullptr;
  for (const auto* axes : {&s.noise.gyroscope, &s.noise.accelerometer})
    for (const auto& a : *axes)
      if (!shortest || a.bias_tc < shortest->bias_tc) shortest = &a;
  y += "  corrtime: " + plain(shortest->bias_tc / 3600.0) + "  # [h] axis " + shortest->channel + ", " +
       std::string(to_string(shortest->bias_source)) + " (not inflated)\n";
  return y;
}

}  // namespace

std::optional<Estimator> parse_estimator(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<Estimator>(i);
  return std::nullopt;
}

std::string_view estimator_name(Estimator e) { return kNames[static_cast<std::size_t>(e)]; }

std::string estimator_names() {
  std::string s;
  for (const std::string_view n : kNames) {
    if (!s.empty()) s += '|';
    s += n;
  }
  return s;
}

std::string_view estimator_file(Estimator e) { return kFiles[static_cast<std::size_t>(e)]; }

void require_imu_units(const std::vector<Unit>& units) {
  if (std::none_of(units.begin(), units.end(),
                   [](const Unit& u) { return u.kind == SensorKind::rate || u.kind == SensorKind::acceleration; }))
    throw UsageError(Field::estimators,
                     "the record has no gyroscope (deg/s, rad/s) or accelerometer (g, m/s^2) channel: "
                     "give {units} of the IMU columns");
}

ImuNoise imu_noise(const AnalysisResult& r) {
  ImuNoise n;
  n.rate_hz = r.rate_hz;
  for (const auto& c : r.channels) {
    if (c.unit.kind == SensorKind::rate)
      n.gyroscope.push_back(axis_noise(c, r.file));
    else if (c.unit.kind == SensorKind::acceleration)
      n.accelerometer.push_back(axis_noise(c, r.file));
  }
  return n;
}

EstimatorFile estimator_config(Estimator e, const AnalysisResult& r, const EstimatorContext& ctx) {
  if (is_simulator(e)) return simulator_config(e, r, ctx);
  const Sensors s = sensors(r, ctx);
  EstimatorFile f{std::string(estimator_file(e)), {}, s.missing};
  switch (e) {
    case Estimator::kalibr: f.text = kalibr(r, s, ctx); break;
    case Estimator::openvins: f.text = openvins(r, s, ctx); break;
    case Estimator::vins: f.text = vins(r, s, ctx); break;
    case Estimator::kf_gins: f.text = kf_gins(r, s, ctx); break;
    default: break;  // the simulators, above
  }
  return f;
}

}  // namespace cubecal::pipeline
