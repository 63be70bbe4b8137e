// Normal (non-overlapping) Allan variance (SP 1065 eq. 8, phase form):
// second differences of phase taken at stride m.
#include "cubecal/core/kernels.hpp"

namespace cubecal {

VarianceTerm avar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 2 * m + 1) return {};
  const std::size_t n = (N - 1) / m - 1;
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = k * m;
    const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (2.0 * static_cast<double>(n) * tau * tau), n};
}

}  // namespace cubecal
