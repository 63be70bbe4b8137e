// Overlapping Hadamard variance (SP 1065 eq. 20):
//   sum_{i=0}^{N-3m-1} (x[i+3m] - 3x[i+2m] + 3x[i+m] - x[i])^2 / (6 (N-3m) tau^2)
#include "cubecal/core/kernels.hpp"

namespace cubecal {

VarianceTerm ohvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m + 1) return {};
  const std::size_t n = N - 3 * m;
  const double* a = x.data();
  const double* b = a + m;
  const double* c = a + 2 * m;
  const double* d = a + 3 * m;
  double sum = 0.0;
#pragma omp simd reduction(+ : sum)
  for (std::size_t i = 0; i < n; ++i) {
    const double t = d[i] - 3.0 * c[i] + 3.0 * b[i] - a[i];
    sum += t * t;
  }
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (6.0 * static_cast<double>(n) * tau * tau), n};
}

}  // namespace cubecal
