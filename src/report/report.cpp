// write_report: an analysis directory read back, its plots rendered, the page
// written atomically.
#include "cubecal/report/report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "analysis_data.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/error.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

namespace fs = std::filesystem;

namespace detail {

std::optional<double> number(const json& j) {
  if (j.is_number()) {
    const double v = j.get<double>();
    if (std::isfinite(v)) return v;
  }
  return std::nullopt;
}

std::optional<double> number(const json& j, const char* key) {
  if (!j.is_object()) return std::nullopt;
  const auto it = j.find(key);
  if (it == j.end()) return std::nullopt;
  return number(*it);
}

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw UsageError("cannot read " + p.string());
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::vector<double> numbers(const json& obj, const char* key) {
  std::vector<double> v;
  if (!obj.is_object() || !obj.contains(key) || !obj[key].is_array()) return v;
  for (const auto& x : obj[key]) v.push_back(number(x).value_or(NAN));
  return v;
}

// "name,f1,...,fk" with the name possibly holding commas: the last k fields
// are numbers (empty: NaN).
bool split_row(const std::string& line, std::size_t k, std::string& name, std::vector<double>& f) {
  f.assign(k, NAN);
  std::size_t end = line.size();
  while (end > 0 && (line[end - 1] == '\r')) --end;
  for (std::size_t i = k; i-- > 0;) {
    const auto comma = line.rfind(',', end == 0 ? 0 : end - 1);
    if (comma == std::string::npos || end == 0) return false;
    const std::string field = line.substr(comma + 1, end - comma - 1);
    if (!field.empty()) {
      char* stop = nullptr;
      const double v = std::strtod(field.c_str(), &stop);
      if (stop == field.c_str()) return false;
      f[i] = v;
    }
    end = comma;
  }
  name = line.substr(0, end);
  return true;
}

// The model curves of adev.csv (channel,tau,n,dev,lo,hi,edf,alpha,fit_dev,
// model_dev,gauss_markov_dev), rows channel by channel as analysis.json
// lists them. False when the file does not match analysis.json.
bool read_adev_csv(const fs::path& p, std::vector<ChannelData>& chans) {
  std::ifstream in(p);
  std::string line;
  if (!std::getline(in, line) || line.rfind("channel,tau,", 0) != 0) return false;
  std::size_t c = 0, i = 0;
  std::string name;
  std::vector<double> f;
  for (auto& ch : chans) {
    ch.curve.fit.assign(ch.curve.tau.size(), NAN);
    ch.curve.model.assign(ch.curve.tau.size(), NAN);
    ch.curve.gm.assign(ch.curve.tau.size(), NAN);
  }
  while (c < chans.size() && i >= chans[c].curve.tau.size()) ++c;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (c >= chans.size() || !split_row(line, 10, name, f)) return false;
    auto& ch = chans[c];
    if (name != ch.name || std::abs(f[0] - ch.curve.tau[i]) > 1e-6 * ch.curve.tau[i]) return false;
    ch.curve.fit[i] = f[7];
    ch.curve.model[i] = f[8];
    ch.curve.gm[i] = f[9];
    if (++i == ch.curve.tau.size()) {
      i = 0;
      ++c;
      while (c < chans.size() && chans[c].curve.tau.empty()) ++c;
    }
  }
  return c == chans.size();
}

// Without adev.csv: the same curves from the parameters in analysis.json.
void compute_model_curves(ChannelData& ch, double rate_hz) {
  const json& j = *ch.j;
  const auto n = ch.curve.tau.size();
  ch.curve.fit.assign(n, NAN);
  ch.curve.model.assign(n, NAN);
  ch.curve.gm.assign(n, NAN);
  const double dt = 1.0 / rate_hz;
  std::array<double, 5> c{};
  bool have_c = false;
  if (j.contains("noise") && j["noise"].contains("fit") && j["noise"]["fit"].contains("coefficients")) {
    const auto v = numbers(j["noise"]["fit"], "coefficients");
    if (v.size() == 5) {
      std::copy(v.begin(), v.end(), c.begin());
      have_c = true;
    }
  }
  const json& m = j.contains("model") ? j["model"] : json();
  const auto sn = number(m, "sigma_n"), smu = number(m, "sigma_mu");
  const double lsb = number(m, "lsb").value_or(0.0);
  const json& gm = m.is_object() && m.contains("gauss_markov") ? m["gauss_markov"] : json();
  const auto gs = number(gm, "sigma"), gt = number(gm, "tau_s"), gn = number(gm, "sigma_n");
  for (std::size_t i = 0; i < n; ++i) {
    const double tau = ch.curve.tau[i];
    const auto k = static_cast<std::size_t>(std::max(1.0, std::round(tau / dt)));
    if (have_c) ch.curve.fit[i] = noise_model_adev(c, tau);
    if (sn && smu) ch.curve.model[i] = std::sqrt(avar(RandomWalkModel{*sn, *smu, dt, lsb}, k));
    if (gs && gt && gn) ch.curve.gm[i] = std::sqrt(avar(GaussMarkovModel{*gn, *gs, *gt, dt, lsb}, k));
  }
}

void read_drift_csv(const fs::path& p, std::vector<ChannelData>& chans) {
  std::ifstream in(p);
  std::string line;
  if (!std::getline(in, line) || line.rfind("channel,t,drift", 0) != 0) return;
  std::map<std::string, std::size_t> index;
  for (std::size_t c = chans.size(); c-- > 0;) index[chans[c].name] = c;
  std::string name, last;
  std::size_t cur = chans.size();
  std::vector<double> f;
  while (std::getline(in, line)) {
    if (line.empty() || !split_row(line, 2, name, f)) continue;
    if (name != last) {
      const auto it = index.find(name);
      cur = it == index.end() ? chans.size() : it->second;
      last = name;
    }
    if (cur == chans.size()) continue;
    chans[cur].drift_t.push_back(f[0]);
    chans[cur].drift.push_back(f[1]);
  }
}

// rate, field or other. analysis.json's "kind" calls every non-rate sensor
// "field" (their noise terms are quoted alike), so the unit decides first.
std::string kind_class(const std::string& kind, const std::string& unit) {
  if (const auto u = parse_unit(unit)) {
    if (u->kind == SensorKind::rate) return "rate";
    if (u->kind == SensorKind::field) return "field";
    return "other";
  }
  if (kind == "rate" || kind == "field") return kind;
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

// --ci of the command that made the analysis, as the intervals' confidence.
std::string ci_from_command(const std::string& cmd) {
  std::istringstream in(cmd);
  std::string tok, prev;
  std::string v;
  while (in >> tok) {
    if (prev == "--ci") v = tok;
    if (tok.rfind("--ci=", 0) == 0) v = tok.substr(5);
    prev = tok;
  }
  if (v.empty()) return "68.3 %";
  char* stop = nullptr;
  const double x = std::strtod(v.c_str(), &stop);
  if (stop == v.c_str() || !(x > 0 && x < 1)) return "68.3 %";
  char b[32];
  std::snprintf(b, sizeof b, "%.4g %%", 100.0 * x);
  return b;
}

}  // namespace

AnalysisData load_analysis(const fs::path& dir) {
  AnalysisData d;
  d.dir = dir;
  const fs::path p = dir / "analysis.json";
  if (!fs::exists(p))
    throw UsageError(p.string() + " not found: " + dir.string() +
                         " holds no analysis (run `cubecal analyze FILE ... --out " + dir.string() + "` first)");
  try {
    d.root = json::parse(read_file(p));
  } catch (const json::parse_error& e) {
    throw UsageError(p.string() + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  const json& r = d.root;
  if (!r.is_object() || !r.contains("channels") || !r["channels"].is_array() || !r.contains("input") ||
      !r["input"].is_object())
    throw UsageError(p.string() + ": not a cubecal analysis result (no 'input' and 'channels')");
  d.rate_hz = number(r["input"], "rate_hz").value_or(0.0);
  d.duration_s = number(r["input"], "duration_s").value_or(0.0);
  d.samples = static_cast<std::size_t>(number(r["input"], "samples").value_or(0.0));
  if (!(d.rate_hz > 0)) throw UsageError(p.string() + ": input.rate_hz is missing or not positive");
  if (r.contains("command") && r["command"].is_string()) d.ci_text = ci_from_command(r["command"].get<std::string>());

  for (const auto& cj : r["channels"]) {
    ChannelData ch;
    ch.j = &cj;
    auto str = [&](const char* k) {
      return cj.contains(k) && cj[k].is_string() ? cj[k].get<std::string>() : std::string();
    };
    ch.name = str("name");
    ch.unit = str("unit");
    ch.kind = str("kind");
    if (!cj.contains("adev") || !cj["adev"].is_object())
      throw UsageError(p.string() + ": channel '" + ch.name + "' has no 'adev' curve");
    const json& a = cj["adev"];
    ch.curve.tau = numbers(a, "tau");
    ch.curve.dev = numbers(a, "dev");
    ch.curve.lo = numbers(a, "lo");
    ch.curve.hi = numbers(a, "hi");
    if (ch.curve.dev.size() != ch.curve.tau.size())
      throw UsageError(p.string() + ": channel '" + ch.name + "': adev.tau and adev.dev differ in length");
    if (ch.curve.lo.size() != ch.curve.tau.size() || ch.curve.hi.size() != ch.curve.tau.size()) {
      ch.curve.lo = ch.curve.dev;
      ch.curve.hi = ch.curve.dev;
    }
    d.channels.push_back(std::move(ch));
  }

  const fs::path adev = dir / "adev.csv";
  d.adev_csv = fs::exists(adev) && read_adev_csv(adev, d.channels);
  if (!d.adev_csv)
    for (auto& ch : d.channels) compute_model_curves(ch, d.rate_hz);
  const fs::path drift = dir / "drift.csv";
  if (fs::exists(drift)) {
    read_drift_csv(drift, d.channels);
    d.drift_csv = true;
  }

  // Sensor groups: rate, field, other; split by unit when a kind mixes units.
  std::vector<std::pair<std::string, std::string>> keys;  // (class, unit) in first-seen order
  for (const auto& ch : d.channels) {
    const std::pair<std::string, std::string> k{kind_class(ch.kind, ch.unit), ch.unit};
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  }
  for (const auto& k : keys) {
    SensorGroup g;
    const auto same_class = std::count_if(keys.begin(), keys.end(), [&](const auto& o) { return o.first == k.first; });
    g.key = same_class > 1 ? k.first + "_" + unit_slug(k.second) : k.first;
    g.unit = k.second;
    g.title = class_title(k.first) + (k.second.empty() ? std::string() : " (" + k.second + ")");
    for (std::size_t c = 0; c < d.channels.size(); ++c)
      if (kind_class(d.channels[c].kind, d.channels[c].unit) == k.first && d.channels[c].unit == k.second)
        g.channels.push_back(c);
    d.groups.push_back(std::move(g));
  }
  return d;
}

}  // namespace detail

namespace {

// Files of an earlier report's plots that this one did not make (the
// analysis had other sensor groups): only the names write_report uses.
void remove_stale_plots(const fs::path& dir, const std::vector<std::string>& current) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const fs::path& p = e.path();
    const std::string stem = p.stem().string(), ext = p.extension().string();
    const bool ours = ext == ".dat" || ext == ".gp" || ext == ".svg" || ext == ".png" || ext == ".log";
    const bool named = stem.rfind("allan_", 0) == 0 || stem.rfind("drift_", 0) == 0 ||
                       stem.rfind("temperature_", 0) == 0 || stem.rfind("compensated_", 0) == 0;
    if (ours && named && std::find(current.begin(), current.end(), stem) == current.end()) stale.push_back(p);
  }
  for (const auto& p : stale) fs::remove(p, ec);
}

}  // namespace

std::vector<std::string> existing_report_outputs(const std::string& dir) {
  std::vector<std::string> v;
  const fs::path d(dir);
  if (fs::exists(d / "report.html")) v.push_back((d / "report.html").string());
  if (fs::exists(d / "plots")) v.push_back((d / "plots").string());
  return v;
}

ReportResult write_report(const std::string& dir, const ReportOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path d(dir);
  const fs::path html = d / "report.html";
  detail::AnalysisData data = detail::load_analysis(d);
  if (!options.force) {
    const auto existing = existing_report_outputs(dir);
    if (!existing.empty())
      throw UsageError(existing.front() + " already exists (add --force to replace the report" +
                           std::string(fs::exists(d / "plots") ? " and its plots" : "") + ")");
  }

  ReportResult res;
  const auto figures = detail::analysis_figures(data, options);
  std::vector<RenderedPlot> rendered;
  if (!find_gnuplot(options.gnuplot)) {
    if (options.require_plots) throw UsageError(kGnuplotMissing);
    res.note = std::string("Plots not rendered: ") + kGnuplotMissing + ".";
  } else {
    std::vector<Plot> plots;
    for (const auto& f : figures) plots.push_back(f.plot);
    RenderOptions ro;
    ro.gnuplot = options.gnuplot;
    ro.keep_scripts = options.keep_scripts;
    ro.jobs = options.jobs;
    rendered = render_plots(plots, d / "plots", ro);
    for (const auto& r : rendered) res.plots.push_back(r.name);
    if (!options.keep_scripts) remove_stale_plots(d / "plots", res.plots);
  }

  const std::string page = detail::analysis_page(data, figures, rendered, res.note);
  write_page(html, page);
  res.html_path = html.string();
  res.html_bytes = page.size();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace cubecal::report
