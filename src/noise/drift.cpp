#include "cubecal/noise/drift.hpp"

namespace cubecal {

DriftSeries bias_drift(std::span<const double> y, double dt, std::size_t window, std::size_t stride,
                       std::optional<double> fixed_bias) {
  DriftSeries d;
  d.window = window;
  if (y.empty()) return d;
  double mean = 0.0;
  if (fixed_bias) {
    mean = *fixed_bias;
  } else {
    for (double v : y) mean += v;
    mean /= static_cast<double>(y.size());
  }
  d.mean = mean;
  if (window == 0 || window > y.size()) return d;
  if (stride == 0) stride = window / 10 > 0 ? window / 10 : 1;
  // Running window sum of (y - mean): the terms stay small, so the
  // add-the-new, drop-the-old update keeps its precision over days of data.
  double s = 0.0;
  for (std::size_t i = 0; i < window; ++i) s += y[i] - mean;
  const double inv = 1.0 / static_cast<double>(window);
  const double half = 0.5 * static_cast<double>(window - 1) * dt;
  for (std::size_t start = 0;;) {
    d.t.push_back(static_cast<double>(start) * dt + half);
    d.drift.push_back(s * inv);
    const std::size_t next = start + stride;
    if (next + window > y.size()) break;
    for (std::size_t i = start; i < next; ++i) s += (y[i + window] - mean) - (y[i] - mean);
    start = next;
  }
  return d;
}

}  // namespace cubecal
