// The page of `cubecal davar`: per channel, the dynamic Allan deviation as a
// heat map (window centre on x, tau on a log y axis, colour log10 of the
// deviation), the deviation over time at a few taus, and per tau its spread
// over the windows.
//
// The plot description (plot.hpp) has no image mark, so the map is drawn in
// it as filled bands: a cell is the rectangle of its column (the window
// centre +- half a step) by its tau cell (from the geometric midpoint with
// the tau below to the one with the tau above), in the colour of its level.
// A band series fills one tau row at one level: over x it spans the row's
// tau cell where the row's columns are at that level and has zero height
// between them, so consecutive columns at one level are one rectangle. More
// windows than kMaxColumns are averaged (in log10) per column.
#include <algorithm>
#include <cmath>
#include <limits>

#include "command_util.hpp"
#include "cubecal/field.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

// Viridis in twelve steps, dark (small deviations) to light (large).
constexpr const char* kLevelColors[] = {"#440154", "#482173", "#433e85", "#38598c", "#2d708e", "#25858e",
                                        "#1e9b8a", "#2ab07f", "#52c569", "#86d549", "#c2df23", "#fde725"};
constexpr std::size_t kLevels = std::size(kLevelColors);
constexpr std::size_t kMaxColumns = 360;      // drawn columns of the map at most
constexpr std::size_t kMaxLinePoints = 1200;  // per series of the over-time plot

// Seconds as the x axis shows them.
struct TimeAxis {
  double per = 1.0;  // seconds per unit
  const char* unit = "s";
};

TimeAxis time_axis(double span_s) {
  if (span_s >= 7200.0) return {3600.0, "h"};
  if (span_s >= 120.0) return {60.0, "min"};
  return {1.0, "s"};
}

std::string ci_text(double ci) { return printf_text("%.4g %%", 100.0 * ci); }

// The tau cell of row j on a log axis: from the geometric midpoint with the
// row below to the one with the row above.
std::pair<double, double> tau_edges(const std::vector<double>& tau, std::size_t j) {
  const std::size_t J = tau.size();
  const double below = j > 0 ? tau[j - 1] : (J > 1 ? tau[0] * tau[0] / tau[1] : tau[0] / 2.0);
  const double above = j + 1 < J ? tau[j + 1] : (J > 1 ? tau[J - 1] * tau[J - 1] / tau[J - 2] : tau[0] * 2.0);
  return {std::sqrt(below * tau[j]), std::sqrt(tau[j] * above)};
}

// The map's columns: groups of consecutive windows, each averaged in
// log10 (value[c * taus + j], NaN: no positive deviation), and the range of
// the levels.
struct MapColumns {
  std::vector<double> x_left, x_right, value;
  double vmin = INFINITY, vmax = -INFINITY;
};

MapColumns map_columns(const DavarMatrix& mx, double step_s, const TimeAxis& ta) {
  const std::size_t K = mx.windows(), J = mx.taus();
  MapColumns m;
  std::vector<double>& x_left = m.x_left;
  std::vector<double>& x_right = m.x_right;
  std::vector<double>& value = m.value;
  double& vmin = m.vmin;
  double& vmax = m.vmax;
  // Columns: groups of consecutive windows, each averaged in log10.
  const std::size_t C = std::min(K, kMaxColumns);
  x_left.resize(C);
  x_right.resize(C);
  value.assign(C * J, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t c = 0; c < C; ++c) {
    const std::size_t k0 = c * K / C, k1 = (c + 1) * K / C;
    x_left[c] = (mx.centre[k0] - 0.5 * step_s) / ta.per;
    x_right[c] = (mx.centre[k1 - 1] + 0.5 * step_s) / ta.per;
    for (std::size_t j = 0; j < J; ++j) {
      double sum = 0.0;
      std::size_t used = 0;
      for (std::size_t k = k0; k < k1; ++k) {
        const double d = mx.dev_at(j, k);
        if (d > 0.0 && std::isfinite(d)) {
          sum += std::log10(d);
          ++used;
        }
      }
      if (used == 0) continue;
      const double v = sum / static_cast<double>(used);
      value[c * J + j] = v;
      vmin = std::min(vmin, v);
      vmax = std::max(vmax, v);
    }
  }
  if (!(vmin <= vmax)) {  // no positive deviation anywhere
    vmin = 0.0;
    vmax = 1.0;
  }
  if (vmax - vmin < 1e-9) {
    vmin -= 0.5;
    vmax += 0.5;
  }
  return m;
}

// One band per level of tau row j: over x, the tau cell of the row where
// the row's columns are at that level and nothing (lo = hi) between them.
void map_row_bands(Plot& p, const DavarMatrix& mx, const MapColumns& m, std::size_t j, double width) {
  const std::size_t J = mx.taus(), C = m.x_left.size();
  const std::vector<double>& x_left = m.x_left;
  const std::vector<double>& x_right = m.x_right;
  const std::vector<double>& value = m.value;
  const double vmin = m.vmin;
  auto level_of = [&](double v) {
    const double l = std::floor((v - vmin) / width);
    return static_cast<std::size_t>(std::clamp(l, 0.0, static_cast<double>(kLevels - 1)));
  };
  const auto [lo, hi] = tau_edges(mx.tau, j);
  std::vector<PlotSeries> row(kLevels);
  for (std::size_t c = 0; c < C;) {
    const double v = value[c * J + j];
    if (std::isnan(v)) {
      ++c;
      continue;
    }
    const std::size_t l = level_of(v);
    std::size_t e = c + 1;  // the run of columns at level l
    while (e < C && !std::isnan(value[e * J + j]) && level_of(value[e * J + j]) == l) ++e;
    PlotSeries& s = row[l];
    for (const auto& [x, top] : {std::pair{x_left[c], lo}, std::pair{x_left[c], hi}, std::pair{x_right[e - 1], hi},
                                 std::pair{x_right[e - 1], lo}}) {
      s.x.push_back(x);
      s.y.push_back(lo);
      s.lo.push_back(lo);
      s.hi.push_back(top);
    }
    c = e;
  }
  for (std::size_t l = 0; l < kLevels; ++l) {
    if (row[l].x.empty()) continue;
    row[l].mark = Mark::band;
    row[l].color = kLevelColors[l];
    row[l].id = "level " + std::to_string(l + 1) + " of " + std::to_string(kLevels) + ", tau " +
                format_num(mx.tau[j], 6) + " s";
    p.series.push_back(std::move(row[l]));
  }
}

ReportFigure heat_map(const std::string& channel, const DavarMatrix& mx, double step_s,
                      std::vector<std::string>& taken) {
  ReportFigure f;
  Plot& p = f.plot;
  const std::size_t K = mx.windows(), J = mx.taus();
  const TimeAxis ta = time_axis(mx.centre.back() - mx.centre.front() + step_s);
  p.name = unique_name("davar_map_", channel, taken);
  p.title = "Dynamic Allan deviation, " + channel;
  p.width = 900;
  p.height = 560;
  p.key = "outside right top title 'σ(τ)'";
  // Columns: groups of consecutive windows, each averaged in log10.
  const std::size_t C = std::min(K, kMaxColumns);
  const MapColumns m = map_columns(mx, step_s, ta);
  const std::vector<double>& x_left = m.x_left;
  const std::vector<double>& x_right = m.x_right;
  const double vmin = m.vmin, vmax = m.vmax;
  const double width = (vmax - vmin) / static_cast<double>(kLevels);
  // One band per (tau row, level).
  for (std::size_t j = 0; j < J; ++j) map_row_bands(p, mx, m, j, width);
  // The colour key, largest level on top.
  for (std::size_t l = kLevels; l-- > 0;) {
    const double a = std::pow(10.0, vmin + width * static_cast<double>(l));
    const double b = std::pow(10.0, vmin + width * static_cast<double>(l + 1));
    p.series.push_back(legend_only(format_num(a, 3) + " – " + format_num(b, 3), kLevelColors[l], Mark::band));
  }
  p.x = {"window centre [" + std::string(ta.unit) + "]", false, x_left.front(), x_right.back()};
  p.y = {"averaging time τ [s]", true, tau_edges(mx.tau, 0).first, tau_edges(mx.tau, J - 1).second};
  p.notes.push_back("dynamic overlapping Allan deviation of channel " + channel +
                    ": one block per tau row and colour "
                    "level (log10 of the deviation in " +
                    std::to_string(kLevels) +
                    " equal steps); rows x, lo, hi "
                    "fill the row's tau cell (lo..hi) over the runs of columns at that level, lo = hi between them");
  const bool grouped = C < K;
  f.caption_html =
      "Dynamic Allan deviation of <code>" + html_escape(channel) + "</code>: the overlapping Allan deviation of each " +
      "window (x: its centre), at each τ (y), coloured by log<sub>10</sub> σ in " + std::to_string(kLevels) +
      " equal steps from " + html_escape(format_num(std::pow(10.0, vmin), 3)) + " to " +
      html_escape(format_num(std::pow(10.0, vmax), 3)) + "." +
      (grouped ? " " + std::to_string(K) + " windows are drawn in " + std::to_string(C) +
                     " columns, each the mean of log<sub>10</sub> σ over its windows."
               : std::string()) +
      " Stationary noise gives horizontal bands; a change of the noise during the run shows as a vertical edge.";
  return f;
}

ReportFigure over_time(const std::string& channel, const DavarMatrix& mx, double step_s,
                       std::vector<std::string>& taken) {
  ReportFigure f;
  Plot& p = f.plot;
  const std::size_t K = mx.windows(), J = mx.taus();
  const TimeAxis ta = time_axis(mx.centre.back() - mx.centre.front() + step_s);
  p.name = unique_name("davar_time_", channel, taken);
  p.title = "Deviation over time at " + std::to_string(std::min<std::size_t>(J, 4)) + " taus, " + channel;
  p.width = 900;
  p.height = 480;
  p.key = "outside right top";
  p.x = {"window centre [" + std::string(ta.unit) + "]", false, std::nullopt, std::nullopt};
  p.y = {"σ(τ)", true, std::nullopt, std::nullopt};
  std::vector<std::size_t> rows;
  const std::size_t shown = std::min<std::size_t>(J, 4);
  for (std::size_t i = 0; i < shown; ++i) rows.push_back(shown == 1 ? 0 : i * (J - 1) / (shown - 1));
  const std::size_t stride = (K + kMaxLinePoints - 1) / kMaxLinePoints;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t j = rows[i];
    const std::string label = "τ = " + format_num(mx.tau[j], 4) + " s";
    if (mx.intervals) {
      PlotSeries band;
      band.mark = Mark::band;
      band.color = run_color(i);
      band.opacity = 0.2;
      band.id = label + " interval";
      for (std::size_t k = 0; k < K; k += stride) {
        band.x.push_back(mx.centre[k] / ta.per);
        band.y.push_back(mx.dev_at(j, k));
        band.lo.push_back(mx.lo[mx.cell(j, k)]);
        band.hi.push_back(mx.hi[mx.cell(j, k)]);
      }
      p.series.push_back(std::move(band));
    }
    PlotSeries s;
    s.color = run_color(i);
    s.label = label;
    s.width = 1.4;
    for (std::size_t k = 0; k < K; k += stride) {
      s.x.push_back(mx.centre[k] / ta.per);
      s.y.push_back(mx.dev_at(j, k));
    }
    p.series.push_back(std::move(s));
  }
  p.notes.push_back("the rows of the dynamic Allan deviation of channel " + channel +
                    " at a few taus over the windows" +
                    (stride > 1 ? ", every " + std::to_string(stride) + "th window" : std::string()));
  f.caption_html =
      "The deviation of <code>" + html_escape(channel) + "</code> over the run at " + std::to_string(rows.size()) +
      " of the " + std::to_string(J) + " taus" +
      (mx.intervals ? " with each window's " + html_escape(ci_text(mx.ci)) + " interval (band)" : std::string()) +
      (stride > 1 ? "; every " + std::to_string(stride) + "th window is drawn" : std::string()) + ".";
  return f;
}

// Per tau, the spread of the deviation over the windows. With missing
// samples (`--gaps skip`) a cell without a whole term has no value: it is
// left out of the smallest, median and largest and counted in a column of
// its own, and the terms are the range of the counts of the cells with a
// value (a window's count varies with its missing samples).
ReportTable spread_table(const std::string& channel, const DavarMatrix& mx) {
  ReportTable t;
  t.title = channel;
  const bool gapped = !mx.terms.empty();
  t.header = {"τ [s]", "terms n", "min σ", "at t [s]", "median σ", "max σ", "at t [s]", "max / min"};
  if (gapped) t.header.push_back("windows without a term");
  const std::size_t K = mx.windows();
  std::vector<std::size_t> with_value;  // windows of the row's cells that have a value
  std::vector<double> sorted;
  for (std::size_t j = 0; j < mx.taus(); ++j) {
    with_value.clear();
    std::size_t fewest = 0, most = 0;
    for (std::size_t k = 0; k < K; ++k) {
      const std::size_t terms = mx.terms_at(j, k);
      if (terms == 0) continue;
      fewest = with_value.empty() ? terms : std::min(fewest, terms);
      most = std::max(most, terms);
      with_value.push_back(k);
    }
    const std::string empty_cells = std::to_string(K - with_value.size());
    if (with_value.empty()) {
      std::vector<std::string> row(t.header.size(), "—");
      row[0] = format_num(mx.tau[j], 5);
      row[1] = "0";
      if (gapped) row.back() = empty_cells;
      t.rows.push_back(std::move(row));
      continue;
    }
    const auto by_dev = [&](std::size_t a, std::size_t b) { return mx.dev_at(j, a) < mx.dev_at(j, b); };
    const std::size_t lo = *std::min_element(with_value.begin(), with_value.end(), by_dev);
    const std::size_t hi = *std::max_element(with_value.begin(), with_value.end(), by_dev);
    sorted.clear();
    for (const std::size_t k : with_value) sorted.push_back(mx.dev_at(j, k));
    const std::size_t mid = sorted.size() / 2;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid), sorted.end());
    const double dlo = mx.dev_at(j, lo), dhi = mx.dev_at(j, hi);
    std::vector<std::string> row = {
        format_num(mx.tau[j], 5),
        fewest == most ? std::to_string(most) : std::to_string(fewest) + "–" + std::to_string(most),
        format_num(dlo, 4),
        format_num(mx.centre[lo], 6),
        format_num(sorted[mid], 4),
        format_num(dhi, 4),
        format_num(mx.centre[hi], 6),
        dlo > 0 ? format_num(dhi / dlo, 4) : std::string("—")};
    if (gapped) row.push_back(empty_cells);
    t.rows.push_back(std::move(row));
  }
  t.note = "Per τ, the deviation over the " + std::to_string(K) +
           " windows: the smallest and the largest with the centre of their window, the median, and their ratio.";
  if (gapped)
    t.note += face_words(" With missing samples ({gaps} skip) ") +
              "the terms of a window are its whole terms (their range over the "
              "windows); a window without a whole term at τ has no value there: it is left out of the smallest, "
              "median and largest and counted in the last column.";
  return t;
}

}  // namespace

std::vector<ReportFigure> davar_figures(const pipeline::DavarResult& r) {
  std::vector<ReportFigure> figs;
  std::vector<std::string> taken;
  const double step_s = static_cast<double>(r.step) / r.rate_hz;
  for (const auto& ch : r.channels) {
    if (ch.matrix.windows() == 0 || ch.matrix.taus() == 0) continue;
    figs.push_back(heat_map(ch.name, ch.matrix, step_s, taken));
    figs.push_back(over_time(ch.name, ch.matrix, step_s, taken));
  }
  return figs;
}

CommandReport davar_report(const pipeline::DavarResult& r, const std::string& command) {
  CommandReport rep;
  rep.title = "Dynamic Allan deviation: " + base_name(r.file);
  rep.lead_html =
      "The overlapping Allan deviation of a window sliding along the record, by <code>cubecal davar</code> "
      "(the dynamic Allan variance of Galleani &amp; Tavella, in the fast form of Wang et al. 2016): how "
      "the noise of the sensor changes during the run. Definition and method: "
      "<code>docs/formulas/davar.md</code>.";
  rep.command = command;
  rep.plot_prefixes = {"davar_map_", "davar_time_"};
  const double tau0 = 1.0 / r.rate_hz;
  const DavarMatrix* first = r.channels.empty() ? nullptr : &r.channels.front().matrix;
  std::string chans;
  for (const auto& c : r.channels) chans += (chans.empty() ? "" : ", ") + c.name;
  rep.input = {
      {"file", r.file, true},
      {"channels", chans, true},
      {"samples",
       std::to_string(r.samples) + " at " + format_num(r.rate_hz, 6) + " Hz (" +
           duration_text(static_cast<double>(r.samples) * tau0) + "), " + std::string(to_string(r.type)) + " data",
       false},
      {"window",
       std::to_string(r.window) + " samples (" + duration_text(static_cast<double>(r.window) * tau0) +
           "; asked: " + r.window_text + ")",
       false},
      {"step",
       std::to_string(r.step) + " samples (" + duration_text(static_cast<double>(r.step) * tau0) +
           "; asked: " + r.step_text + ")",
       false}};
  std::size_t missing = 0;
  for (const auto& c : r.channels) missing += c.matrix.missing;
  if (missing > 0)
    rep.input.push_back({"missing samples",
                         std::to_string(missing) + face_words(" ({gaps} skip: left out of each window's OADEV terms)"),
                         false});
  if (first) {
    rep.input.push_back({"windows", std::to_string(first->windows()), false});
    if (first->taus() > 0)
      rep.input.push_back({"taus",
                           std::to_string(first->taus()) + " from " + format_num(first->tau.front(), 4) + " s to " +
                               format_num(first->tau.back(), 4) + " s",
                           false});
    rep.input.push_back(
        {"intervals",
         first->intervals
             ? ci_text(first->ci) + ", EDF " +
                   (first->edf_method == EdfMethod::simple ? std::string("simple") : std::string("Greenhall")) +
                   ", noise type " +
                   (first->fixed_alpha ? "fixed at α = " + std::to_string(*first->fixed_alpha)
                                       : std::string("identified in each cell"))
             : std::string("none"),
         false});
  }
  const auto figs = davar_figures(r);
  std::size_t f = 0;
  for (const auto& ch : r.channels) {
    std::string id = "channel-" + slug(ch.name);
    std::replace(id.begin(), id.end(), '_', '-');
    ReportSection s{id, ch.name, {}};
    if (ch.matrix.windows() > 0 && ch.matrix.taus() > 0)
      for (int k = 0; k < 2 && f < figs.size(); ++k) s.blocks.push_back({{}, std::nullopt, {figs[f++]}});
    ReportBlock table;
    table.table = spread_table(ch.name, ch.matrix);
    s.blocks.push_back(std::move(table));
    rep.sections.push_back(std::move(s));
  }
  return rep;
}

}  // namespace cubecal::report
