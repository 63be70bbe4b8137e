#include "magnitude.hpp"

#include <cstddef>
#include <cstring>

#include "simd.hpp"

namespace cubecal {

namespace {
using Lanes = double __attribute__((vector_size(4 * sizeof(double))));
}  // namespace

// Two groups of four lanes (the maximum is exact in any order). A NaN
// compares false and leaves a lane's maximum as it was; v * 0 is 0 for a
// finite sample and NaN for an infinite or NaN one, so `bad` flags them
// without a branch per sample.
CUBECAL_VECTOR_CLONES
Magnitude largest_magnitude(std::span<const double> v) noexcept {
  const std::size_t n = v.size();
  const double* p = v.data();
  Lanes big0{}, big1{}, bad0{}, bad1{};
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    Lanes a, b;
    std::memcpy(&a, p + i, sizeof a);
    std::memcpy(&b, p + i + 4, sizeof b);
    bad0 += a * 0.0;
    bad1 += b * 0.0;
    a = a < 0.0 ? -a : a;
    b = b < 0.0 ? -b : b;
    big0 = big0 < a ? a : big0;
    big1 = big1 < b ? b : big1;
  }
  double top = 0.0, flag = 0.0;
  for (int k = 0; k < 4; ++k) {
    top = top < big0[k] ? big0[k] : top;
    top = top < big1[k] ? big1[k] : top;
    flag += bad0[k] + bad1[k];
  }
  for (; i < n; ++i) {
    const double a = p[i] < 0.0 ? -p[i] : p[i];
    top = top < a ? a : top;
    flag += p[i] * 0.0;
  }
  return {top, flag == 0.0};
}

}  // namespace cubecal
