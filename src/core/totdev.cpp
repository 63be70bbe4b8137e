// Total variance (SP 1065 eq. 25): the overlapping Allan sum over the interior
// points i = 1..N-2, on the phase record extended at both ends by odd
// reflection, x*[-j] = 2x[0] - x[j] and x*[N-1+j] = 2x[N-1] - x[N-1-j].
#include "cubecal/core/kernels.hpp"

namespace cubecal {

TotvarExtension totvar_extend(std::span<const double> x) {
  TotvarExtension e;
  const std::size_t N = x.size();
  e.n = N;
  if (N < 3) return e;
  const std::size_t r = N - 2;  // reflected points on each side
  e.offset = r;
  e.xs.resize(N + 2 * r);
  for (std::size_t j = 1; j <= r; ++j) e.xs[r - j] = 2.0 * x[0] - x[j];
  for (std::size_t i = 0; i < N; ++i) e.xs[r + i] = x[i];
  for (std::size_t j = 1; j <= r; ++j) e.xs[r + N - 1 + j] = 2.0 * x[N - 1] - x[N - 1 - j];
  return e;
}

VarianceTerm totvar(const TotvarExtension& e, std::size_t m, double tau0) {
  const std::size_t N = e.n;
  if (m == 0 || N < 3 || m > N - 2) return {};
  const std::size_t n = N - 2;
  // Terms for i = 1..N-2: x*[i-m] - 2x[i] + x*[i+m].
  const double* base = e.xs.data() + e.offset + 1 - m;
  const double sum = second_difference_energy(base, n, m);
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (2.0 * tau * tau * static_cast<double>(n)), n};
}

}  // namespace cubecal
