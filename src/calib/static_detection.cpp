// Static detection for the multi-position calibration: the windowed variance
// norm, the block variance norm and the runs below a threshold
// (docs/formulas/multiposition.md §2.1-2.2).
#include "cubecal/calib/static_detection.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "cubecal/error.hpp"

namespace cubecal::multipos {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

std::size_t normalised_window(std::size_t window) {
  if (window < kMinWindow)
    throw CalibrationError(CalibrationReason::bad_option, "the variance window must be at least " +
                                                              std::to_string(kMinWindow) + " samples (got " +
                                                              std::to_string(window) + ")");
  return window % 2 == 0 ? window + 1 : window;
}

std::vector<double> variance_norm(std::span<const Vec3> x, std::size_t window) {
  const std::size_t w = normalised_window(window);
  const std::size_t h = w / 2;
  const std::size_t n = x.size();
  std::vector<double> v(n, kInf);
  if (n < w) return v;
  for (std::size_t i = h; i + h < n; ++i) {
    double var2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      double mean = 0.0;
      for (std::size_t k = i - h; k <= i + h; ++k) mean += x[k][c];
      mean /= static_cast<double>(w);
      double ss = 0.0;
      for (std::size_t k = i - h; k <= i + h; ++k) {
        const double d = x[k][c] - mean;
        ss += d * d;
      }
      const double var = ss / static_cast<double>(w - 1);
      var2 += var * var;
    }
    v[i] = std::sqrt(var2);
  }
  return v;
}

double block_variance_norm(std::span<const Vec3> x) {
  if (x.size() < 2) throw CalibrationError(CalibrationReason::too_few_points, "a variance needs at least 2 samples");
  double var2 = 0.0;
  for (std::size_t c = 0; c < 3; ++c) {
    double mean = 0.0;
    for (const Vec3& s : x) mean += s[c];
    mean /= static_cast<double>(x.size());
    double ss = 0.0;
    for (const Vec3& s : x) ss += (s[c] - mean) * (s[c] - mean);
    const double var = ss / static_cast<double>(x.size() - 1);
    var2 += var * var;
  }
  return std::sqrt(var2);
}

std::vector<IndexRange> static_intervals(std::span<const double> v, double threshold) {
  std::vector<IndexRange> out;
  bool in = false;
  IndexRange cur;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const bool still = v[i] < threshold;
    if (!in && still) {
      cur.begin = i;
      in = true;
    } else if (in && !still) {
      cur.end = i;
      out.push_back(cur);
      in = false;
    }
  }
  if (in) {
    cur.end = v.size();
    out.push_back(cur);
  }
  return out;
}

}  // namespace cubecal::multipos
