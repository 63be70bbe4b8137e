#include "cubecal/noise/streaming_covariance.hpp"

#include <algorithm>
#include <stdexcept>

namespace cubecal {

StreamingCovariance::StreamingCovariance(std::size_t channels, std::size_t limit)
    : k_(channels), limit_(limit), mean_(channels, 0.0), comoment_(channels * channels, 0.0) {}

void StreamingCovariance::add(std::span<const std::span<const double>> pieces) {
  if (pieces.size() != k_) throw std::invalid_argument("StreamingCovariance::add: wrong number of channels");
  if (k_ == 0) return;
  std::size_t m = pieces[0].size();
  for (const auto& p : pieces)
    if (p.size() != m) throw std::invalid_argument("StreamingCovariance::add: channels of different lengths");
  if (limit_ > 0) m = std::min(m, limit_ > n_ ? limit_ - n_ : 0);
  if (m == 0) return;
  // The piece's own means and centred co-moments (two passes, as
  // covariance_matrix), then merged with what came before.
  piece_mean_.assign(k_, 0.0);
  piece_comoment_.assign(k_ * k_, 0.0);
  for (std::size_t a = 0; a < k_; ++a) {
    double s = 0.0;
    for (std::size_t i = 0; i < m; ++i) s += pieces[a][i];
    piece_mean_[a] = s / static_cast<double>(m);
  }
  for (std::size_t a = 0; a < k_; ++a)
    for (std::size_t b = a; b < k_; ++b) {
      const double ma = piece_mean_[a], mb = piece_mean_[b];
      double s = 0.0;
      for (std::size_t i = 0; i < m; ++i) s += (pieces[a][i] - ma) * (pieces[b][i] - mb);
      piece_comoment_[a * k_ + b] = piece_comoment_[b * k_ + a] = s;
    }
  const double n1 = static_cast<double>(n_), n2 = static_cast<double>(m), n = n1 + n2;
  for (std::size_t a = 0; a < k_; ++a)
    for (std::size_t b = 0; b < k_; ++b)
      comoment_[a * k_ + b] +=
          piece_comoment_[a * k_ + b] + (piece_mean_[a] - mean_[a]) * (piece_mean_[b] - mean_[b]) * n1 * n2 / n;
  for (std::size_t a = 0; a < k_; ++a) mean_[a] += (piece_mean_[a] - mean_[a]) * n2 / n;
  n_ += m;
}

double StreamingCovariance::variance(std::size_t channel) const {
  if (channel >= k_) throw std::invalid_argument("StreamingCovariance::variance: no such channel");
  if (n_ < 2) throw std::invalid_argument("covariance needs at least 2 samples");
  return comoment_[channel * k_ + channel] / static_cast<double>(n_ - 1);
}

Matrix StreamingCovariance::matrix() const {
  if (n_ < 2) throw std::invalid_argument("covariance needs at least 2 samples");
  Matrix cov(k_, k_);
  for (std::size_t a = 0; a < k_; ++a)
    for (std::size_t b = 0; b < k_; ++b) cov(a, b) = comoment_[a * k_ + b] / static_cast<double>(n_ - 1);
  return cov;
}

}  // namespace cubecal
