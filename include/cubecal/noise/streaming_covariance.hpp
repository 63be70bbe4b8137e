/// @file
/// The means, standard deviations and covariance matrix of several channels
/// taken a piece at a time (the streamed form of covariance.hpp and of the
/// fixed bias): pieces merged by the pairwise update of Chan, Golub and
/// LeVeque, each piece centred on its own mean first, so no sum of squares
/// about zero ever cancels (docs/formulas/drift-covariance-temperature.md §2).
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/math/matrix.hpp"

namespace cubecal {

/// The mean and covariance of several channels, taken a piece at a time (constant memory).
class StreamingCovariance {
 public:
  /// channels: how many; limit: the first `limit` samples are taken (0: all).
  explicit StreamingCovariance(std::size_t channels, std::size_t limit = 0);

  /// One piece: pieces[c] holds channel c (equal lengths; std::invalid_argument
  /// otherwise). Samples past the limit are ignored.
  void add(std::span<const std::span<const double>> pieces);

  /// Samples taken so far (per channel). Throws nothing.
  std::size_t count() const noexcept { return n_; }
  /// The mean of `channel` (data unit). Throws std::out_of_range for a channel that does not exist.
  double mean(std::size_t channel) const { return mean_.at(channel); }
  /// Unbiased (n - 1) normalization; std::invalid_argument below 2 samples.
  double variance(std::size_t channel) const;
  /// The covariance matrix of the channels (channels x channels, data unit
  /// squared), unbiased (n - 1); std::invalid_argument below 2 samples.
  Matrix matrix() const;

 private:
  std::size_t k_ = 0;
  std::size_t limit_ = 0;
  std::size_t n_ = 0;
  std::vector<double> mean_;
  std::vector<double> comoment_;                     ///< k x k, row-major: sum (x_a - mean_a)(x_b - mean_b)
  std::vector<double> piece_mean_, piece_comoment_;  ///< scratch
};

}  // namespace cubecal
