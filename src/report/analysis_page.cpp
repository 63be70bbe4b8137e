// The report page of an analysis: input summary, the command that reproduces
// it, figures, parameter tables (units, uncertainties), fitted models,
// temperature dependence and covariance. Every string from the data is escaped.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "analysis_data.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report::detail {

namespace {

const json& null_json() {
  static const json n;
  return n;
}

// j[k1][k2]... or null.
const json& at(const json& j, std::initializer_list<const char*> path) {
  const json* p = &j;
  for (const char* k : path) {
    if (!p->is_object()) return null_json();
    const auto it = p->find(k);
    if (it == p->end()) return null_json();
    p = &*it;
  }
  return *p;
}

std::string text(const json& j) {
  if (j.is_string()) return j.get<std::string>();
  if (j.is_null()) return {};
  return j.dump();
}

std::string esc(const json& j) { return html_escape(text(j)); }

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string duration_text(double s) {
  if (!(s > 0)) return "—";
  const double h = s / 3600.0;
  if (h >= 1.0) return fmt("%.6g s", s) + " (" + fmt("%.4g h", h) + ")";
  if (s >= 60.0) return fmt("%.6g s", s) + " (" + fmt("%.4g min", s / 60.0) + ")";
  return fmt("%.6g s", s);
}

// A parameter table with one column per channel of a group.
class Table {
 public:
  Table(const AnalysisData& d, const SensorGroup& g) : d_(d), g_(g) {
    s_ = "<div class=\"scroll\"><table>\n<thead><tr><th>parameter</th><th>unit</th>";
    for (auto c : g.channels) s_ += "<th>" + html_escape(d.channels[c].name) + "</th>";
    s_ += "</tr></thead>\n<tbody>\n";
  }
  void section(const std::string& title_html) {
    s_ += "<tr class=\"sub\"><th colspan=\"" + std::to_string(g_.channels.size() + 2) + "\">" + title_html +
          "</th></tr>\n";
  }
  // Cells from a function of the channel's JSON object: (html, title).
  template <class F>
  void row(const std::string& label_html, const std::string& unit, F cell) {
    std::string r = "<tr><th>" + label_html + "</th><td class=\"unit\">" + html_escape(unit) + "</td>";
    bool any = false;
    for (auto c : g_.channels) {
      const auto [html, title] = cell(*d_.channels[c].j);
      if (html != "—") any = true;
      r += "<td class=\"num\"" + (title.empty() ? std::string() : " title=\"" + html_escape(title) + "\"") + ">" + html +
           "</td>";
    }
    r += "</tr>\n";
    if (any || keep_empty_) s_ += r;
  }
  // A quantity {value, sigma, unit[, tau_range_s]} at `path` of each channel.
  void quantity(const std::string& label_html, std::initializer_list<const char*> path) {
    std::string unit;
    for (auto c : g_.channels) {
      const json& q = at(*d_.channels[c].j, path);
      if (unit.empty()) unit = text(at(q, {"unit"}));
    }
    keep_empty_ = true;
    row(label_html, unit, [&](const json& ch) {
      const json& q = at(ch, path);
      std::string html = html_escape(format_pm(number(q, "value"), number(q, "sigma")));
      const std::string u = text(at(q, {"unit"}));
      if (!u.empty() && u != unit && html != "—") html += " " + html_escape(u);
      std::string title;
      const json& r = at(q, {"tau_range_s"});
      if (r.is_array() && r.size() == 2 && number(r[0]) && number(r[1]))
        title = "read over tau " + format_num(number(r[0]), 4) + " to " + format_num(number(r[1]), 4) + " s";
      return std::make_pair(html, title);
    });
    keep_empty_ = false;
  }
  void value(const std::string& label_html, const std::string& unit, std::initializer_list<const char*> path,
             int digits = 5) {
    row(label_html, unit, [&](const json& ch) {
      const json& v = at(ch, path);
      if (v.is_string()) return std::make_pair(html_escape(v.get<std::string>()), std::string());
      return std::make_pair(html_escape(format_num(number(v), digits)), std::string());
    });
  }
  // Why something was not fitted: a note under the table, not a cell.
  void reason(const std::string& what_html, std::initializer_list<const char*> path) {
    for (auto c : g_.channels) {
      const json& v = at(*d_.channels[c].j, path);
      if (v.is_string() && !v.get<std::string>().empty())
        notes_ += "<li><b>" + html_escape(d_.channels[c].name) + "</b>: " + what_html + " not fitted: " +
                  html_escape(v.get<std::string>()) + "</li>\n";
    }
  }
  std::string str() const {
    return s_ + "</tbody></table></div>\n" + (notes_.empty() ? "" : "<ul class=\"reasons\">\n" + notes_ + "</ul>\n");
  }

 private:
  const AnalysisData& d_;
  const SensorGroup& g_;
  std::string s_, notes_;
  bool keep_empty_ = false;
};

std::string first_unit(const AnalysisData& d, const SensorGroup& g, std::initializer_list<const char*> path) {
  for (auto c : g.channels) {
    const std::string u = text(at(*d.channels[c].j, path));
    if (!u.empty()) return u;
  }
  return {};
}

std::string noise_table(const AnalysisData& d, const SensorGroup& g) {
  Table t(d, g);
  t.section("Record");
  t.value("fixed bias β (record mean)", g.unit, {"mean"}, 7);
  t.value("standard deviation", g.unit, {"stddev"});
  t.section("Slope read-offs (IEEE 952, as the paper): N at τ = 1 s, B = σ<sub>min</sub> / 0.664, K at τ = 3 s");
  t.quantity("N, white noise (angle random walk)", {"noise", "arw"});
  t.quantity("B, bias instability", {"noise", "bias_instability"});
  t.row("T, time constant (τ at the minimum)", "s", [](const json& ch) {
    const auto v = number(at(ch, {"noise", "time_constant_s"}));
    if (!v) return std::make_pair(std::string("—"), std::string("no minimum inside the record"));
    std::string h = format_num(v, 4);
    const json& r = at(ch, {"noise", "time_constant_range_s"});
    if (r.is_array() && r.size() == 2 && number(r[0]) && number(r[1]))
      h += " (" + format_num(number(r[0]), 3) + "–" + format_num(number(r[1]), 3) + ")";
    return std::make_pair(html_escape(h), std::string("range: taus whose intervals reach sigma_min"));
  });
  t.value("σ<sub>min</sub>, minimum of the curve", g.unit, {"noise", "sigma_min", "value"});
  t.quantity("K, rate random walk", {"noise", "rate_random_walk"});
  t.quantity("Q, quantization", {"noise", "quantization"});
  t.quantity("R, rate ramp", {"noise", "rate_ramp"});
  t.section("Weighted least-squares fit of σ²(τ) = Σ C<sub>k</sub> τ<sup>k</sup>, k = −2…2");
  t.quantity("N, white noise", {"noise", "fit", "arw"});
  t.quantity("B, bias instability", {"noise", "fit", "bias_instability"});
  t.quantity("K, rate random walk", {"noise", "fit", "rate_random_walk"});
  t.quantity("Q, quantization", {"noise", "fit", "quantization"});
  t.quantity("R, rate ramp", {"noise", "fit", "rate_ramp"});
  t.row("χ² / degrees of freedom", "", [](const json& ch) {
    const auto c2 = number(at(ch, {"noise", "fit", "chi2"})), dof = number(at(ch, {"noise", "fit", "dof"}));
    if (!c2 || !dof) return std::make_pair(std::string("—"), std::string());
    return std::make_pair(html_escape(format_num(c2, 4) + " / " + format_num(dof, 6)), std::string());
  });
  t.row("RMS relative residual", "%", [](const json& ch) {
    const auto v = number(at(ch, {"noise", "fit", "rms_rel_residual"}));
    return std::make_pair(v ? html_escape(format_num(100.0 * *v, 3)) : std::string("—"), std::string());
  });
  t.section("Noise densities (from the fit where it found the term, else the read-off)");
  t.quantity("white noise density", {"noise", "densities", "white"});
  t.quantity("white noise density, SI", {"noise", "densities", "white_si"});
  t.quantity("random-walk density", {"noise", "densities", "random_walk"});
  t.quantity("random-walk density, SI", {"noise", "densities", "random_walk_si"});
  return t.str();
}

std::string model_table(const AnalysisData& d, const SensorGroup& g) {
  Table t(d, g);
  t.section("Random-walk model (paper eq. 1–3): tangent to the white-noise arm, same minimum");
  t.value("σ<sub>n</sub>, white noise per sample", g.unit, {"model", "sigma_n"});
  t.value("σ<sub>μ</sub>, bias random-walk rate", first_unit(d, g, {"model", "sigma_mu_unit"}), {"model", "sigma_mu"});
  t.row("quantizer (m<sub>lsb</sub>)", "counts/" + g.unit, [](const json& ch) {
    const auto v = number(at(ch, {"model", "lsb"}));
    if (!v) return std::make_pair(std::string("—"), std::string());
    return std::make_pair(*v > 0 ? html_escape(format_num(v, 6)) : std::string("none"), std::string());
  });
  t.value("samples fitted", "", {"model", "samples"}, 10);
  t.value("Allan-curve residual, RMS of ln(model / data)", "", {"model", "residual_rms_log"}, 3);
  t.reason("random-walk model", {"model", "error"});
  t.section("Gauss–Markov alternative: white noise + first-order Gauss–Markov bias");
  t.value("σ<sub>b</sub>, stationary bias", g.unit, {"model", "gauss_markov", "sigma"});
  t.value("T<sub>c</sub>, correlation time", "s", {"model", "gauss_markov", "tau_s"});
  t.value("σ<sub>n</sub>, white noise per sample", g.unit, {"model", "gauss_markov", "sigma_n"});
  t.value("Allan-curve residual, RMS of ln(model / data)", "", {"model", "gauss_markov", "residual_rms_log"}, 3);
  t.reason("Gauss–Markov model", {"model", "gauss_markov_error"});
  t.row("the better fit", "", [](const json& ch) {
    const std::string v = text(at(ch, {"model", "better_fit"}));
    if (v.empty()) return std::make_pair(std::string("—"), std::string());
    return std::make_pair(html_escape(v == "gauss_markov" ? std::string("Gauss–Markov")
                                      : v == "random_walk" ? std::string("random walk")
                                                           : v),
                          std::string("smaller RMS of ln(model / data)"));
  });
  t.section("Bias drift");
  t.value("moving-average window", "s", {"drift", "window_s"});
  t.value("drift points (drift.csv)", "", {"drift", "points"}, 10);
  return t.str();
}

std::string temperature_table(const AnalysisData& d, const SensorGroup& g) {
  std::size_t order = 0;
  for (auto c : g.channels) {
    const json& co = at(*d.channels[c].j, {"temperature", "coeff"});
    if (co.is_array()) order = std::max(order, co.size());
  }
  Table t(d, g);
  t.section("Polynomial fit of the channel on temperature, y = Σ c<sub>p</sub> (T − T<sub>ref</sub>)<sup>p</sup>");
  t.value("temperature column", "", {"temperature", "sensor"});
  t.value("T<sub>ref</sub> (mean temperature)", "°C", {"temperature", "t_ref"}, 5);
  for (std::size_t p = 0; p < order; ++p) {
    std::string unit;
    for (auto c : g.channels) {
      const json& u = at(*d.channels[c].j, {"temperature", "coeff_units"});
      if (u.is_array() && u.size() > p && unit.empty()) unit = text(u[p]);
    }
    const std::string label = p == 0 ? std::string("c<sub>1</sub>, temperature coefficient")
                                     : "c<sub>" + std::to_string(p + 1) + "</sub>";
    t.row(label, unit, [p](const json& ch) {
      const json& co = at(ch, {"temperature", "coeff"});
      const json& cs = at(ch, {"temperature", "coeff_sigma"});
      if (!co.is_array() || co.size() <= p) return std::make_pair(std::string("—"), std::string());
      return std::make_pair(
          html_escape(format_pm(number(co[p]), cs.is_array() && cs.size() > p ? number(cs[p]) : std::nullopt)),
          std::string());
    });
  }
  t.value("c<sub>0</sub>, bias at T<sub>ref</sub>", g.unit, {"temperature", "offset"}, 7);
  t.value("R²", "", {"temperature", "r2"}, 4);
  t.value("residual RMS", g.unit, {"temperature", "residual_rms"}, 4);
  t.section("Noise terms after compensation (slope read-offs)");
  t.quantity("N, white noise", {"temperature", "compensated", "arw"});
  t.quantity("B, bias instability", {"temperature", "compensated", "bias_instability"});
  t.value("T, time constant", "s", {"temperature", "compensated", "time_constant_s"}, 4);
  t.quantity("K, rate random walk", {"temperature", "compensated", "rate_random_walk"});
  return t.str();
}

std::string covariance_section(const AnalysisData& d) {
  const json& cov = at(d.root, {"covariance"});
  const json& names = at(cov, {"channels"});
  const json& m = at(cov, {"matrix"});
  if (!names.is_array() || !m.is_array() || names.empty() || m.size() != names.size())
    return "<p class=\"muted\">No covariance in analysis.json.</p>\n";
  const std::size_t n = names.size();
  std::vector<std::vector<std::optional<double>>> v(n, std::vector<std::optional<double>>(n));
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n && m[a].is_array() && b < m[a].size(); ++b) v[a][b] = number(m[a][b]);
  // The unit of entry (a, b) is unit_a * unit_b.
  std::vector<std::string> units(n);
  for (std::size_t a = 0; a < n; ++a)
    for (const auto& ch : d.channels)
      if (ch.name == text(names[a])) {
        units[a] = ch.unit;
        break;
      }
  std::string s;
  const auto samples = number(cov, "samples");
  s += "<p>Sample covariance of the channels over " +
       (samples ? html_escape(format_num(samples, 12)) + " samples" : std::string("the record")) +
       " (the sensor noise covariance of a Kalman filter); entry (a, b) in unit<sub>a</sub>·unit<sub>b</sub>. "
       "Beside it the correlation coefficients.</p>\n";
  auto matrix = [&](bool corr) {
    std::string t = "<div class=\"scroll\"><table>\n<thead><tr><th></th>";
    for (std::size_t b = 0; b < n; ++b)
      t += "<th>" + esc(names[b]) + (corr || units[b].empty() ? "" : " <span class=\"muted\">[" + html_escape(units[b]) + "]</span>") + "</th>";
    t += "</tr></thead>\n<tbody>\n";
    for (std::size_t a = 0; a < n; ++a) {
      t += "<tr><th>" + esc(names[a]) + (corr || units[a].empty() ? "" : " <span class=\"muted\">[" + html_escape(units[a]) + "]</span>") + "</th>";
      for (std::size_t b = 0; b < n; ++b) {
        std::optional<double> x = v[a][b];
        if (corr && x && v[a][a] && v[b][b] && *v[a][a] > 0 && *v[b][b] > 0) x = *x / std::sqrt(*v[a][a] * *v[b][b]);
        else if (corr) x.reset();
        t += "<td class=\"num\">" + html_escape(corr ? (x ? fmt("%+.3f", *x) : "—") : (x ? fmt("%.4e", *x) : "—")) + "</td>";
      }
      t += "</tr>\n";
    }
    return t + "</tbody></table></div>\n";
  };
  s += "<h3>Covariance</h3>\n" + matrix(false);
  s += "<h3>Correlation</h3>\n" + matrix(true);
  return s;
}

std::string input_section(const AnalysisData& d) {
  const json& in = at(d.root, {"input"});
  const std::string cmd = text(at(d.root, {"command"}));
  std::string s = "<table class=\"kv\"><tbody>\n";
  auto kv = [&](const std::string& k, const std::string& v_html) {
    s += "<tr><th>" + k + "</th><td>" + v_html + "</td></tr>\n";
  };
  kv("file", "<code>" + esc(at(in, {"file"})) + "</code>");
  kv("samples", html_escape(format_num(number(in, "samples"), 15)));
  kv("sampling rate", html_escape(format_num(number(in, "rate_hz"), 8)) + " Hz");
  kv("duration", html_escape(duration_text(d.duration_s)));
  const auto seg = number(in, "segments").value_or(1.0);
  const bool split = cmd.find("--gaps split") != std::string::npos || cmd.find("--gaps=split") != std::string::npos;
  if (seg > 1)
    kv("gaps", html_escape(format_num(seg, 10)) +
                   " contiguous segments: the record was split at its gaps (<code>--gaps split</code>), each "
                   "segment analysed and the results combined");
  else
    kv("gaps", std::string("none: one contiguous segment") +
                   (split ? " (<code>--gaps split</code>)" : " (policy <code>--gaps error</code>: a gap stops the analysis)"));
  std::string chans;
  for (const auto& ch : d.channels) {
    if (!chans.empty()) chans += ", ";
    chans += "<code>" + html_escape(ch.name) + "</code> [" + html_escape(ch.unit) + ", " + html_escape(ch.kind) + "]";
  }
  kv("channels", chans);
  std::string temp;
  std::optional<double> model_samples;
  for (const auto& ch : d.channels) {
    if (temp.empty()) temp = text(at(*ch.j, {"temperature", "sensor"}));
    if (!model_samples) model_samples = number(at(*ch.j, {"model"}), "samples");
  }
  kv("temperature", temp.empty() ? std::string("not analysed (no <code>--temp-col</code>)")
                                 : "column <code>" + html_escape(temp) + "</code>, regressed per channel");
  if (model_samples && *model_samples > 0)
    kv("model fitted on",
       html_escape(format_num(model_samples, 12)) + " samples" +
           (d.samples > 0 && *model_samples < static_cast<double>(d.samples)
                ? " (the first ones: <code>--max-samples</code>, as the paper reduced its record to 42000)"
                : std::string(" (the whole record)")));
  kv("confidence of the intervals", html_escape(d.ci_text));
  s += "</tbody></table>\n";
  return s;
}

}  // namespace

std::string analysis_page(const AnalysisData& d, const std::vector<Figure>& figures,
                          const std::vector<RenderedPlot>& rendered, const std::string& note) {
  const std::string file = text(at(d.root, {"input", "file"}));
  const std::string base = file.substr(file.find_last_of('/') == std::string::npos ? 0 : file.find_last_of('/') + 1);
  int figno = 0;
  auto figures_of = [&](const std::string& section, const std::string& group) {
    std::string s;
    for (std::size_t i = 0; i < figures.size(); ++i) {
      if (figures[i].section != section || figures[i].group != group) continue;
      ++figno;
      const std::string cap = "<b>Figure " + std::to_string(figno) + ".</b> " + figures[i].caption_html;
      if (i < rendered.size())
        s += html_figure(rendered[i], cap);
      else
        s += "<figure><p class=\"muted\">[plot " + html_escape(figures[i].plot.name) + " not rendered]</p><figcaption>" +
             cap + "</figcaption></figure>\n";
    }
    return s;
  };
  bool any_temp = false, any_drift = false;
  for (const auto& f : figures) {
    any_temp = any_temp || f.section == "temperature";
    any_drift = any_drift || f.section == "drift";
  }
  for (const auto& ch : d.channels) any_temp = any_temp || at(*ch.j, {"temperature"}).is_object();

  std::string b;
  b += "<header>\n<h1>Sensor analysis: " + html_escape(base.empty() ? std::string("record") : base) + "</h1>\n";
  b += "<p class=\"lead\">Static characterization by <code>cubecal analyze</code>: Allan deviation with confidence "
       "intervals, IEEE 952 noise terms, the paper's sensor model and a Gauss–Markov alternative, bias drift, "
       "temperature dependence and covariance (Carrara, Pereira and Azevedo, “Attitude sensors calibration and "
       "modeling for CubeSats”).</p>\n</header>\n";
  if (!note.empty()) b += "<p class=\"note\">" + html_escape(note) + "</p>\n";
  b += "<nav class=\"toc\"><b>Contents</b><ol>";
  b += "<li><a href=\"#input\">Input</a></li><li><a href=\"#reproduce\">Reproduce</a></li>";
  b += "<li><a href=\"#allan\">Allan deviation and noise terms</a></li>";
  b += "<li><a href=\"#model\">Fitted sensor model and bias drift</a></li>";
  if (any_temp) b += "<li><a href=\"#temperature\">Temperature</a></li>";
  b += "<li><a href=\"#covariance\">Covariance</a></li><li><a href=\"#files\">Files</a></li>";
  b += "</ol></nav>\n";

  b += "<section id=\"input\">\n<h2>Input</h2>\n" + input_section(d) + "</section>\n";

  const std::string cmd = text(at(d.root, {"command"}));
  b += "<section id=\"reproduce\">\n<h2>Reproduce</h2>\n";
  if (!cmd.empty())
    b += "<p>The analysis, as recorded in analysis.json" +
         std::string(cmd.find("--out") == std::string::npos
                         ? " (add <code>--out DIR</code> to have it write these files)"
                         : "") +
         ":</p>\n<pre><code>" + html_escape(cmd) + "</code></pre>\n";
  else
    b += "<p class=\"muted\">analysis.json does not record its command.</p>\n";
  b += "<p>This page and its plots:</p>\n<pre><code>cubecal report " + html_escape(d.dir.string()) +
       " --force</code></pre>\n";
  b += "<p>Each plot is a gnuplot script beside its data in <code>plots/</code>: edit the script (line styles "
       "come first), run <code>gnuplot NAME.gp</code> in that directory for new SVG and PNG files, and "
       "<code>cubecal report DIR --force --keep-scripts</code> to put the restyled plots into this page.</p>\n";
  b += "</section>\n";

  b += "<section id=\"allan\">\n<h2>Allan deviation and noise terms</h2>\n";
  b += "<p>Noise terms in the units the literature quotes: for rate sensors N in °/√h, B in °/h, K in "
       "°/h/√h; for other sensors, as the paper does for its magnetometer, N in unit·√h, B in unit, K in "
       "unit/√h. Uncertainties are 1σ, from the confidence intervals of the curve. Hover a value for the τ range "
       "it was read from.</p>\n";
  for (const auto& g : d.groups) {
    b += "<h3>" + html_escape(g.title) + "</h3>\n";
    b += figures_of("allan", g.key);
    b += noise_table(d, g);
  }
  b += "</section>\n";

  b += "<section id=\"model\">\n<h2>Fitted sensor model and bias drift</h2>\n";
  b += "<p>The paper's measurement model, per axis and sample k (period Δt): "
       "w<sub>k</sub> = ω<sub>k</sub> + β + b<sub>k</sub> + σ<sub>n</sub> η<sub>k</sub>, with the bias a random walk "
       "b<sub>k+1</sub> = b<sub>k</sub> + σ<sub>μ</sub> Δt μ<sub>k</sub> (η, μ unit Gaussian), quantized as "
       "int(w · m<sub>lsb</sub>) / m<sub>lsb</sub>. It is fitted so that its Allan curve is tangent to the measured "
       "white-noise arm and has the same minimum. The Gauss–Markov alternative replaces the random walk by a "
       "bounded first-order process b<sub>k+1</sub> = φ b<sub>k</sub> + σ<sub>b</sub> √(1 − φ²) μ<sub>k</sub>, "
       "φ = exp(−Δt / T<sub>c</sub>), fitted by weighted least squares.</p>\n";
  if (!d.drift_csv) b += "<p class=\"muted\">No drift.csv in the directory: no drift plots.</p>\n";
  for (const auto& g : d.groups) {
    b += "<h3>" + html_escape(g.title) + "</h3>\n";
    b += model_table(d, g);
    if (any_drift) b += figures_of("drift", g.key);
  }
  b += "</section>\n";

  if (any_temp) {
    b += "<section id=\"temperature\">\n<h2>Temperature</h2>\n";
    for (const auto& g : d.groups) {
      bool has = false;
      for (auto c : g.channels) has = has || at(*d.channels[c].j, {"temperature"}).is_object();
      if (!has) continue;
      b += "<h3>" + html_escape(g.title) + "</h3>\n";
      b += temperature_table(d, g);
      b += figures_of("temperature", g.key);
    }
    b += "</section>\n";
  }

  b += "<section id=\"covariance\">\n<h2>Covariance</h2>\n" + covariance_section(d) + "</section>\n";

  b += "<section id=\"files\">\n<h2>Files</h2>\n<p>In <code>" + html_escape(d.dir.string()) + "</code>: ";
  b += "<code>analysis.json</code> (every number on this page, with units), <code>adev.csv</code> (Allan curves "
       "with the fitted models), <code>drift.csv</code> (bias drift)";
  b += ", and in <code>plots/</code> for each figure its data (<code>.dat</code>), gnuplot script "
       "(<code>.gp</code>), <code>.svg</code> and <code>.png</code>.";
  if (!d.adev_csv)
    b += " <span class=\"muted\">(adev.csv was missing or did not match analysis.json: the model curves were "
         "computed from the parameters in analysis.json.)</span>";
  b += "</p>\n</section>\n";
  b += "<footer>Written by cubecal report from " + html_escape((d.dir / "analysis.json").string()) +
       ". This page is self-contained: no network access, plots embedded as SVG.</footer>\n";
  return html_document("cubecal analysis: " + (base.empty() ? std::string("record") : base), b);
}

}  // namespace cubecal::report::detail
