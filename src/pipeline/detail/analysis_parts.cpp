#include "analysis_parts.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"

#include "cubecal/stats/allan_curve.hpp"

namespace cubecal::pipeline::detail {

void check_channel_lists(const AnalyzeRequest& req, std::size_t nch) {
  if (!req.units.empty() && req.units.size() != 1 && req.units.size() != nch)
    throw UsageError(Field::units, std::to_string(req.units.size()) + " units for " + std::to_string(nch) +
                                       " columns (give one unit, or one per column)");
  if (!req.lsb.empty() && req.lsb.size() != 1 && req.lsb.size() != nch)
    throw UsageError(Field::lsb, std::to_string(req.lsb.size()) + " values for " + std::to_string(nch) +
                                     " columns (give one value, or one per column)");
}

Unit unit_of(const AnalyzeRequest& req, std::size_t c) {
  return req.units.empty() ? *parse_unit("counts") : req.units[req.units.size() == 1 ? 0 : c];
}

double model_lsb(const AnalyzeRequest& req, std::size_t c) {
  return req.lsb.empty() ? 0.0 : req.lsb[req.lsb.size() == 1 ? 0 : c];
}

namespace {

std::string seconds(double s) { return fmt::format("{:.6g} s", s); }

}  // namespace

std::size_t drift_window(const AnalyzeRequest& req, const Unit& unit, double dt) {
  const double window_s =
      req.drift_window_s > 0.0 ? req.drift_window_s : (unit.kind == SensorKind::rate ? 300.0 : 1000.0);
  const double samples = window_s / dt;
  if (!(samples >= 0.5) && !(req.drift_window_s > 0.0)) return 0;  // the default, below one sample: no drift
  if (!(samples >= 0.5))
    throw UsageError(Field::drift_window, "{drift_window} " + seconds(window_s) +
                                              " is shorter than one sample (the sample period is " + seconds(dt) +
                                              "): give at least " + seconds(dt));
  // Beyond any record, and beyond what llround and size_t hold.
  if (!(samples < static_cast<double>(kMaxDriftWindow))) return kMaxDriftWindow;
  return static_cast<std::size_t>(std::llround(samples));
}

void check_drift_window(const AnalyzeRequest& req, AnalysisResult& r, std::size_t longest, std::size_t samples,
                        double dt) {
  const auto span = [dt](std::size_t n) { return seconds(static_cast<double>(n) * dt); };
  const std::string record =
      longest < samples ? "the longest gap-free part of the record (" + span(longest) + " of " + span(samples) + ")"
                        : "the record (" + span(samples) + ", " + std::to_string(samples) + " samples)";
  for (const ChannelAnalysis& ch : r.channels) {
    const std::size_t window = drift_window(req, ch.unit, dt);
    if (window == 0) {
      r.drift_skipped = "the default drift window (" + seconds(ch.unit.kind == SensorKind::rate ? 300.0 : 1000.0) +
                        ") is shorter than one sample (the sample period is " + seconds(dt) + "): give a longer one";
      return;
    }
    if (window <= longest) continue;
    if (req.drift_window_s > 0.0)
      throw UsageError(Field::drift_window, "{drift_window} " + seconds(req.drift_window_s) + " is longer than " +
                                                record + ": no moving average fits in it; give at most " +
                                                span(longest));
    r.drift_skipped = ("the default drift window (" + span(window) + " for " +
                       (ch.unit.kind == SensorKind::rate ? "rate sensors" : "this unit") + ") is longer than " +
                       record + ": give a shorter one");
    return;
  }
}

NoiseAnalysis noise_of(std::vector<StabilityPoint> points) {
  NoiseAnalysis n;
  n.adev = std::move(points);
  const AllanCurve curve = to_allan_curve(n.adev);
  n.readoffs = read_off_noise_terms(curve);
  n.fit = fit_noise_terms(curve);
  return n;
}

DevRequest oadev_request(const AnalyzeRequest& req) {
  DevRequest d;
  d.stat = Stat::oadev;
  d.type = DataType::freq;
  d.grid = req.grid;
  d.options.ci = req.ci;
  // The IMU curve's last taus (bias instability, rate random walk) are read
  // for numbers: their intervals never take a B1 misidentification for
  // precision (stats/stability.hpp).
  d.options.conservative_short = true;
  d.threads = req.threads;
  d.times = req.times;
  return d;
}

void fit_models(ModelAnalysis& m, double dt, double lsb) {
  const AllanCurve curve = to_allan_curve(m.adev);
  // The sample period and quantizer asked for, also when a fit fails.
  m.random_walk.dt = m.gauss_markov.dt = dt;
  m.random_walk.lsb = m.gauss_markov.lsb = lsb;
  try {
    m.random_walk = fit_random_walk_model(curve, dt, lsb);
    m.random_walk_residual = residual(m.random_walk, curve);
    m.ok = true;
  } catch (const CalibrationError& e) {
    m.error = face_words(e.text());
  } catch (const std::invalid_argument& e) {
    m.error = e.what();
  }
  try {
    m.gauss_markov = fit_gauss_markov_model(curve, dt, lsb);
    m.gauss_markov_residual = residual(m.gauss_markov, curve);
    // A correlation time pinned at the ends of the search (one sample, or
    // beyond the longest tau) means the curve shows no Gauss-Markov hump:
    // the "fit" is white noise or a random walk in disguise.
    const double tc = m.gauss_markov.tau_c;
    if (!(m.gauss_markov.sigma_b > 0.0) || tc < 2.0 * dt || tc > 2.0 * curve.tau.back()) {
      m.gm_error = fmt::format("no Gauss-Markov correlation time between {:.4g} s and {:.4g} s fits the curve",
                               2.0 * dt, 2.0 * curve.tau.back());
    } else {
      m.gm_ok = true;
    }
  } catch (const CalibrationError& e) {
    m.gm_error = face_words(e.text());
  } catch (const std::invalid_argument& e) {
    m.gm_error = e.what();
  }
}

void composite_residual(ModelAnalysis& m, double dt) {
  m.composite_residual = {};
  m.twin_error = {};
  if (!m.composite || m.adev.empty()) return;
  m.composite_residual = residual(m.composite->fit.model, dt, to_allan_curve(m.adev));
  m.twin_error = twin_error(m.composite->fit.model, m.adev);
}

}  // namespace cubecal::pipeline::detail
