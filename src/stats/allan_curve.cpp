#include "cubecal/stats/allan_curve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cubecal {

AllanCurve to_allan_curve(const std::vector<StabilityPoint>& points) {
  // Points the record could not support (n == 0) and zero deviations carry
  // no information and have no logarithm: the estimators work in log-log.
  std::vector<std::size_t> keep;
  keep.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (p.n > 0 && p.dev > 0.0 && std::isfinite(p.dev) && p.tau > 0.0) keep.push_back(i);
  }
  std::stable_sort(keep.begin(), keep.end(),
                   [&](std::size_t a, std::size_t b) { return points[a].tau < points[b].tau; });

  AllanCurve c;
  c.tau.reserve(keep.size());
  c.dev.reserve(keep.size());
  c.interval.reserve(keep.size());
  c.edf.reserve(keep.size());
  for (const std::size_t i : keep) {
    const auto& p = points[i];
    c.tau.push_back(p.tau);
    c.dev.push_back(p.dev);
    c.interval.push_back(p.interval);
    c.edf.push_back(p.edf);
    c.m.push_back(p.m);
    c.terms.push_back(p.n);
  }
  return c;
}

double relative_uncertainty(const AllanCurve& c, std::size_t i) noexcept {
  if (i < c.interval.size() && c.interval[i].hi > c.interval[i].lo && c.dev[i] > 0.0)
    return (c.interval[i].hi - c.interval[i].lo) / (2.0 * c.dev[i]);
  if (i < c.edf.size() && c.edf[i] > 0.0) return 1.0 / std::sqrt(2.0 * c.edf[i]);
  return 0.0;
}

std::vector<double> running_relative_uncertainty(const AllanCurve& c) {
  std::vector<double> rel(c.size(), 0.0);
  double running = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    running = std::max(running, relative_uncertainty(c, i));
    rel[i] = running;
  }
  return rel;
}

std::vector<std::size_t> well_measured(const AllanCurve& c, std::size_t first, std::size_t last, double factor) {
  std::vector<std::size_t> out;
  if (first > last || last >= c.size()) return out;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = first; i <= last; ++i) best = std::min(best, relative_uncertainty(c, i));
  for (std::size_t i = first; i <= last; ++i)
    if (relative_uncertainty(c, i) <= factor * best) out.push_back(i);
  return out;
}

}  // namespace cubecal
