#include "cubecal/sim/power_law_noise.hpp"

#include <algorithm>
#include <boost/random/normal_distribution.hpp>
#include <random>

namespace cubecal {

std::vector<double> power_law_noise(double alpha, std::size_t n, std::uint64_t seed, DataType type) {
  // Innovations as the simulator draws them: std::mt19937_64 and Boost's
  // normal distribution, the same numbers on every platform.
  std::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> w(n);
  for (double& v : w) v = normal(engine);

  // Kasdin & Walter's filter: the impulse response of (1 - z^-1)^(-a/2).
  const double a = type == DataType::phase ? 2.0 - alpha : -alpha;
  std::vector<double> h(n);
  if (n > 0) h[0] = 1.0;
  for (std::size_t k = 1; k < n; ++k)
    h[k] = h[k - 1] * (static_cast<double>(k) - 1.0 + a / 2.0) / static_cast<double>(k);

  // Direct convolution. A filter with a = 0 (white) or a negative even a
  // (differences) is zero beyond its first terms: stop there.
  std::size_t len = n;
  while (len > 0 && h[len - 1] == 0.0) --len;
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t kmax = std::min(i + 1, len);
    double s = 0.0;
    for (std::size_t k = 0; k < kmax; ++k) s += h[k] * w[i - k];
    out[i] = s;
  }
  return out;
}

}  // namespace cubecal
