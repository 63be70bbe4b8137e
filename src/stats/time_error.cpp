// TIE rms and MTIE (docs/formulas/stability.md, "Time-interval error").
//
// MTIE needs the maximum and the minimum of every window of w = m + 1
// phase points. The van Herk / Gil-Werman scheme gets both in O(N) per
// window length whatever w: cut the record into blocks of w points, take
// running maxima forward from each block's start (g) and backward from its
// end (h); a window [i, i+w-1] covers the end of one block and the start of
// the next, so its maximum is max(h[i], g[i+w-1]). Three comparisons per
// point and no branches on the data, against O(N w) for the direct scan.
#include "detail/time_error.hpp"

#include <algorithm>

#include "../detail/simd.hpp"

namespace cubecal {

std::vector<double> integrate_frequency(std::span<const double> y, double tau0, double scale) {
  std::vector<double> x(y.size() + 1, 0.0);
  const double step = tau0 / scale;
  double acc = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    acc += y[i] * step;
    x[i + 1] = acc;
  }
  return x;
}

namespace {

CUBECAL_VECTOR_CLONES
double lag_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept {
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8)
    for (std::size_t j = 0; j < 8; ++j) {
      const double d = x[i + j + m] - x[i + j];
      s[j] += d * d;
    }
  double tail = 0.0;
  for (; i < count; ++i) {
    const double d = x[i + m] - x[i];
    tail += d * d;
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

// Largest window range max - min over the windows of w points of x.
double largest_range(std::span<const double> x, std::size_t w) {
  const std::size_t N = x.size();
  std::vector<double> gmax(N), gmin(N), hmax(N), hmin(N);
  for (std::size_t b = 0; b < N; b += w) {
    const std::size_t e = std::min(N, b + w);
    gmax[b] = gmin[b] = x[b];
    for (std::size_t i = b + 1; i < e; ++i) {
      gmax[i] = std::max(gmax[i - 1], x[i]);
      gmin[i] = std::min(gmin[i - 1], x[i]);
    }
    hmax[e - 1] = hmin[e - 1] = x[e - 1];
    for (std::size_t i = e - 1; i > b; --i) {
      hmax[i - 1] = std::max(hmax[i], x[i - 1]);
      hmin[i - 1] = std::min(hmin[i], x[i - 1]);
    }
  }
  double best = 0.0;
  for (std::size_t i = 0; i + w <= N; ++i) {
    const double hi = std::max(hmax[i], gmax[i + w - 1]);
    const double lo = std::min(hmin[i], gmin[i + w - 1]);
    best = std::max(best, hi - lo);
  }
  return best;
}

}  // namespace

VarianceTerm tie_mean_square(std::span<const double> x, std::size_t m) {
  const std::size_t N = x.size();
  if (m == 0 || N < m + 1) return {};
  const std::size_t n = N - m;
  return {lag_difference_energy(x.data(), n, m) / static_cast<double>(n), n};
}

VarianceTerm mtie_square(std::span<const double> x, std::size_t m) {
  const std::size_t N = x.size();
  if (m == 0 || N < m + 1) return {};
  const double r = largest_range(x, m + 1);
  return {r * r, N - m};
}

}  // namespace cubecal
