// The period, gaps and jitter of a time-stamped record.
#include "cubecal/stats/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
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

// Without a copy of the intervals: a sample of them brackets the median,
// one pass counts the intervals below the bracket and keeps only those
// inside it (a few per cent of them, or none when the stamps are regular).
// Should the bracket miss the median (stamps far from stationary), all
// intervals are taken.
double median_interval(std::span<const double> time) {
  if (time.size() < 2) throw std::invalid_argument("median_interval: fewer than two time stamps");
  const std::size_t n = time.size() - 1;
  const auto interval = [&time](std::size_t i) { return time[i + 1] - time[i]; };
  constexpr std::size_t kSample = 4096;
  if (n > 8 * kSample) {
    std::vector<double> sample(kSample);
    for (std::size_t j = 0; j < kSample; ++j) sample[j] = interval(j * (n / kSample));
    std::sort(sample.begin(), sample.end());
    const double lo = sample[kSample * 15 / 32];
    const double hi = sample[kSample * 17 / 32];
    std::size_t below = 0, at_lo = 0, at_hi = 0;
    std::vector<double> inside;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = interval(i);
      if (d < lo) {
        ++below;
      } else if (d == lo) {
        ++at_lo;
      } else if (d < hi) {
        inside.push_back(d);
      } else if (d == hi) {
        ++at_hi;
      }
    }
    // The k-th smallest interval (0-based), if the bracket holds it.
    const auto kth = [&](std::size_t k) -> std::optional<double> {
      if (k < below) return std::nullopt;
      k -= below;
      if (k < at_lo) return lo;
      k -= at_lo;
      if (k < inside.size()) {
        std::nth_element(inside.begin(), inside.begin() + static_cast<std::ptrdiff_t>(k), inside.end());
        return inside[k];
      }
      k -= inside.size();
      if (k < at_hi) return hi;
      return std::nullopt;
    };
    const std::size_t mid = n / 2;
    const std::optional<double> upper = kth(mid);
    const std::optional<double> lower = n % 2 != 0 ? upper : kth(mid - 1);
    if (upper && lower) return n % 2 != 0 ? *upper : 0.5 * (*upper + *lower);
  }
  std::vector<double> dt(n);
  for (std::size_t i = 0; i < n; ++i) dt[i] = interval(i);
  const std::size_t mid = n / 2;
  std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(mid), dt.end());
  if (n % 2 != 0) return dt[mid];
  return 0.5 * (dt[mid] + *std::max_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(mid)));
}

}  // namespace cubecal
