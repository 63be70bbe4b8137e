// Overlapping Hadamard variance (SP 1065 eq. 20):
//   sum_{i=0}^{N-3m-1} (x[i+3m] - 3x[i+2m] + 3x[i+m] - x[i])^2 / (6 (N-3m) tau^2)
#include "cubecal/core/kernels.hpp"
#include "simd.hpp"

namespace cubecal {

namespace {

// Same layout as second_difference_energy (see oadev.cpp).
CUBECAL_VECTOR_CLONES
double third_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept {
  const double* a = x;
  const double* b = a + m;
  const double* c = a + 2 * m;
  const double* d = a + 3 * m;
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    for (std::size_t j = 0; j < 8; ++j) {
      const double t = d[i + j] - 3.0 * c[i + j] + 3.0 * b[i + j] - a[i + j];
      s[j] += t * t;
    }
  }
  double tail = 0.0;
  for (; i < count; ++i) {
    const double t = d[i] - 3.0 * c[i] + 3.0 * b[i] - a[i];
    tail += t * t;
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

}  // namespace

VarianceTerm ohvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m + 1) return {};
  const std::size_t n = N - 3 * m;
  const double sum = third_difference_energy(x.data(), n, m);
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (6.0 * static_cast<double>(n) * tau * tau), n};
}

}  // namespace cubecal
