// The period, gaps and jitter of a time-stamped record.
#include "cubecal/stats/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace cubecal {

SamplingCheck check_sampling(std::span<const double> t, double tolerance) {
  if (!(tolerance >= 0.0)) throw std::invalid_argument("check_sampling: tolerance must be >= 0");
  SamplingCheck c;
  if (t.size() < 2) return c;
  c.intervals = t.size() - 1;
  std::vector<double> dt(c.intervals);
  for (std::size_t i = 1; i < t.size(); ++i) {
    dt[i - 1] = t[i] - t[i - 1];
    if (!(dt[i - 1] > 0.0) || !std::isfinite(dt[i - 1]))
      throw std::invalid_argument("check_sampling: time stamps not strictly increasing at " + std::to_string(i));
  }
  std::vector<double> sorted = dt;
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  c.period_s = *mid;
  for (std::size_t i = 0; i < dt.size(); ++i) {
    if (dt[i] >= kGapPeriods * c.period_s) {
      if (c.gaps++ == 0) c.first_gap = i + 1;
      continue;
    }
    const double off = std::fabs(dt[i] - c.period_s) / c.period_s;
    c.max_jitter = std::max(c.max_jitter, off);
    if (off > tolerance && c.jittered++ == 0) c.first_jitter = i + 1;
  }
  return c;
}

}  // namespace cubecal
