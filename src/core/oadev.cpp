// Overlapping Allan variance (SP 1065 eq. 11):
//   sigma^2(m tau0) = sum_{i=0}^{N-2m-1} (x[i+2m] - 2x[i+m] + x[i])^2 / (2 (N-2m) tau^2)
#include "cubecal/core/kernels.hpp"

namespace cubecal {

double second_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept {
  const double* a = x;
  const double* b = x + m;
  const double* c = x + 2 * m;
  double sum = 0.0;
  // Vectorized reduction; the reassociation this allows is harmless
  // (terms are all non-negative).
#pragma omp simd reduction(+ : sum)
  for (std::size_t i = 0; i < count; ++i) {
    const double d = c[i] - 2.0 * b[i] + a[i];
    sum += d * d;
  }
  return sum;
}

VarianceTerm oavar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 2 * m + 1) return {};
  const std::size_t n = N - 2 * m;
  const double tau = static_cast<double>(m) * tau0;
  const double sum = second_difference_energy(x.data(), n, m);
  return {sum / (2.0 * static_cast<double>(n) * tau * tau), n};
}

}  // namespace cubecal
