// Normal (non-overlapping) Hadamard variance (SP 1065 eq. 18, phase form):
// third differences of phase at stride m, divided by 6 tau^2.
#include "cubecal/core/kernels.hpp"

namespace cubecal {

VarianceTerm hvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m + 1) return {};
  const std::size_t n = (N - 1) / m - 2;
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = k * m;
    const double d = x[i + 3 * m] - 3.0 * x[i + 2 * m] + 3.0 * x[i + m] - x[i];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (6.0 * static_cast<double>(n) * tau * tau), n};
}

}  // namespace cubecal
