// docs/formulas/spectral.md §2.3.
#include "cubecal/spectral/detrend.hpp"

#include <cstddef>

namespace cubecal {

void detrend(std::span<double> x, Detrend how) noexcept {
  const std::size_t n = x.size();
  if (how == Detrend::none || n == 0) return;
  double mean = 0.0;
  for (const double v : x) mean += v;
  mean /= static_cast<double>(n);
  if (how == Detrend::constant || n < 2) {
    for (double& v : x) v -= mean;
    return;
  }
  // Least-squares line over t = 0..n-1, centred on t_c = (n - 1) / 2:
  // slope = sum (t - t_c) x_t / sum (t - t_c)^2, the sum of squares being
  // n (n^2 - 1) / 12.
  const double tc = 0.5 * static_cast<double>(n - 1);
  double sxt = 0.0;
  for (std::size_t t = 0; t < n; ++t) sxt += (static_cast<double>(t) - tc) * x[t];
  const double nd = static_cast<double>(n);
  const double slope = sxt / (nd * (nd * nd - 1.0) / 12.0);
  for (std::size_t t = 0; t < n; ++t) x[t] -= mean + slope * (static_cast<double>(t) - tc);
}

}  // namespace cubecal
