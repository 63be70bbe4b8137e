#include "cubecal/core/allan_curve.hpp"

#include <algorithm>
#include <cmath>

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
  c.lo.reserve(keep.size());
  c.hi.reserve(keep.size());
  c.edf.reserve(keep.size());
  for (const std::size_t i : keep) {
    const auto& p = points[i];
    c.tau.push_back(p.tau);
    c.dev.push_back(p.dev);
    c.lo.push_back(p.lo);
    c.hi.push_back(p.hi);
    c.edf.push_back(p.edf);
  }
  return c;
}

}  // namespace cubecal
