// Modified Allan variance (SP 1065 eq. 14):
//   sum_{j=0}^{N-3m} ( sum_{i=j}^{j+m-1} (x[i+2m] - 2x[i+m] + x[i]) )^2 / (2 m^2 tau^2 (N-3m+1))
// The inner sum slides along j: add the entering second difference, drop the
// leaving one. Unlike a prefix sum of phase (whose magnitude grows like N^2
// and cancels catastrophically for random-walk noise) the running window
// stays at the size of the terms it holds.
#include "cubecal/core/kernels.hpp"

namespace cubecal {

VarianceTerm mvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m) return {};
  const std::size_t n = N - 3 * m + 1;
  auto d = [&](std::size_t i) { return x[i + 2 * m] - 2.0 * x[i + m] + x[i]; };
  double s = 0.0;
  for (std::size_t i = 0; i < m; ++i) s += d(i);
  double sum = s * s;
  for (std::size_t j = 1; j < n; ++j) {
    s += d(j + m - 1) - d(j - 1);
    sum += s * s;
  }
  const double md = static_cast<double>(m);
  const double tau = md * tau0;
  return {sum / (2.0 * md * md * tau * tau * static_cast<double>(n)), n};
}

}  // namespace cubecal
