// The figures of an analysis: Allan deviation with the fitted models and
// noise-term lines (the paper's Figs. 1, 2, 4), bias drift of the data and
// of the fitted model simulated (Figs. 3, 5), the temperature fit and the
// Allan deviation after temperature compensation. One of each per sensor group.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis_data.hpp"
#include "cubecal/field.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/report/html.hpp"
#include "cubecal/sim/simulator.hpp"

namespace cubecal::report::detail {

using pipeline::AnalysisResult;
using pipeline::ChannelAnalysis;

namespace {

constexpr const char* kPalette[] = {"#d62728", "#2ca02c", "#1f77b4", "#9467bd",
                                    "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
constexpr const char* kInk = "#444444";

const char* color(std::size_t k) { return kPalette[k % std::size(kPalette)]; }

std::string lower_first(std::string s) {
  if (!s.empty() && s[0] >= 'A' && s[0] <= 'Z') s[0] = static_cast<char>(s[0] - 'A' + 'a');
  return s;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

bool any_finite(const std::vector<double>& v) {
  return std::any_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

PlotSeries legend_entry(std::string label, const char* c, Dash dash = Dash::solid, Mark mark = Mark::line,
                        double opacity = 1.0) {
  PlotSeries s;
  s.label = std::move(label);
  s.color = c;
  s.dash = dash;
  s.mark = mark;
  s.opacity = opacity;
  return s;
}

// A channel's measured OADEV with its intervals as error lines.
PlotSeries measured_oadev(const std::vector<StabilityPoint>& curve, const std::string& channel, const char* c) {
  PlotSeries m;
  for (const auto& pt : curve) {
    m.x.push_back(pt.tau);
    m.y.push_back(pt.dev);
    m.lo.push_back(pt.interval.lo);
    m.hi.push_back(pt.interval.hi);
  }
  m.mark = Mark::errorlines;
  m.id = channel + " measured OADEV";
  m.color = c;
  m.width = 1.3;
  m.point_size = 0.25;
  return m;
}

// A power law a * tau^p drawn across [t0, t1] (a straight line in log-log).
PlotSeries term_line(double a, double p, double t0, double t1, const char* c, std::string id) {
  PlotSeries s;
  s.id = std::move(id);
  for (int i = 0; i <= 8; ++i) {
    const double t = t0 * std::pow(t1 / t0, i / 8.0);
    s.x.push_back(t);
    s.y.push_back(a * std::pow(t, p));
  }
  s.color = c;
  s.opacity = 0.35;
  s.width = 1.0;
  s.scale = false;
  return s;
}

// What an Allan figure draws beside the measured curves.
struct AllanDrawn {
  bool any_model = false, any_gm = false, any_composite = false, any_terms = false, any_twins = false;
};

// Channel k of the group: its measured curve, its models' curves, its
// twins' mean curve and its noise-term lines over [tmin, tmax].
void allan_channel_series(Plot& p, const AnalysisResult& d, const ChannelAnalysis& ch, std::size_t k, bool twin,
                          double tmin, double tmax, AllanDrawn& drawn) {
  bool& any_model = drawn.any_model;
  bool& any_gm = drawn.any_gm;
  bool& any_composite = drawn.any_composite;
  bool& any_terms = drawn.any_terms;
  bool& any_twins = drawn.any_twins;
  const char* c = color(k);
  const ModelCurves mc = model_curves(ch, d.rate_hz);
  std::vector<double> tau;
  for (const auto& pt : ch.noise.adev) tau.push_back(pt.tau);
  p.series.push_back(measured_oadev(ch.noise.adev, ch.name, c));
  // A model's curve, drawn when it has any point.
  const auto model_curve = [&](const std::vector<double>& y, const char* what, Dash dash, double width, bool& any) {
    if (!any_finite(y)) return;
    PlotSeries s;
    s.x = tau;
    s.y = y;
    s.id = ch.name + " " + what;
    s.dash = dash;
    s.color = c;
    s.width = width;
    p.series.push_back(std::move(s));
    any = true;
  };
  model_curve(mc.model, "random-walk model", Dash::dashed, 1.6, any_model);
  model_curve(mc.gm, "Gauss-Markov model", Dash::dotted, 1.8, any_gm);
  model_curve(mc.composite, twin ? "twin" : "composite model", Dash::dash_dot, 1.8, any_composite);
  // analyze --twin-check: the mean curve of the simulated twins, broad and light.
  if (d.twin_check)
    for (const pipeline::TwinCheckChannel& t : d.twin_check->channels)
      if (t.name == ch.name && !t.tau.empty()) {
        PlotSeries s;
        s.x = t.tau;
        s.y = t.twins;
        s.id = ch.name + " mean of twins";
        s.color = c;
        s.width = 4.0;
        s.opacity = 0.35;
        p.series.push_back(std::move(s));
        any_twins = true;
      }
  // Noise-term lines of the weighted fit: N (slope -1/2), K (+1/2), and the
  // bias-instability floor at sigma_min (0.664 B) where the curve has a minimum.
  if (tmax > tmin) {
    const auto& cf = ch.noise.fit.c;
    if (cf[1] > 0) p.series.push_back(term_line(std::sqrt(cf[1]), -0.5, tmin, tmax, c, ch.name + " N line"));
    if (cf[3] > 0) p.series.push_back(term_line(std::sqrt(cf[3]), 0.5, tmin, tmax, c, ch.name + " K line"));
    any_terms = any_terms || cf[1] > 0 || cf[3] > 0;
    std::optional<double> floor;
    if (ch.noise.readoffs.B.valid)
      floor = ch.noise.readoffs.sigma_min;
    else if (cf[2] > 0)
      floor = std::sqrt(cf[2]);
    if (floor && *floor > 0) {
      p.series.push_back(term_line(*floor, 0.0, tmin, tmax, c, ch.name + " B floor (0.664 B)"));
      any_terms = true;
    }
  }
}

// The legend (the channels' colours, then the kinds of curve drawn) and the notes.
void allan_legend(Plot& p, const AnalysisResult& d, const SensorGroup& g, const std::string& ci, bool twin,
                  const AllanDrawn& drawn) {
  const bool any_model = drawn.any_model, any_gm = drawn.any_gm, any_composite = drawn.any_composite;
  const bool any_terms = drawn.any_terms, any_twins = drawn.any_twins;
  for (std::size_t k = 0; k < g.channels.size(); ++k)
    p.series.push_back(legend_entry(d.channels[g.channels[k]].name, color(k)));
  p.series.push_back(legend_entry("measured, " + ci + " interval", kInk, Dash::solid, Mark::errorlines));
  if (any_model) p.series.push_back(legend_entry("random-walk model (paper eq. 1–3)", kInk, Dash::dashed));
  if (any_gm) p.series.push_back(legend_entry("Gauss–Markov model", kInk, Dash::dotted));
  if (any_composite)
    p.series.push_back(
        legend_entry(twin ? "twin (composite model, GMWM)" : "composite model (GMWM)", kInk, Dash::dash_dot));
  if (any_twins)
    p.series.push_back(legend_entry("mean of " + std::to_string(d.twin_check->twins) + " simulated twins", kInk,
                                    Dash::solid, Mark::line, 0.35));
  if (any_terms)
    p.series.push_back(legend_entry("noise terms: N (−½), B floor, K (+½)", kInk, Dash::solid, Mark::line, 0.35));
  p.notes.push_back("OADEV of each channel with its " + ci + " confidence interval (analysis.json adev),");
  p.notes.push_back(
      "model curves from the fitted parameters (analysis.json model), noise-term lines from the "
      "weighted fit (noise.fit.coefficients).");
}

// The caption: the kinds of curve drawn, as the paper's figures.
std::string allan_caption(const AnalysisResult& d, const SensorGroup& g, const std::string& ci, bool twin,
                          const AllanDrawn& drawn) {
  const bool any_model = drawn.any_model, any_gm = drawn.any_gm, any_composite = drawn.any_composite;
  const bool any_terms = drawn.any_terms, any_twins = drawn.any_twins;
  std::string cap = "Overlapping Allan deviation of the " + html_escape(lower_first(g.title)) + " (solid, " +
                    html_escape(ci) + " confidence intervals)";
  if (any_model) cap += ", the fitted random-walk model of the paper (dashed)";
  if (any_gm) cap += ", the Gauss–Markov alternative (dotted)";
  if (any_composite)
    cap += twin ? ", the twin: the composite noise model selected and fitted by the GMWM (dash-dotted)"
                : ", the composite noise model fitted by the GMWM (dash-dotted)";
  if (any_twins)
    cap += ", the mean Allan deviation of " + std::to_string(d.twin_check->twins) +
           " twins simulated at the record's length (broad, light)";
  if (any_terms)
    cap +=
        " and, light, the noise-term lines of the weighted fit: white noise N (slope −½), rate random walk K "
        "(+½) and the bias-instability floor 0.664 B";
  cap += ". As the paper's Figs. 1, 2 and 4.";
  return cap;
}

}  // namespace

ReportFigure allan_figure(const AnalysisResult& d, const SensorGroup& g) {
  const std::string ci = ci_text(d.ci);
  ReportFigure f;
  Plot& p = f.plot;
  p.name = "allan_" + g.key;
  p.title = "Allan deviation, " + lower_first(g.title);
  p.x = {"averaging time τ [s]", true, std::nullopt, std::nullopt};
  p.y = {"Allan deviation σ(τ) [" + g.unit + "]", true, std::nullopt, std::nullopt};
  p.key = "outside bottom center horizontal Left reverse maxrows 3";
  p.height = 640;
  AllanDrawn drawn;
  const bool twin = d.composite && pipeline::is_twin(d.composite->model);
  double tmin = INFINITY, tmax = 0;
  for (auto c : g.channels)
    for (const auto& pt : d.channels[c].noise.adev)
      if (pt.tau > 0) {
        tmin = std::min(tmin, pt.tau);
        tmax = std::max(tmax, pt.tau);
      }
  for (std::size_t k = 0; k < g.channels.size(); ++k)
    allan_channel_series(p, d, d.channels[g.channels[k]], k, twin, tmin, tmax, drawn);
  allan_legend(p, d, g, ci, twin, drawn);
  f.caption_html = allan_caption(d, g, ci, twin, drawn);
  return f;
}

namespace {

// "N 0.3218 deg/sqrt(h)", "sigma_b 0.0012 deg/h, T_c 34.2 s": a term's
// quantities as quoted.
std::string term_text(const pipeline::ModelTerm& t) {
  std::string text;
  for (const pipeline::ModelQuantity& q : t.quantities)
    text += (text.empty() ? "" : ", ") + q.name + " " + fmt("%.4g", q.display.value) + " " + q.display.unit;
  return text;
}

}  // namespace

ReportFigure composite_figure(const AnalysisResult& d, const ChannelAnalysis& ch, const std::string& name) {
  const pipeline::ModelChannel& mc = *ch.model.composite;
  const std::string ci = ci_text(d.ci);
  const double dt = 1.0 / d.rate_hz;
  ReportFigure f;
  Plot& p = f.plot;
  p.name = name;
  p.title = "Composite noise model of " + ch.name + ": " + mc.model;
  p.x = {"averaging time τ [s]", true, std::nullopt, std::nullopt};
  p.y = {"Allan deviation σ(τ) [" + ch.unit.name + "]", true, std::nullopt, std::nullopt};
  p.key = "outside bottom center horizontal Left reverse maxrows 4";
  p.height = 640;
  // The curve the models were fitted with (the record's, or its head's).
  const std::vector<StabilityPoint>& curve = ch.model.adev.empty() ? ch.noise.adev : ch.model.adev;
  PlotSeries m = measured_oadev(curve, ch.name, kInk);
  m.label = "measured OADEV, " + ci + " interval";
  p.series.push_back(std::move(m));
  // The moments the GMWM matched: the Haar wavelet variance at tau = 2^j
  // samples is half the Allan variance at m = 2^(j-1), drawn as the Allan
  // deviation sqrt(2 nu2) with its chi-square interval.
  PlotSeries w;
  for (std::size_t j = 0; j < mc.wv.size(); ++j) {
    w.x.push_back(0.5 * mc.wv.tau[j] * dt);
    w.y.push_back(std::sqrt(2.0 * mc.wv.nu2[j]));
    w.lo.push_back(std::sqrt(2.0 * mc.wv.interval[j].lo));
    w.hi.push_back(std::sqrt(2.0 * mc.wv.interval[j].hi));
  }
  w.mark = Mark::errorbars;
  w.id = ch.name + " Haar wavelet variance";
  w.label = "fitted scales: √(2ν²), " + ci + " interval (η₃ EDF)";
  w.color = "#1f77b4";
  w.point_size = 0.6;
  p.series.push_back(std::move(w));
  std::vector<double> tau;
  for (const auto& pt : curve) tau.push_back(pt.tau);
  for (std::size_t t = 0; t < mc.terms.size(); ++t) {
    PlotSeries s;
    for (double x : tau) {
      const double v = avar(mc.terms[t].process, static_cast<std::size_t>(std::max(1.0, std::round(x / dt))));
      if (!(v > 0.0)) continue;
      s.x.push_back(x);
      s.y.push_back(std::sqrt(v));
    }
    s.id = ch.name + " term " + std::to_string(t + 1) + " " + std::string(to_string(mc.terms[t].kind));
    s.label = std::string(to_string(mc.terms[t].kind)) + ": " + term_text(mc.terms[t]);
    s.color = color(t + 1);
    s.dash = Dash::dashed;
    s.width = 1.2;
    s.opacity = 0.8;
    s.scale = false;  // a term far below the curve does not stretch the axis
    if (!s.x.empty()) p.series.push_back(std::move(s));
  }
  PlotSeries total;
  for (double x : tau) {
    total.x.push_back(x);
    total.y.push_back(std::sqrt(avar(mc.fit.model, static_cast<std::size_t>(std::max(1.0, std::round(x / dt))))));
  }
  total.id = ch.name + " composite model";
  total.label = "the model: " + mc.model;
  total.color = color(0);
  total.width = 2.2;
  p.series.push_back(std::move(total));
  p.notes.push_back("measured: analysis.json channels[].adev (or model.adev, the curve the models were fitted on)");
  p.notes.push_back(
      "each term and the model: AVAR(m) = 2 nu2(2m), the exact Haar wavelet variance of the fitted "
      "per-sample parameters (analysis.json channels[].model.composite)");
  f.caption_html =
      "The composite noise model of <code>" + html_escape(ch.name) + "</code> (<code>" + html_escape(mc.model) +
      "</code>), fitted by the Generalized Method of Wavelet Moments: the measured Allan deviation "
      "with its " +
      html_escape(ci) +
      " intervals (grey), the Haar wavelet variances the fit matched (points, as √(2ν²) at τ = 2<sup>j−1</sup> "
      "samples), each term's contribution (dashed) and the model, their sum (bold). Each term's Allan "
      "variance is twice its Haar wavelet variance at the scale 2m, exact for the sampled process.";
  return f;
}

namespace {

struct SimDrift {
  bool ok = false;
  std::string process;  // "random walk" or "Gauss–Markov"
  DriftSeries d;
};

// The fitted model of each channel run for the record's length at its rate
// (white noise and bias process, no quantization, no temperature), averaged
// over the same window as the data.
std::vector<SimDrift> simulate_model_drift(const AnalysisResult& d, const SensorGroup& g, std::uint64_t seed) {
  std::vector<SimDrift> out(g.channels.size());
  const double dt = 1.0 / d.rate_hz;
  std::size_t n = d.samples;
  if (n == 0) n = static_cast<std::size_t>(std::llround(d.duration_s * d.rate_hz));
  for (std::size_t first = 0; first < g.channels.size(); first += 3) {
    TriadModel tm;
    tm.name = "report-model";
    std::array<std::size_t, 3> window{};
    bool any = false;
    for (std::size_t a = 0; a < 3 && first + a < g.channels.size(); ++a) {
      const ChannelAnalysis& ch = d.channels[g.channels[first + a]];
      const pipeline::ModelAnalysis& m = ch.model;
      if (ch.drift.window == 0) continue;
      window[a] = ch.drift.window;
      AxisModel& ax = tm.axes[a];
      if (m.ok) {
        ax.white_sigma = m.random_walk.sigma_n;
        ax.bias = BiasProcess::random_walk;
        ax.bias_sigma = m.random_walk.sigma_mu;
        out[first + a].process = "random walk";
      } else if (m.gm_ok && m.gauss_markov.tau_c > 0) {
        ax.white_sigma = m.gauss_markov.sigma_n;
        ax.bias = BiasProcess::gauss_markov;
        ax.bias_sigma = m.gauss_markov.sigma_b;
        ax.tau_c = m.gauss_markov.tau_c;
        out[first + a].process = "Gauss–Markov";
      } else {
        continue;
      }
      out[first + a].ok = true;
      any = true;
    }
    if (!any || n == 0) continue;
    TriadSimulator sim(tm, dt, seed + g.channels[first]);
    // Means of consecutive blocks of `block` samples (a divisor of the window,
    // about a tenth of it, as bias_drift's default stride), so that days of
    // samples need no memory: the moving average over the window at every
    // block boundary is the mean of window / block consecutive block means.
    std::array<std::size_t, 3> block{};
    std::array<std::vector<double>, 3> means;
    std::array<double, 3> acc{};
    std::array<std::size_t, 3> filled{};
    for (std::size_t a = 0; a < 3; ++a) {
      if (!(first + a < g.channels.size() && out[first + a].ok) || window[a] == 0) continue;
      std::size_t b = std::max<std::size_t>(1, window[a] / 10);
      while (window[a] % b != 0) --b;
      block[a] = b;
      means[a].reserve(n / b + 1);
    }
    constexpr std::size_t kChunk = 1 << 16;
    std::vector<double> buf(3 * kChunk);
    for (std::size_t i = 0; i < n; i += kChunk) {
      const std::size_t nb = std::min(kChunk, n - i);
      sim.run(nb, {}, {}, std::span<double>(buf.data(), 3 * nb));
      for (std::size_t a = 0; a < 3; ++a) {
        if (block[a] == 0) continue;
        for (std::size_t k = 0; k < nb; ++k) {
          acc[a] += buf[3 * k + a];
          if (++filled[a] == block[a]) {
            means[a].push_back(acc[a] / static_cast<double>(block[a]));
            acc[a] = 0.0;
            filled[a] = 0;
          }
        }
      }
    }
    for (std::size_t a = 0; a < 3; ++a) {
      if (block[a] == 0) continue;
      const double bdt = static_cast<double>(block[a]) * dt;
      DriftSeries ds = bias_drift(means[a], bdt, window[a] / block[a], 1);
      // Centre of the window in samples, not in blocks.
      for (double& t : ds.t) t += 0.5 * static_cast<double>(block[a] - 1) * dt;
      out[first + a].d = std::move(ds);
    }
  }
  return out;
}

}  // namespace

std::optional<ReportFigure> drift_figure(const AnalysisResult& d, const SensorGroup& g, const ReportOptions& o) {
  bool any = false;
  for (auto c : g.channels) any = any || !d.channels[c].drift.t.empty();
  if (!any) return std::nullopt;
  ReportFigure f;
  Plot& p = f.plot;
  p.name = "drift_" + g.key;
  p.title = "Bias drift, " + lower_first(g.title) + ": data and fitted model";
  p.x = {"time since the start of the record [h]", false, 0.0,
         d.duration_s > 0 ? std::optional(d.duration_s / 3600.0) : std::nullopt};
  p.y = {"bias drift [" + g.unit + "]", false, std::nullopt, std::nullopt};
  p.key = "outside bottom center horizontal Left reverse maxrows 2";
  const auto sim = simulate_model_drift(d, g, o.seed);
  std::vector<std::string> windows;
  bool any_model = false;
  std::string process;
  for (std::size_t k = 0; k < g.channels.size(); ++k) {
    const ChannelAnalysis& ch = d.channels[g.channels[k]];
    PlotSeries s;
    s.x = ch.drift.t;
    for (double& t : s.x) t /= 3600.0;
    s.y = ch.drift.drift;
    decimate_minmax(s.x, s.y, o.max_points);
    s.id = ch.name + " drift (data)";
    s.color = color(k);
    s.width = 1.2;
    if (!s.x.empty()) p.series.push_back(std::move(s));
    if (ch.drift.window > 0) {
      const std::string ws = fmt("%g s", static_cast<double>(ch.drift.window) / d.rate_hz);
      if (std::find(windows.begin(), windows.end(), ws) == windows.end()) windows.push_back(ws);
    }
    if (sim[k].ok && !sim[k].d.t.empty()) {
      PlotSeries m;
      m.x = sim[k].d.t;
      for (double& t : m.x) t /= 3600.0;
      m.y = sim[k].d.drift;
      decimate_minmax(m.x, m.y, o.max_points);
      m.id = ch.name + " drift (model, simulated)";
      m.color = color(k);
      m.dash = Dash::dashed;
      m.width = 1.2;
      m.opacity = 0.85;
      p.series.push_back(std::move(m));
      any_model = true;
      if (process.empty())
        process = sim[k].process;
      else if (process != sim[k].process)
        process = "fitted";
    }
  }
  std::string win;
  for (const auto& w : windows) win += (win.empty() ? "" : ", ") + w;
  for (std::size_t k = 0; k < g.channels.size(); ++k)
    p.series.push_back(legend_entry(d.channels[g.channels[k]].name, color(k)));
  p.series.push_back(legend_entry("data: " + win + " moving average − fixed bias", kInk));
  if (any_model) p.series.push_back(legend_entry("model, simulated (" + process + " bias)", kInk, Dash::dashed));
  p.notes.push_back("data: drift.csv (moving average of " + win + " minus the record mean), at most " +
                    std::to_string(o.max_points) + " points per series (min/max per bucket)");
  p.notes.push_back("model: the fitted sensor model (white noise + bias process, no quantization, no temperature)");
  p.notes.push_back("simulated by cubecal's TriadSimulator for the record's length and rate (seed " +
                    std::to_string(o.seed) + " + index of the triad's first channel), then averaged the same way");
  std::string cap = "Bias drift of the " + html_escape(lower_first(g.title)) + ": moving average over " +
                    html_escape(win) + " minus the fixed bias (solid)";
  if (any_model)
    cap += ", and the same for the fitted model (" + html_escape(process) +
           " bias plus white noise) simulated over the record's length and averaged the same way (dashed; one "
           "realization, so only its size and character compare, not its course)";
  cap += ". As the paper's Figs. 3 and 5.";
  f.caption_html = cap;
  return f;
}

namespace {

// The temperature spread the fit saw: R^2 = var(fit) / var(y) and, for the
// linear term, var(fit) = c1^2 var(T), so sigma_T = sqrt(R^2) std(y) / |c1|.
std::optional<double> temperature_sigma(const ChannelAnalysis& ch) {
  const TemperatureFit& t = ch.temperature->fit;
  if (t.coeff.size() < 2 || !std::isfinite(t.r2) || !std::isfinite(ch.stddev)) return std::nullopt;
  const double c1 = t.coeff[1];
  if (!std::isfinite(c1) || c1 == 0.0 || t.r2 <= 0) return std::nullopt;
  const double s = std::sqrt(t.r2) * ch.stddev / std::abs(c1);
  if (!std::isfinite(s) || s <= 0) return std::nullopt;
  return s;
}

}  // namespace

namespace {

// Channel k's fitted bias change over T_ref +- half (its polynomial
// without the offset, tr its own T_ref), with the linear coefficient moved by
// +-1 sigma when known; true when that band is drawn.
bool bias_change_series(Plot& p, const ChannelAnalysis& ch, std::size_t k, double t_ref, double half) {
  const TemperatureFit& t = ch.temperature->fit;
  // c1, c2, ...: the orders above the offset.
  std::vector<double> c, cs;
  if (t.coeff.size() > 1) c.assign(t.coeff.begin() + 1, t.coeff.end());
  if (t.coeff_sigma.size() > 1) cs.assign(t.coeff_sigma.begin() + 1, t.coeff_sigma.end());
  const double tr = std::isfinite(t.t_ref) ? t.t_ref : t_ref;
  auto poly = [&](double dT, double c1shift) {
    double y = 0.0, pw = 1.0;
    for (std::size_t q = 0; q < c.size(); ++q) {
      pw *= dT;
      y += (c[q] + (q == 0 ? c1shift : 0.0)) * pw;
    }
    return y;
  };
  PlotSeries s, up, dn;
  for (int i = 0; i <= 40; ++i) {
    const double T = t_ref - half + 2.0 * half * i / 40.0;
    s.x.push_back(T);
    s.y.push_back(poly(T - tr, 0.0));
    if (!cs.empty()) {
      up.x.push_back(T);
      up.y.push_back(poly(T - tr, cs[0]));
      dn.x.push_back(T);
      dn.y.push_back(poly(T - tr, -cs[0]));
    }
  }
  s.id = ch.name + " fitted bias change";
  s.color = color(k);
  s.width = 1.8;
  const std::string unit = ch.unit.name + "/degC";
  s.label =
      ch.name + ": " +
      format_pm(c.empty() ? std::nullopt : std::optional(c[0]), cs.empty() ? std::nullopt : std::optional(cs[0])) +
      " " + unit + (c.size() > 1 ? " (+ higher orders)" : "");
  p.series.push_back(std::move(s));
  if (!up.x.empty()) {
    for (PlotSeries* b : {&up, &dn}) {
      b->id = ch.name + (b == &up ? " fit, c1 + 1 sigma" : " fit, c1 - 1 sigma");
      b->color = color(k);
      b->width = 1.0;
      b->dash = Dash::dashed;
      b->opacity = 0.6;
      p.series.push_back(std::move(*b));
    }
    return true;
  }
  return false;
}

// The fitted bias change against temperature, the channels of `with`.
ReportFigure bias_change_figure(const AnalysisResult& d, const SensorGroup& g, const std::vector<std::size_t>& with) {
  // Fitted bias change against temperature.
  std::vector<double> sig;
  double t_ref = 0.0;
  for (auto k : with) {
    const ChannelAnalysis& ch = d.channels[g.channels[k]];
    if (const auto s = temperature_sigma(ch)) sig.push_back(*s);
    t_ref += std::isfinite(ch.temperature->fit.t_ref) ? ch.temperature->fit.t_ref : 0.0;
  }
  t_ref /= static_cast<double>(with.size());
  std::sort(sig.begin(), sig.end());
  const bool inferred = !sig.empty();
  const double half = inferred ? 2.0 * sig[sig.size() / 2] : 10.0;
  ReportFigure f;
  Plot& p = f.plot;
  p.name = "temperature_" + g.key;
  p.title = "Temperature dependence of the bias, " + lower_first(g.title);
  p.x = {"temperature [°C]", false, t_ref - half, t_ref + half};
  p.y = {"bias − bias at T_ref [" + g.unit + "]", false, std::nullopt, std::nullopt};
  p.key = "outside bottom center horizontal Left reverse maxrows 3";
  bool band = false;
  const std::string sensor = d.temp_name;
  for (auto k : with)
    if (bias_change_series(p, d.channels[g.channels[k]], k, t_ref, half)) band = true;
  if (band) p.series.push_back(legend_entry("linear coefficient ± 1σ", kInk, Dash::dashed, Mark::line, 0.6));
  p.notes.push_back("the fitted polynomial of analysis.json channels[].temperature (coeff, t_ref), offset removed");
  p.notes.push_back(inferred ? "temperature range: T_ref ± 2 sigma_T, sigma_T = sqrt(R^2) std(y) / |c1| (the record's "
                               "temperatures are not in the analysis files)"
                             : "temperature range: T_ref ± 10 degC (the spread could not be inferred)");
  std::string cap = "Bias change against temperature";
  if (!sensor.empty()) cap += " (sensor column <code>" + html_escape(sensor) + "</code>)";
  cap +=
      face_words(": the polynomial fitted by <code>{temp_index}</code>, relative to the bias at T<sub>ref</sub> = ") +
      html_escape(fmt("%.2f", t_ref)) + " °C";
  if (band) cap += ", with the linear coefficient moved by ±1σ (dashed)";
  cap += ". The record's temperatures are not part of the analysis files, so the raw points are not shown; ";
  if (inferred)
    cap += "the range drawn is T<sub>ref</sub> ± 2σ<sub>T</sub> with the temperature spread σ<sub>T</sub> ≈ " +
           html_escape(fmt("%.3g", half / 2.0)) +
           " °C inferred from the fit (σ<sub>T</sub> = √R² · std(y) / |c<sub>1</sub>|).";
  else
    cap += "the range drawn is T<sub>ref</sub> ± 10 °C (the spread could not be inferred from the fit).";
  f.caption_html = cap;
  return f;
}

// Channel k's Allan deviation as recorded and compensated, with the
// random-walk model of the compensated series; true when that model is drawn.
bool compensated_series(Plot& q, const AnalysisResult& d, const ChannelAnalysis& ch, std::size_t k) {
  PlotSeries raw;
  for (const auto& pt : ch.noise.adev) {
    raw.x.push_back(pt.tau);
    raw.y.push_back(pt.dev);
  }
  raw.id = ch.name + " as recorded";
  raw.color = color(k);
  raw.opacity = 0.4;
  raw.width = 1.2;
  q.series.push_back(std::move(raw));
  PlotSeries s;
  for (const auto& pt : ch.temperature->compensated.adev) {
    s.x.push_back(pt.tau);
    s.y.push_back(pt.dev);
    s.lo.push_back(pt.interval.lo);
    s.hi.push_back(pt.interval.hi);
  }
  s.mark = Mark::errorlines;
  s.id = ch.name + " temperature compensated";
  s.color = color(k);
  s.width = 1.4;
  s.point_size = 0.25;
  if (!s.x.empty()) q.series.push_back(std::move(s));
  // The random-walk model fitted to the compensated series.
  const pipeline::ModelAnalysis& cm = ch.temperature->compensated_model;
  if (cm.ok && d.rate_hz > 0) {
    PlotSeries m;
    for (const auto& pt : ch.temperature->compensated.adev) {
      const auto factor = static_cast<std::size_t>(std::max(1.0, std::round(pt.tau * d.rate_hz)));
      m.x.push_back(pt.tau);
      m.y.push_back(std::sqrt(avar(cm.random_walk, factor)));
    }
    m.id = ch.name + " compensated, random-walk model";
    m.color = color(k);
    m.width = 1.0;
    m.dash = Dash::dashed;
    if (!m.x.empty()) {
      q.series.push_back(std::move(m));
      return true;
    }
  }
  return false;
}

// The Allan deviation before and after compensation, the channels of `with`.
ReportFigure compensated_figure(const AnalysisResult& d, const SensorGroup& g, const std::vector<std::size_t>& with,
                                const std::string& ci) {
  // Allan deviation before and after compensation.
  ReportFigure h;
  Plot& q = h.plot;
  q.name = "compensated_" + g.key;
  q.title = "Allan deviation before and after temperature compensation, " + lower_first(g.title);
  q.x = {"averaging time τ [s]", true, std::nullopt, std::nullopt};
  q.y = {"Allan deviation σ(τ) [" + g.unit + "]", true, std::nullopt, std::nullopt};
  q.key = "outside bottom center horizontal Left reverse maxrows 3";
  bool comp_model = false;
  for (auto k : with)
    if (compensated_series(q, d, d.channels[g.channels[k]], k)) comp_model = true;
  for (auto k : with) q.series.push_back(legend_entry(d.channels[g.channels[k]].name, color(k)));
  q.series.push_back(legend_entry("as recorded", kInk, Dash::solid, Mark::line, 0.4));
  q.series.push_back(legend_entry("temperature compensated, " + ci + " interval", kInk, Dash::solid, Mark::errorlines));
  if (comp_model) q.series.push_back(legend_entry("random-walk model of the compensated series", kInk, Dash::dashed));
  h.caption_html = "Allan deviation of the " + html_escape(lower_first(g.title)) +
                   " as recorded (light) and after removing the fitted temperature dependence (with " +
                   html_escape(ci) + " intervals): what the temperature swing adds at long averaging times.";
  return h;
}

}  // namespace

std::vector<ReportFigure> temperature_figures(const AnalysisResult& d, const SensorGroup& g) {
  std::vector<std::size_t> with;
  for (std::size_t k = 0; k < g.channels.size(); ++k)
    if (d.channels[g.channels[k]].temperature) with.push_back(k);
  if (with.empty()) return {};
  std::vector<ReportFigure> figs;
  const std::string ci = ci_text(d.ci);
  figs.push_back(bias_change_figure(d, g, with));
  figs.push_back(compensated_figure(d, g, with, ci));
  return figs;
}

}  // namespace cubecal::report::detail
