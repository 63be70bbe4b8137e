// Internal to cubecal_report: small helpers shared by the command reports
// (colours, number text, plot-name slugs, common series).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <iterator>
#include <string>
#include <vector>

#include "cubecal/report/plot.hpp"

namespace cubecal::report::detail {

// Colours of runs (tab10) and of the axes x, y, z.
inline const char* run_color(std::size_t k) {
  static constexpr const char* kRuns[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                          "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
  return kRuns[k % std::size(kRuns)];
}
inline const char* axis_color(std::size_t a) {
  static constexpr const char* kAxes[] = {"#d62728", "#2ca02c", "#1f77b4"};
  return kAxes[a % 3];
}
inline constexpr const char* kInkColor = "#444444";

inline std::string printf_text(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// "1.5 h", "20 min", "45 s".
inline std::string duration_text(double s) {
  if (!(s > 0) || !std::isfinite(s)) return "—";
  if (s >= 3600.0) return printf_text("%.4g h", s / 3600.0);
  if (s >= 60.0) return printf_text("%.4g min", s / 60.0);
  return printf_text("%.4g s", s);
}

inline std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Letters and digits of `s` joined by '_' (a plot-name piece; "c" when empty).
inline std::string slug(const std::string& s) {
  std::string o;
  for (char c : s) {
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'))
      o += c;
    else if (!o.empty() && o.back() != '_')
      o += '_';
  }
  while (!o.empty() && o.back() == '_') o.pop_back();
  return o.empty() ? std::string("c") : o;
}

// prefix + slug(s), with _2, _3... appended when already in `taken` (updated).
inline std::string unique_name(const std::string& prefix, const std::string& s, std::vector<std::string>& taken) {
  const std::string base = prefix + slug(s);
  std::string n = base;
  for (int k = 2; std::find(taken.begin(), taken.end(), n) != taken.end(); ++k) n = base + "_" + std::to_string(k);
  taken.push_back(n);
  return n;
}

// A series only in the legend.
inline PlotSeries legend_only(std::string label, const char* color, Mark mark = Mark::line, Dash dash = Dash::solid,
                              double opacity = 1.0) {
  PlotSeries s;
  s.label = std::move(label);
  s.color = color;
  s.mark = mark;
  s.dash = dash;
  s.opacity = opacity;
  return s;
}

// A horizontal line at y across [x0, x1].
inline PlotSeries hline(double y, double x0, double x1, const char* color, Dash dash, std::string id) {
  PlotSeries s;
  s.id = std::move(id);
  s.x = {x0, x1};
  s.y = {y, y};
  s.color = color;
  s.dash = dash;
  s.width = 1.0;
  return s;
}

}  // namespace cubecal::report::detail
