// The report page of an analysis as a CommandReport: input summary, the
// command that reproduces it, figures, parameter tables (units,
// uncertainties), fitted models, temperature dependence and covariance, all
// from the typed result. Every string from the data is escaped.
#include "cubecal/field.hpp"
#include "cubecal/report/analysis_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "analysis_data.hpp"
#include "command_util.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/spectral_analysis.hpp"
#include "cubecal/report/html.hpp"
#include "spectrum_figure.hpp"

namespace cubecal::report {

using pipeline::AnalysisResult;
using pipeline::ChannelAnalysis;

namespace detail {

namespace {

// rate, field or other.
std::string kind_class(const Unit& u) {
  if (u.kind == SensorKind::rate) return "rate";
  if (u.kind == SensorKind::field) return "field";
  return "other";
}

std::string class_title(const std::string& cls) {
  if (cls == "rate") return "Rate sensors";
  if (cls == "field") return "Field sensors";
  return "Other sensors";
}

std::string unit_slug(const std::string& u) {
  std::string s;
  for (char c : u) {
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'))
      s += c;
    else if (!s.empty() && s.back() != '_')
      s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  return s.empty() ? std::string("u") : s;
}

}  // namespace

std::vector<SensorGroup> sensor_groups(const AnalysisResult& r) {
  // Sensor groups: rate, field, other; split by unit when a kind mixes units.
  std::vector<std::pair<std::string, std::string>> keys;  // (class, unit) in first-seen order
  for (const auto& ch : r.channels) {
    const std::pair<std::string, std::string> k{kind_class(ch.unit), ch.unit.name};
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  }
  std::vector<SensorGroup> groups;
  for (const auto& k : keys) {
    SensorGroup g;
    const auto same_class = std::count_if(keys.begin(), keys.end(), [&](const auto& o) { return o.first == k.first; });
    g.key = same_class > 1 ? k.first + "_" + unit_slug(k.second) : k.first;
    g.unit = k.second;
    g.title = class_title(k.first) + (k.second.empty() ? std::string() : " (" + k.second + ")");
    for (std::size_t c = 0; c < r.channels.size(); ++c)
      if (kind_class(r.channels[c].unit) == k.first && r.channels[c].unit.name == k.second) g.channels.push_back(c);
    groups.push_back(std::move(g));
  }
  return groups;
}

std::string ci_text(double ci) {
  if (!(ci > 0 && ci < 1)) return "68.3 %";
  char b[32];
  std::snprintf(b, sizeof b, "%.4g %%", 100.0 * ci);
  return b;
}

ModelCurves model_curves(const ChannelAnalysis& c, double rate_hz) {
  const auto n = c.noise.adev.size();
  ModelCurves m;
  m.fit.assign(n, NAN);
  m.model.assign(n, NAN);
  m.gm.assign(n, NAN);
  m.composite.assign(n, NAN);
  const double dt = 1.0 / rate_hz;
  for (std::size_t i = 0; i < n; ++i) {
    const double tau = c.noise.adev[i].tau;
    const auto k = static_cast<std::size_t>(std::max(1.0, std::round(tau / dt)));
    m.fit[i] = noise_model_adev(c.noise.fit.c, tau);
    if (c.model.ok) m.model[i] = std::sqrt(avar(c.model.random_walk, k));
    if (c.model.gm_ok) m.gm[i] = std::sqrt(avar(c.model.gauss_markov, k));
    if (c.model.composite) m.composite[i] = std::sqrt(avar(c.model.composite->fit.model, k));
  }
  return m;
}

}  // namespace detail

namespace {

using detail::SensorGroup;

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::optional<double> finite(double v) { return std::isfinite(v) ? std::optional(v) : std::nullopt; }

std::string duration_text(double s) {
  if (!(s > 0)) return "—";
  const double h = s / 3600.0;
  if (h >= 1.0) return fmt("%.6g s", s) + " (" + fmt("%.4g h", h) + ")";
  if (s >= 60.0) return fmt("%.6g s", s) + " (" + fmt("%.4g min", s / 60.0) + ")";
  return fmt("%.6g s", s);
}

using Cell = std::pair<std::string, std::string>;  // (html, title)

// A parameter table with one column per channel of a group.
class Table {
 public:
  Table(const AnalysisResult& r, const SensorGroup& g) : r_(r), g_(g) {
    s_ = "<div class=\"scroll\"><table>\n<thead><tr><th>parameter</th><th>unit</th>";
    for (auto c : g.channels) s_ += "<th>" + html_escape(r.channels[c].name) + "</th>";
    s_ += "</tr></thead>\n<tbody>\n";
  }
  void section(const std::string& title_html) {
    s_ += "<tr class=\"sub\"><th colspan=\"" + std::to_string(g_.channels.size() + 2) + "\">" + title_html +
          "</th></tr>\n";
  }
  // A row of cells from the channels; left out when every cell is empty ("—")
  // unless it is a noise-term row.
  void row(const std::string& label_html, const std::string& unit,
           const std::function<Cell(const ChannelAnalysis&)>& cell, bool keep_empty = false) {
    std::string r = "<tr><th>" + label_html + "</th><td class=\"unit\">" + html_escape(unit) + "</td>";
    bool any = false;
    for (auto c : g_.channels) {
      const auto [html, title] = cell(r_.channels[c]);
      if (html != "—") any = true;
      r += "<td class=\"num\"" + (title.empty() ? std::string() : " title=\"" + html_escape(title) + "\"") + ">" +
           html + "</td>";
    }
    r += "</tr>\n";
    if (any || keep_empty) s_ += r;
  }
  // A noise term in its display unit, with the tau range it was read from.
  void term(const std::string& label_html, Term which,
            const std::function<const TermEstimate*(const ChannelAnalysis&)>& get) {
    std::string unit;
    if (!g_.channels.empty()) unit = display(TermEstimate{}, which, r_.channels[g_.channels.front()].unit).unit;
    row(
        label_html, unit,
        [&](const ChannelAnalysis& ch) {
          const TermEstimate* t = get(ch);
          if (!t || !t->valid) return Cell{"—", ""};
          const Quantity q = display(*t, which, ch.unit);
          std::string html = html_escape(format_pm(finite(q.value), finite(q.sigma)));
          if (q.unit != unit && html != "—") html += " " + html_escape(q.unit);
          const std::string title =
              "read over tau " + format_num(t->tau_lo, 4) + " to " + format_num(t->tau_hi, 4) + " s";
          return Cell{html, title};
        },
        true);
  }
  void value(const std::string& label_html, const std::string& unit,
             const std::function<std::optional<double>(const ChannelAnalysis&)>& get, int digits = 5) {
    row(label_html, unit, [&](const ChannelAnalysis& ch) {
      return Cell{html_escape(format_num(get(ch), digits)), ""};
    });
  }
  // Why something was not fitted: a note under the table, not a cell.
  void reason(const std::string& what_html, const std::function<std::string(const ChannelAnalysis&)>& get) {
    for (auto c : g_.channels) {
      const std::string v = get(r_.channels[c]);
      if (!v.empty())
        notes_ += "<li><b>" + html_escape(r_.channels[c].name) + "</b>: " + what_html +
                  " not fitted: " + html_escape(v) + "</li>\n";
    }
  }
  std::string str() const {
    return s_ + "</tbody></table></div>\n" + (notes_.empty() ? "" : "<ul class=\"reasons\">\n" + notes_ + "</ul>\n");
  }

 private:
  const AnalysisResult& r_;
  const SensorGroup& g_;
  std::string s_, notes_;
};

std::optional<double> count(std::size_t n) { return static_cast<double>(n); }

// The display unit of a term for the group (its first channel's).
std::string unit_of(const AnalysisResult& r, const SensorGroup& g, Term which) {
  if (g.channels.empty()) return "";
  return display(TermEstimate{}, which, r.channels[g.channels.front()].unit).unit;
}

// The slope read-offs (IEEE 952, as the paper).
void readoff_rows(Table& t, const AnalysisResult& r, const SensorGroup& g) {
  t.section(
      "Slope read-offs (IEEE 952, as the paper): N on the −1/2 line at τ = 1 s, B = σ<sub>min</sub> / 0.664, "
      "K at τ = 3 s");
  t.term("N, white noise (angle random walk): the reported N", Term::N,
         [](const ChannelAnalysis& c) { return &c.noise.readoffs.N; });
  t.row("N read over τ", "s", [](const ChannelAnalysis& c) {
    const auto& n = c.noise.readoffs.N;
    if (!n.valid) return Cell{"—", "no −1/2 slope in the curve"};
    const bool at_1s = n.tau_lo <= 1.0 && 1.0 <= n.tau_hi;
    return Cell{
        html_escape(format_num(n.tau_lo, 3) + "–" + format_num(n.tau_hi, 3) + (at_1s ? "" : " (extended to 1 s)")),
        at_1s ? "the −1/2 line through the curve around τ = 1 s"
              : "the curve is not white at 1 s: the line of its white arm extended to 1 s"};
  });
  t.row(
      "B, bias instability", unit_of(r, g, Term::B),
      [](const ChannelAnalysis& c) {
        const auto& ro = c.noise.readoffs;
        const ReportedTerms rt = reported_terms(ro, c.noise.fit, to_allan_curve(c.noise.adev));
        if (rt.constant) return Cell{"—", ""};
        const Quantity q = display(rt.B.estimate, Term::B, c.unit);
        if (rt.no_minimum)
          return Cell{"no minimum within the record (&lt; " + html_escape(format_num(q.value, 4)) + ")",
                      "the curve is lowest at an end of the record: sigma_min / 0.664 only bounds B from above"};
        return Cell{html_escape(format_pm(finite(q.value), finite(q.sigma))),
                    "read over tau " + format_num(ro.B.tau_lo, 4) + " to " + format_num(ro.B.tau_hi, 4) + " s"};
      },
      true);
  t.row("T, time constant (τ at the minimum)", "s", [](const ChannelAnalysis& c) {
    const auto& ro = c.noise.readoffs;
    if (!ro.B.valid) return Cell{"—", "no minimum inside the record"};
    const std::string h =
        format_num(ro.tau_min, 4) + " (" + format_num(ro.tau_min_lo, 3) + "–" + format_num(ro.tau_min_hi, 3) + ")";
    return Cell{html_escape(h), "range: taus whose intervals reach sigma_min"};
  });
  t.value("σ<sub>min</sub>, minimum of the curve", g.unit,
          [](const ChannelAnalysis& c) { return finite(c.noise.readoffs.sigma_min); });
  t.term("K, rate random walk (read-off)", Term::K, [](const ChannelAnalysis& c) { return &c.noise.readoffs.K; });
  t.row(
      "K reported (estimator files): significant when > 2σ", unit_of(r, g, Term::K),
      [](const ChannelAnalysis& c) {
        const ReportedTerms rt = reported_terms(c.noise.readoffs, c.noise.fit, to_allan_curve(c.noise.adev));
        if (!rt.K.estimate.valid) return Cell{"—", ""};
        const Quantity q = display(rt.K.estimate, Term::K, c.unit);
        if (!rt.K.bound())
          return Cell{html_escape(format_pm(finite(q.value), finite(q.sigma))) + " (" +
                          html_escape(std::string(to_string(rt.K.source))) + ")",
                      "significant: value > 2 sigma"};
        return Cell{"&lt; " + html_escape(format_num(q.value, 4)) + " (upper bound)",
                    rt.K_candidate.valid ? "K estimated but not significant (value <= 2 sigma)"
                                         : "no K in the record: min over tau of sigma sqrt(3/tau)"};
      },
      true);
  t.term("Q, quantization", Term::Q, [](const ChannelAnalysis& c) { return &c.noise.readoffs.Q; });
  t.term("R, rate ramp", Term::R, [](const ChannelAnalysis& c) { return &c.noise.readoffs.R; });
}

// The weighted least-squares fit of the curve.
void curve_fit_rows(Table& t) {
  t.section("Weighted least-squares fit of σ²(τ) = Σ C<sub>k</sub> τ<sup>k</sup>, k = −2…2");
  t.term("white-noise term √C<sub>−1</sub> (the fit's, not the reported N)", Term::N,
         [](const ChannelAnalysis& c) { return &c.noise.fit.N; });
  t.term("B, bias instability", Term::B, [](const ChannelAnalysis& c) { return &c.noise.fit.B; });
  t.term("K, rate random walk", Term::K, [](const ChannelAnalysis& c) { return &c.noise.fit.K; });
  t.term("Q, quantization", Term::Q, [](const ChannelAnalysis& c) { return &c.noise.fit.Q; });
  t.term("R, rate ramp", Term::R, [](const ChannelAnalysis& c) { return &c.noise.fit.R; });
  t.row("χ² / degrees of freedom", "", [](const ChannelAnalysis& c) {
    if (!std::isfinite(c.noise.fit.chi2)) return Cell{"—", ""};
    return Cell{html_escape(format_num(c.noise.fit.chi2, 4) + " / " + format_num(count(c.noise.fit.dof), 6)), ""};
  });
  t.row("RMS relative residual", "%", [](const ChannelAnalysis& c) {
    const auto v = finite(c.noise.fit.rms_rel_residual);
    return Cell{v ? html_escape(format_num(100.0 * *v, 3)) : std::string("—"), ""};
  });
}

// The noise densities of the reported N and K.
void density_rows(Table& t, const AnalysisResult& r, const SensorGroup& g) {
  // Densities from the fit where it found the term, else from the read-off.
  auto density = [&](const std::string& label, bool white, bool si) {
    std::string unit;
    if (!g.channels.empty()) {
      const Unit& u = r.channels[g.channels.front()].unit;
      unit = white ? white_density(TermEstimate{}, u, si).unit : random_walk_density(TermEstimate{}, u, si).unit;
    }
    t.row(
        label, unit,
        [&](const ChannelAnalysis& c) {
          const ReportedTerms rt = reported_terms(c.noise.readoffs, c.noise.fit, to_allan_curve(c.noise.adev));
          const ReportedTerm& rep = white ? rt.N : rt.K;
          const TermEstimate& e = rep.estimate;
          if (!e.valid) return Cell{"—", ""};
          const Quantity q = white ? white_density(e, c.unit, si) : random_walk_density(e, c.unit, si);
          if (rep.bound()) return Cell{"&lt; " + html_escape(format_num(q.value, 4)) + " (upper bound)", ""};
          return Cell{html_escape(format_pm(finite(q.value), finite(q.sigma))), ""};
        },
        true);
  };
  t.section("Noise densities of the reported N and K (as in the estimator files)");
  density("white noise density", true, false);
  density("white noise density, SI", true, true);
  density("random-walk density", false, false);
  density("random-walk density, SI", false, true);
}

std::string noise_table(const AnalysisResult& r, const SensorGroup& g) {
  Table t(r, g);
  t.section("Record");
  t.value(
      "fixed bias β (record mean)", g.unit, [](const ChannelAnalysis& c) { return finite(c.mean); }, 7);
  t.value("standard deviation", g.unit, [](const ChannelAnalysis& c) { return finite(c.stddev); });
  readoff_rows(t, r, g);
  curve_fit_rows(t);
  density_rows(t, r, g);
  return t.str();
}

std::string model_table(const AnalysisResult& r, const SensorGroup& g) {
  Table t(r, g);
  t.section("Random-walk model (paper eq. 1–3): tangent to the white-noise arm, same minimum");
  t.value("σ<sub>n</sub>, white noise per sample", g.unit,
          [](const ChannelAnalysis& c) { return c.model.ok ? finite(c.model.random_walk.sigma_n) : std::nullopt; });
  t.value("σ<sub>μ</sub>, bias random-walk rate", g.unit + "/s",
          [](const ChannelAnalysis& c) { return c.model.ok ? finite(c.model.random_walk.sigma_mu) : std::nullopt; });
  t.row("quantizer (m<sub>lsb</sub>)", "counts/" + g.unit, [](const ChannelAnalysis& c) {
    if (!c.model.ok) return Cell{"—", ""};
    const double v = c.model.random_walk.lsb;
    return Cell{v > 0 ? html_escape(format_num(v, 6)) : std::string("none"), ""};
  });
  t.value(
      "samples fitted", "", [](const ChannelAnalysis& c) { return count(c.model.samples); }, 10);
  t.value(
      "Allan-curve residual, RMS of ln(model / data)", "",
      [](const ChannelAnalysis& c) { return c.model.ok ? finite(c.model.random_walk_residual.rms_log) : std::nullopt; },
      3);
  t.reason("random-walk model", [](const ChannelAnalysis& c) { return c.model.ok ? std::string() : c.model.error; });
  t.section("Gauss–Markov alternative: white noise + first-order Gauss–Markov bias");
  t.value("σ<sub>b</sub>, stationary bias", g.unit,
          [](const ChannelAnalysis& c) { return c.model.gm_ok ? finite(c.model.gauss_markov.sigma_b) : std::nullopt; });
  t.value("T<sub>c</sub>, correlation time", "s",
          [](const ChannelAnalysis& c) { return c.model.gm_ok ? finite(c.model.gauss_markov.tau_c) : std::nullopt; });
  t.value("σ<sub>n</sub>, white noise per sample", g.unit,
          [](const ChannelAnalysis& c) { return c.model.gm_ok ? finite(c.model.gauss_markov.sigma_n) : std::nullopt; });
  t.value(
      "Allan-curve residual, RMS of ln(model / data)", "",
      [](const ChannelAnalysis& c) {
        return c.model.gm_ok ? finite(c.model.gauss_markov_residual.rms_log) : std::nullopt;
      },
      3);
  t.reason("Gauss–Markov model",
           [](const ChannelAnalysis& c) { return c.model.gm_ok ? std::string() : c.model.gm_error; });
  t.row("the better fit", "", [](const ChannelAnalysis& c) {
    if (!c.model.ok || !c.model.gm_ok) return Cell{"—", ""};
    const bool gm = c.model.gauss_markov_residual.rms_log < c.model.random_walk_residual.rms_log;
    return Cell{gm ? "Gauss–Markov" : "random walk", "smaller RMS of ln(model / data)"};
  });
  if (r.composite) {
    const bool twin = pipeline::is_twin(r.composite->model);
    t.section(twin ? "Twin (composite noise model selected and fitted by the GMWM, docs/twins.md): terms and "
                     "uncertainties in the section “Composite noise model”"
                   : face_words("Composite noise model (GMWM, <code>analyze {composite}</code>): terms and "
                                "uncertainties in the section “Composite noise model”"));
    t.row("model", "", [](const ChannelAnalysis& c) {
      if (!c.model.composite) return Cell{"—", ""};
      const pipeline::ModelChannel& m = *c.model.composite;
      if (m.fidelity)
        return Cell{html_escape(m.model), "the twin's search passed " + std::to_string(m.candidates.size()) +
                                              " models; " + std::to_string(m.lines.size()) + " spectral line(s) found"};
      return Cell{html_escape(m.model),
                  m.candidates.size() > 1
                      ? "selected by the WIC among " + std::to_string(m.candidates.size()) + " candidates"
                      : std::string("as asked")};
    });
    t.value(
        "twin error: largest |σ_model / σ − 1| on the Allan curve", "%",
        [](const ChannelAnalysis& c) {
          return c.model.composite ? finite(100.0 * c.model.twin_error.max_error) : std::nullopt;
        },
        3);
    t.value(
        "taus whose model deviation lies inside the curve's interval", "%",
        [](const ChannelAnalysis& c) {
          return c.model.composite ? finite(100.0 * c.model.twin_error.share_inside) : std::nullopt;
        },
        3);
    t.value(
        "Allan-curve residual, RMS of ln(model / data)", "",
        [](const ChannelAnalysis& c) {
          return c.model.composite ? finite(c.model.composite_residual.rms_log) : std::nullopt;
        },
        3);
    t.row("the best fit of the three", "", [](const ChannelAnalysis& c) {
      if (!c.model.composite) return Cell{"—", ""};
      const pipeline::ModelAnalysis& m = c.model;
      std::string best = "composite";
      double least = m.composite_residual.rms_log;
      if (m.ok && m.random_walk_residual.rms_log < least) {
        best = "random walk";
        least = m.random_walk_residual.rms_log;
      }
      if (m.gm_ok && m.gauss_markov_residual.rms_log < least) best = "Gauss–Markov";
      return Cell{best, "smallest RMS of ln(model / data)"};
    });
  }
  t.section("Bias drift");
  t.value("moving-average window", "s",
          [&](const ChannelAnalysis& c) { return finite(static_cast<double>(c.drift.window) / r.rate_hz); });
  t.value(
      "drift points (drift.csv)", "", [](const ChannelAnalysis& c) { return count(c.drift.t.size()); }, 10);
  return t.str();
}

// The polynomial fit of each channel on temperature.
void temperature_fit_rows(Table& t, const AnalysisResult& r, const SensorGroup& g) {
  std::size_t order = 0;  // highest power fitted
  for (auto c : g.channels)
    if (r.channels[c].temperature && !r.channels[c].temperature->fit.coeff.empty())
      order = std::max(order, r.channels[c].temperature->fit.coeff.size() - 1);
  auto fit_of = [](const ChannelAnalysis& c) -> const TemperatureFit* {
    return c.temperature ? &c.temperature->fit : nullptr;
  };
  auto tan_of = [](const ChannelAnalysis& c) -> const pipeline::TemperatureAnalysis* {
    return c.temperature ? &*c.temperature : nullptr;
  };
  t.section(
      "Polynomial fit of the channel on temperature, y = Σ c<sub>p</sub> (T − T<sub>ref</sub>)<sup>p</sup> + "
      "random-walk bias + white noise");
  t.row("temperature column", "", [&](const ChannelAnalysis& c) {
    return c.temperature ? Cell{html_escape(r.temp_name), ""} : Cell{"—", ""};
  });
  t.row("estimator", "", [&](const ChannelAnalysis& c) {
    const auto* a = tan_of(c);
    if (!a) return Cell{"—", ""};
    return a->joint
               ? Cell{"jointly with the random-walk bias (GLS, Kalman filter)",
                      "noise model fitted to the compensated record; docs/formulas/drift-covariance-temperature.md §4"}
               : Cell{"least squares", html_escape(a->joint_error)};
  });
  t.value("T<sub>ref</sub> (mean temperature)", "°C", [&](const ChannelAnalysis& c) {
    const auto* f = fit_of(c);
    return f ? finite(f->t_ref) : std::nullopt;
  });
  for (std::size_t p = 1; p <= order; ++p) {
    const std::string unit = g.unit + (p == 1 ? "/degC" : "/degC^" + std::to_string(p));
    const std::string label =
        p == 1 ? std::string("c<sub>1</sub>, temperature coefficient") : "c<sub>" + std::to_string(p) + "</sub>";
    t.row(label, unit, [&](const ChannelAnalysis& c) {
      const auto* f = fit_of(c);
      if (!f || f->coeff.size() <= p) return Cell{"—", ""};
      return Cell{html_escape(format_pm(finite(f->coeff[p]),
                                        f->coeff_sigma.size() > p ? finite(f->coeff_sigma[p]) : std::nullopt)),
                  ""};
    });
  }
  t.row("c<sub>1</sub> by least squares (batch-means sandwich σ)", g.unit + "/degC", [&](const ChannelAnalysis& c) {
    const auto* a = tan_of(c);
    if (!a || !a->joint || a->ols.coeff.size() < 2) return Cell{"—", ""};
    return Cell{html_escape(format_pm(finite(a->ols.coeff[1]),
                                      a->ols.coeff_sigma.size() > 1 ? finite(a->ols.coeff_sigma[1]) : std::nullopt)),
                "for comparison; scatters more than the joint estimate"};
  });
  t.value("σ<sub>μ</sub> the joint estimate weighted with", g.unit + "/s", [&](const ChannelAnalysis& c) {
    const auto* a = tan_of(c);
    return a && a->joint ? finite(a->noise.sigma_mu) : std::nullopt;
  });
  t.value(
      "c<sub>0</sub>, bias at T<sub>ref</sub>", g.unit,
      [&](const ChannelAnalysis& c) {
        const auto* f = fit_of(c);
        return f && !f->coeff.empty() ? finite(f->coeff[0]) : std::nullopt;
      },
      7);
  t.value(
      "R²", "",
      [&](const ChannelAnalysis& c) {
        const auto* f = fit_of(c);
        return f ? finite(f->r2) : std::nullopt;
      },
      4);
  t.value(
      "residual RMS", g.unit,
      [&](const ChannelAnalysis& c) {
        const auto* f = fit_of(c);
        return f ? finite(f->residual_rms) : std::nullopt;
      },
      4);
}

// The noise terms of the compensated series (slope read-offs).
void compensated_noise_rows(Table& t) {
  t.section("Noise terms after compensation (slope read-offs)");
  auto comp = [](const ChannelAnalysis& c) -> const SlopeReadOffs* {
    return c.temperature ? &c.temperature->compensated.readoffs : nullptr;
  };
  t.term("N, white noise", Term::N, [&](const ChannelAnalysis& c) { return comp(c) ? &comp(c)->N : nullptr; });
  t.term("B, bias instability", Term::B, [&](const ChannelAnalysis& c) { return comp(c) ? &comp(c)->B : nullptr; });
  t.value(
      "T, time constant", "s",
      [&](const ChannelAnalysis& c) { return comp(c) && comp(c)->B.valid ? finite(comp(c)->tau_min) : std::nullopt; },
      4);
  t.term("K, rate random walk", Term::K, [&](const ChannelAnalysis& c) { return comp(c) ? &comp(c)->K : nullptr; });
}

// The sensor models of the compensated series.
void compensated_model_rows(Table& t, const SensorGroup& g) {
  // The sensor models of the compensated series beside the record's (Models
  // table): a temperature cycle raises the record's σ_μ.
  auto cm = [&](const ChannelAnalysis& c) -> const pipeline::ModelAnalysis* {
    return c.temperature ? &c.temperature->compensated_model : nullptr;
  };
  t.section("Sensor models after compensation (beside them in the Models table: the same fits to the record)");
  t.value("σ<sub>n</sub>, white noise per sample", g.unit, [&](const ChannelAnalysis& c) {
    return cm(c) && cm(c)->ok ? finite(cm(c)->random_walk.sigma_n) : std::nullopt;
  });
  t.value("σ<sub>μ</sub>, bias random-walk rate", g.unit + "/s", [&](const ChannelAnalysis& c) {
    return cm(c) && cm(c)->ok ? finite(cm(c)->random_walk.sigma_mu) : std::nullopt;
  });
  t.value("σ<sub>μ</sub> of the record, not compensated", g.unit + "/s", [&](const ChannelAnalysis& c) {
    return cm(c) && c.model.ok ? finite(c.model.random_walk.sigma_mu) : std::nullopt;
  });
  t.value(
      "samples fitted", "", [&](const ChannelAnalysis& c) { return cm(c) ? count(cm(c)->samples) : std::nullopt; }, 10);
  t.reason("random-walk model of the compensated series",
           [&](const ChannelAnalysis& c) { return cm(c) && !cm(c)->ok ? cm(c)->error : std::string(); });
  t.value("Gauss–Markov σ<sub>b</sub>", g.unit, [&](const ChannelAnalysis& c) {
    return cm(c) && cm(c)->gm_ok ? finite(cm(c)->gauss_markov.sigma_b) : std::nullopt;
  });
  t.value("Gauss–Markov T<sub>c</sub>", "s", [&](const ChannelAnalysis& c) {
    return cm(c) && cm(c)->gm_ok ? finite(cm(c)->gauss_markov.tau_c) : std::nullopt;
  });
  t.reason("Gauss–Markov model of the compensated series",
           [&](const ChannelAnalysis& c) { return cm(c) && !cm(c)->gm_ok ? cm(c)->gm_error : std::string(); });
}

std::string temperature_table(const AnalysisResult& r, const SensorGroup& g) {
  Table t(r, g);
  temperature_fit_rows(t, r, g);
  compensated_noise_rows(t);
  compensated_model_rows(t, g);
  return t.str();
}

std::string covariance_html(const AnalysisResult& r) {
  const auto& names = r.cov_names;
  const auto& m = r.covariance;
  if (names.empty() || m.rows() != names.size()) return "<p class=\"muted\">No covariance in the analysis.</p>\n";
  const std::size_t n = names.size();
  std::vector<std::vector<std::optional<double>>> v(n, std::vector<std::optional<double>>(n));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n && b < m.cols(); ++b) v[a][b] = finite(m(a, b));
  // The unit of entry (a, b) is unit_a * unit_b.
  std::vector<std::string> units(n);
  for (std::size_t a = 0; a < n; ++a)
    for (const auto& ch : r.channels)
      if (ch.name == names[a]) {
        units[a] = ch.unit.name;
        break;
      }
  std::string s;
  s +=
      "<p>Sample covariance of the channels over " +
      (r.cov_samples > 0 ? html_escape(format_num(count(r.cov_samples), 12)) + " samples" : std::string("the record")) +
      " (the sensor noise covariance of a Kalman filter); entry (a, b) in unit<sub>a</sub>·unit<sub>b</sub>. "
      "Beside it the correlation coefficients.</p>\n";
  auto head = [&](std::size_t a, bool corr) {
    return html_escape(names[a]) +
           (corr || units[a].empty() ? "" : " <span class=\"muted\">[" + html_escape(units[a]) + "]</span>");
  };
  auto matrix = [&](bool corr) {
    std::string t = "<div class=\"scroll\"><table>\n<thead><tr><th></th>";
    for (std::size_t b = 0; b < n; ++b) t += "<th>" + head(b, corr) + "</th>";
    t += "</tr></thead>\n<tbody>\n";
    for (std::size_t a = 0; a < n; ++a) {
      t += "<tr><th>" + head(a, corr) + "</th>";
      for (std::size_t b = 0; b < n; ++b) {
        std::optional<double> x = v[a][b];
        if (corr && x && v[a][a] && v[b][b] && *v[a][a] > 0 && *v[b][b] > 0)
          x = *x / std::sqrt(*v[a][a] * *v[b][b]);
        else if (corr)
          x.reset();
        t += "<td class=\"num\">" + html_escape(corr ? (x ? fmt("%+.3f", *x) : "—") : (x ? fmt("%.4e", *x) : "—")) +
             "</td>";
      }
      t += "</tr>\n";
    }
    return t + "</tbody></table></div>\n";
  };
  s += "<h3>Covariance</h3>\n" + matrix(false);
  s += "<h3>Correlation</h3>\n" + matrix(true);
  return s;
}

std::vector<ReportHtmlField> input_fields(const AnalysisResult& r) {
  std::vector<ReportHtmlField> in;
  auto html = [&](const std::string& label, const std::string& value_html) { in.push_back({label, value_html}); };
  html("file", "<code>" + html_escape(r.file) + "</code>");
  html("samples", html_escape(format_num(count(r.samples), 15)));
  html("sampling rate", html_escape(format_num(finite(r.rate_hz), 8)) + " Hz");
  html("duration", html_escape(duration_text(r.duration_s)));
  const bool split = r.gaps == io::GapPolicy::split;
  if (r.segments > 1)
    html("gaps", html_escape(format_num(count(r.segments), 10)) +
                     face_words(" contiguous segments: the record was split at its gaps (<code>{gaps} split</code>), "
                                "each segment analysed and the results combined"));
  else
    html("gaps", std::string("none: one contiguous segment") +
                     face_words(split ? " (<code>{gaps} split</code>)"
                                      : " (policy <code>{gaps} error</code>: a gap stops the analysis)"));
  std::string chans;
  for (const auto& ch : r.channels) {
    if (!chans.empty()) chans += ", ";
    chans += "<code>" + html_escape(ch.name) + "</code> [" + html_escape(ch.unit.name) + ", " +
             html_escape(std::string(to_string(ch.unit.kind))) + "]";
  }
  html("channels", chans);
  bool temp = false;
  for (const auto& ch : r.channels) temp = temp || ch.temperature.has_value();
  html("temperature", !temp ? face_words("not analysed (no <code>{temp_index}</code>)")
                            : "column <code>" + html_escape(r.temp_name) + "</code>, regressed per channel");
  const std::size_t model_samples = r.channels.empty() ? 0 : r.channels.front().model.samples;
  if (model_samples > 0)
    html(
        "model fitted on",
        html_escape(format_num(count(model_samples), 12)) + " samples" +
            (r.samples > 0 && model_samples < r.samples
                 ? face_words(" (the first ones: <code>{max_samples}</code>, as the paper reduced its record to 42000)")
                 : std::string(" (the whole record)")));
  html("confidence of the intervals", html_escape(detail::ci_text(r.ci)));
  return in;
}

// The spectral view of a channel (analyze --psd): N, B, K from the Allan
// curve's five-term fit and from the spectrum's power-law fit, their units
// and their difference in combined standard errors.
ReportTable views_table(const ChannelAnalysis& c) {
  ReportTable t;
  t.title = c.name + ": Allan curve vs spectrum";
  t.header = {"term", "Allan curve (five-term fit)", "spectrum (power-law fit)", "unit", "difference [σ]"};
  t.numeric = {false, true, true, false, true};
  const auto shown = [](const TermEstimate& e, const Quantity& q) {
    return e.valid ? format_pm(finite(q.value), finite(q.sigma)) : std::string("not seen (0)");
  };
  for (const pipeline::TermViews& v : pipeline::compare_views(c.noise.fit, *c.spectral)) {
    const char* name = v.term == Term::N   ? "N, white noise"
                       : v.term == Term::B ? "B, bias instability"
                       : v.term == Term::K ? "K, rate random walk"
                                           : nullptr;
    if (name == nullptr) continue;  // Q: in analysis.json, not on the page
    const Quantity a = display(v.allan, v.term, c.unit), s = display(v.spectrum, v.term, c.unit);
    t.rows.push_back({name, shown(v.allan, a), shown(v.spectrum, s), s.unit,
                      v.difference_sigmas ? fmt("%+.2f", *v.difference_sigmas) : std::string("—")});
  }
  const PowerLawFit& f = c.spectral->fit;
  t.note =
      "Each term from the Allan curve (the weighted fit of σ²(τ) = Σ C_k τ^k, k = −2…2) and from the "
      "one-sided spectrum (the fit of S(f) = Σ h_α f^α over " +
      format_num(f.f_lo, 3) + "–" + format_num(f.f_hi, 3) +
      " Hz, each h_α converted to its term: docs/formulas/spectral.md §6). "
      "Difference: (spectrum − Allan curve) / √(σ_spectrum² + σ_Allan²); both views are of the same samples, "
      "so a difference beyond about 3 says they disagree. “not seen”: the term is at its bound 0 in that fit.";
  return t;
}

// "[lo, hi]" (std::string{} += ...: GCC 12 warns falsely on "[" + std::string at -O3).
std::string interval_text(double lo, double hi) {
  std::string s{"["};
  s += format_num(finite(lo), 4);
  s += ", ";
  s += format_num(finite(hi), 4);
  s += "]";
  return s;
}

// A channel's composite model: each term's quantities as quoted, with the
// bootstrap's standard deviation and percentile interval when made; how the
// model was chosen in the note.
ReportTable composite_table(const AnalysisResult& r, const ChannelAnalysis& c) {
  const pipeline::ModelChannel& m = *c.model.composite;
  const pipeline::CompositeSettings& cs = *r.composite;
  const bool sd = cs.bootstrap > 0 && m.replicates >= 2;
  ReportTable t;
  t.title = c.name + ": " + m.model;
  t.header = {
      "term", "quantity", "value", "σ (asymptotic)", "σ (bootstrap)", detail::ci_text(r.ci) + " interval (bootstrap)",
      "unit"};
  t.numeric = {false, false, true, true, true, true, false};
  for (const pipeline::ModelTerm& term : m.terms)
    for (std::size_t i = 0; i < term.quantities.size(); ++i) {
      const pipeline::ModelQuantity& q = term.quantities[i];
      t.rows.push_back(
          {i == 0 ? std::string(to_string(term.kind)) : std::string(), q.name, format_num(finite(q.display.value), 5),
           format_num(finite(q.display_asymptotic_sd), 2), sd ? format_num(finite(q.display.sigma), 2) : "—",
           sd ? interval_text(q.display_interval.lo, q.display_interval.hi) : std::string("—"), q.display.unit});
    }
  std::string note = "GMWM fit to the Haar wavelet variance of " + format_num(count(c.model.samples), 12) +
                     " samples over " + std::to_string(m.wv.size()) + " dyadic scales (objective " +
                     format_num(finite(m.fit.objective), 4) + (m.fit.converged ? "" : ", the optimiser stopped early") +
                     "). ";
  if (m.candidates.size() > 1) {
    note += "Selected by the Wavelet Information Criterion (" + std::to_string(cs.selection_replicates) +
            " bootstrap replicates of each candidate's optimism) among " + std::to_string(m.candidates.size()) +
            " candidates, WIC " + format_num(finite(m.candidates[0].score.wic), 4) +
            " (the fewest parameters near the lowest); the others: ";
    for (std::size_t k = 1; k < m.candidates.size(); ++k)
      note += (k > 1 ? ", " : "") + m.candidates[k].model + " " + format_num(finite(m.candidates[k].score.wic), 4);
    note += ". ";
  }
  note +=
      "σ (asymptotic): the GMWM's sandwich standard deviation by the delta method (docs/formulas/noise-terms.md "
      "§8d; — where the wavelet variance does not determine it). ";
  note += sd ? "Bootstrap: " + std::to_string(m.replicates) + " parametric replicates fitted (seed " +
                   std::to_string(cs.seed) + ")."
             : face_words("No bootstrap: {composite_bootstrap} B adds its standard deviation and interval.");
  t.note = note;
  return t;
}

ReportBlock html_block(std::string html) {
  ReportBlock b;
  b.html = std::move(html);
  return b;
}

ReportBlock figure_block(ReportFigure f) {
  ReportBlock b;
  b.figures.push_back(std::move(f));
  return b;
}

// How to make the analysis and this page again.
std::string reproduce_html(const AnalysisReportContext& ctx, const std::string& dir) {
  std::string rep;
  if (!ctx.command.empty())
    rep += "<p>The analysis, as recorded in analysis.json:</p>\n<pre><code>" + html_escape(ctx.command) +
           "</code></pre>\n";
  else
    rep += "<p class=\"muted\">analysis.json does not record its command.</p>\n";
  rep += "<p>This page and its plots:</p>\n<pre><code>cubecal report " + html_escape(dir) +
         face_words(" {force}</code></pre>\n");
  rep +=
      "<p>Each plot is a gnuplot script beside its data in <code>plots/</code>: edit the script (line styles "
      "come first), run <code>gnuplot NAME.gp</code> in that directory for new SVG and PNG files, and "
      "<code>cubecal report DIR " +
      face_words("{force} {keep_scripts}") + "</code> to put the restyled plots into this page.</p>\n";
  return rep;
}

// The Allan curves and noise terms of each sensor group.
ReportSection allan_section(const AnalysisResult& r, const std::vector<SensorGroup>& groups) {
  ReportSection allan{"allan", "Allan deviation and noise terms", {}};
  allan.blocks.push_back(html_block(
      "<p>Noise terms in the units the literature quotes: for rate sensors N in °/√h, B in °/h, K in "
      "°/h/√h; for other sensors, as the paper does for its magnetometer, N in unit·√h, B in unit, K in "
      "unit/√h. Uncertainties are 1σ, from the confidence intervals of the curve. Hover a value for the τ range "
      "it was read from.</p>\n"));
  for (const auto& g : groups) {
    ReportBlock b = html_block("<h3>" + html_escape(g.title) + "</h3>\n");
    bool any_curve = false;
    for (auto c : g.channels) any_curve = any_curve || !r.channels[c].noise.adev.empty();
    if (any_curve) b.figures.push_back(detail::allan_figure(r, g));
    allan.blocks.push_back(std::move(b));
    allan.blocks.push_back(html_block(noise_table(r, g)));
  }
  return allan;
}

// The spectral view (analyze --psd), when made.
void add_spectral_section(CommandReport& page, const AnalysisResult& r) {
  bool any_spectral = false;
  for (const auto& ch : r.channels) any_spectral = any_spectral || ch.spectral.has_value();
  if (any_spectral) {
    ReportSection spec{"spectrum", "Allan curve and spectrum", {}};
    spec.blocks.push_back(
        html_block(face_words("<p>The same noise seen twice (<code>analyze {psd}</code>): ") +
                   "the IEEE 952 terms from the Allan curve above "
                   "and from the one-sided power spectral density of each channel (Welch's method with the defaults of "
                   "<code>cubecal psd</code>), whose power-law fit S(f) = Σ h<sub>α</sub> f<sup>α</sup> stands for N "
                   "(h<sub>0</sub> = 2N²), B (h<sub>−1</sub> = B²/π) and K (h<sub>−2</sub> = K²/(2π²)). Definitions: "
                   "<code>docs/formulas/spectral.md</code>.</p>\n"));
    std::vector<std::string> taken;
    for (const auto& ch : r.channels) {
      if (!ch.spectral) continue;
      const pipeline::SpectralAnalysis& sa = *ch.spectral;
      ReportBlock b;
      if (!sa.fit.terms.empty())
        b.table = views_table(ch);
      else
        b.html = "<h3>" + html_escape(ch.name) +
                 "</h3>\n<p>No power-law fit: " + html_escape(sa.fit_error.empty() ? "not made" : sa.fit_error) +
                 "</p>\n";
      if (sa.spectrum.size() > 0)
        b.figures.push_back(detail::spectrum_figure(detail::unique_name("psd_", ch.name, taken), ch.name, ch.unit,
                                                    sa.spectrum, sa.fit, sa.fit_error));
      spec.blocks.push_back(std::move(b));
    }
    page.sections.push_back(std::move(spec));
  }
}

// The sensor models and bias drift of each sensor group.
ReportSection model_section(const AnalysisResult& r, const std::vector<SensorGroup>& groups,
                            const AnalysisReportContext& ctx, const ReportOptions& options) {
  ReportSection model{"model", "Fitted sensor model and bias drift", {}};
  model.blocks.push_back(html_block(
      "<p>The paper's measurement model, per axis and sample k (period Δt): "
      "w<sub>k</sub> = ω<sub>k</sub> + β + b<sub>k</sub> + σ<sub>n</sub> η<sub>k</sub>, with the bias a random walk "
      "b<sub>k+1</sub> = b<sub>k</sub> + σ<sub>μ</sub> Δt μ<sub>k</sub> (η, μ unit Gaussian), quantized as "
      "int(w · m<sub>lsb</sub>) / m<sub>lsb</sub>. It is fitted so that its Allan curve is tangent to the measured "
      "white-noise arm and has the same minimum. The Gauss–Markov alternative replaces the random walk by a "
      "bounded first-order process b<sub>k+1</sub> = φ b<sub>k</sub> + σ<sub>b</sub> √(1 − φ²) μ<sub>k</sub>, "
      "φ = exp(−Δt / T<sub>c</sub>), fitted by weighted least squares.</p>\n" +
      (ctx.drift_note.empty() ? std::string() : "<p class=\"muted\">" + html_escape(ctx.drift_note) + "</p>\n")));
  for (const auto& g : groups) {
    ReportBlock b = html_block("<h3>" + html_escape(g.title) + "</h3>\n" + model_table(r, g));
    if (auto f = detail::drift_figure(r, g, options)) b.figures.push_back(std::move(*f));
    model.blocks.push_back(std::move(b));
  }
  return model;
}

// The composite noise model (analyze --composite), when fitted.
void add_composite_section(CommandReport& page, const AnalysisResult& r) {
  if (r.composite) {
    ReportSection comp{"composite", "Composite noise model", {}};
    comp.blocks.push_back(html_block(
        "<p>Beside the paper's model and the Gauss–Markov alternative, a composite noise model " +
        face_words("(<code>analyze {composite}</code>): ") +
        "a sum of white noise (WN, N), quantization noise (QN, Q), a random walk "
        "(RW, K), a drift (DR, R) and first-order Gauss–Markov terms (GM, σ<sub>b</sub> and T<sub>c</sub>), fitted "
        "by the Generalized Method of Wavelet Moments to the Haar wavelet variance of the samples the models are "
        "fitted on, as <code>cubecal model</code> does (<code>docs/formulas/noise-terms.md</code> §8a–8c). " +
        face_words("<code>cubecal simulate {model} analysis.json {bias} composite</code>") +
        " simulates it, each term in its "
        "discrete-time form at any rate.</p>\n"));
    std::vector<std::string> taken;
    for (const auto& ch : r.channels) {
      if (!ch.model.composite) continue;
      ReportBlock b;
      b.table = composite_table(r, ch);
      b.figures.push_back(detail::composite_figure(r, ch, detail::unique_name("composite_", ch.name, taken)));
      comp.blocks.push_back(std::move(b));
    }
    page.sections.push_back(std::move(comp));
  }
}

// The temperature fits of each sensor group with a temperature.
void add_temperature_section(CommandReport& page, const AnalysisResult& r, const std::vector<SensorGroup>& groups) {
  bool any_temp = false;
  for (const auto& ch : r.channels) any_temp = any_temp || ch.temperature.has_value();
  if (any_temp) {
    ReportSection temp{"temperature", "Temperature", {}};
    for (const auto& g : groups) {
      bool has = false;
      for (auto c : g.channels) has = has || r.channels[c].temperature.has_value();
      if (!has) continue;
      temp.blocks.push_back(html_block("<h3>" + html_escape(g.title) + "</h3>\n" + temperature_table(r, g)));
      for (auto& f : detail::temperature_figures(r, g)) temp.blocks.push_back(figure_block(std::move(f)));
    }
    page.sections.push_back(std::move(temp));
  }
}

}  // namespace

CommandReport analysis_report(const AnalysisResult& r, const AnalysisReportContext& ctx, const std::string& dir,
                              const ReportOptions& options) {
  const auto groups = detail::sensor_groups(r);
  const std::string& file = r.file;
  const std::string base = file.substr(file.find_last_of('/') == std::string::npos ? 0 : file.find_last_of('/') + 1);

  CommandReport page;
  page.title = "Sensor analysis: " + (base.empty() ? std::string("record") : base);
  page.lead_html =
      "Static characterization by <code>cubecal analyze</code>: Allan deviation with confidence "
      "intervals, IEEE 952 noise terms, the paper's sensor model and a Gauss–Markov alternative, bias drift, "
      "temperature dependence and covariance (Carrara, Pereira and Azevedo, “Attitude sensors calibration and "
      "modeling for CubeSats”).";
  page.input_html = input_fields(r);
  page.command = ctx.command;
  page.plot_prefixes = {"allan_", "drift_", "temperature_", "compensated_", "psd_", "composite_"};

  page.reproduce_html = reproduce_html(ctx, dir);
  page.sections.push_back(allan_section(r, groups));
  add_spectral_section(page, r);
  page.sections.push_back(model_section(r, groups, ctx, options));
  add_composite_section(page, r);
  add_temperature_section(page, r, groups);

  ReportSection cov{"covariance", "Covariance", {}};
  cov.blocks.push_back(html_block(covariance_html(r)));
  page.sections.push_back(std::move(cov));

  page.files_html =
      "<p>In <code>" + html_escape(dir) +
      "</code>: <code>analysis.json</code> (every number on this page, with units), <code>adev.csv</code> (Allan "
      "curves with the fitted models), <code>drift.csv</code> (bias drift), and in <code>plots/</code> for each "
      "figure its data (<code>.dat</code>), gnuplot script (<code>.gp</code>), <code>.svg</code> and "
      "<code>.png</code>. The model curves were computed from the fitted parameters (the values of analysis.json, "
      "as adev.csv lists them).</p>\n";
  page.footer_html = "Written by cubecal from the analysis of " +
                     html_escape(base.empty() ? std::string("a record") : base) + " (every number in " +
                     html_escape(dir) +
                     "/analysis.json). This page is self-contained: no network access, plots embedded as SVG.";
  return page;
}

}  // namespace cubecal::report
