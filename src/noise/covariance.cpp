#include "cubecal/noise/covariance.hpp"

#include <algorithm>
#include <stdexcept>

namespace cubecal {

std::vector<std::vector<double>> covariance_matrix(const std::vector<std::span<const double>>& channels,
                                                   std::size_t count) {
  const std::size_t k = channels.size();
  std::vector<std::vector<double>> cov(k, std::vector<double>(k, 0.0));
  if (k == 0) return cov;
  std::size_t n = channels[0].size();
  for (const auto& c : channels) n = std::min(n, c.size());
  if (count > 0) n = std::min(n, count);
  if (n < 2) throw std::invalid_argument("covariance needs at least 2 samples");
  // Two passes: means first, then centred products (no cancellation).
  std::vector<double> mean(k, 0.0);
  for (std::size_t a = 0; a < k; ++a) {
    for (std::size_t i = 0; i < n; ++i) mean[a] += channels[a][i];
    mean[a] /= static_cast<double>(n);
  }
  for (std::size_t a = 0; a < k; ++a)
    for (std::size_t b = a; b < k; ++b) {
      double s = 0.0;
      for (std::size_t i = 0; i < n; ++i) s += (channels[a][i] - mean[a]) * (channels[b][i] - mean[b]);
      cov[a][b] = cov[b][a] = s / static_cast<double>(n - 1);
    }
  return cov;
}

}  // namespace cubecal
