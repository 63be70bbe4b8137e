#include "cubecal/stats/lag_sums.hpp"

#include "../detail/simd.hpp"

namespace cubecal {

double LagSums::r1() const noexcept {
  if (n < 2) return 0.0;
  const double nn = static_cast<double>(n);
  const double mu = s1 / nn;
  const double den = s2 - nn * mu * mu;
  const double num = p - mu * (2.0 * s1 - first - last) + (nn - 1.0) * mu * mu;
  return den > 0.0 ? (nn - 1.0) / nn * num / den : 0.0;
}

CUBECAL_VECTOR_CLONES
void LagSums::add(const double* w, std::size_t len) noexcept {
  if (len == 0) return;
  if (n > 0)
    p += last * w[0];
  else
    first = w[0];
  // 16 lanes = four AVX2 registers per sum: enough independent chains to
  // hide the add latency.
  constexpr std::size_t L = 16;
  double a1[L] = {}, a2[L] = {}, ap[L] = {};
  std::size_t i = 0;
  for (; i + L + 1 <= len; i += L)
    for (std::size_t j = 0; j < L; ++j) {
      const double v = w[i + j];
      a1[j] += v;
      a2[j] += v * v;
      ap[j] += v * w[i + j + 1];
    }
  double t1 = 0, t2 = 0, tp = 0;
  for (; i < len; ++i) {
    t1 += w[i];
    t2 += w[i] * w[i];
    if (i + 1 < len) tp += w[i] * w[i + 1];
  }
  for (std::size_t j = 0; j < L; ++j) {
    t1 += a1[j];
    t2 += a2[j];
    tp += ap[j];
  }
  s1 += t1;
  s2 += t2;
  p += tp;
  last = w[len - 1];
  n += len;
}

}  // namespace cubecal
