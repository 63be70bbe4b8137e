/// @file
/// The least-squares temperature fit of temperature.hpp taken a piece at a
/// time, for a record read once in bounded memory: power sums of the
/// temperature (about its first value) and their products with the channel,
/// per block of samples for the batch-means covariance. The blocks double in
/// length as the record grows (at most 1280 of them), so at the end the 20
/// batches of the in-memory fit are made of whole blocks: the coefficients,
/// residual and R^2 equal the in-memory ones to rounding, the batch
/// boundaries are off by at most one block (1/640 of the record), which
/// moves the coefficient sigmas by little.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/noise/temperature.hpp"

namespace cubecal {

/// The least-squares temperature fit (fit_temperature) from pieces of a record, in constant memory.
class StreamingTemperatureFit {
 public:
  /// Throws CalibrationError bad_option for an order not 1 to 5.
  explicit StreamingTemperatureFit(std::size_t order);

  /// y and temp of equal lengths (CalibrationError bad_data otherwise).
  void add(std::span<const double> y, std::span<const double> temp);

  /// Samples added so far. Throws nothing.
  std::size_t count() const noexcept { return n_; }

  /// As fit_temperature over every sample added (its CalibrationErrors:
  /// too_few_points, degenerate).
  TemperatureFit finish() const;

 private:
  struct Sums {
    std::size_t n = 0;
    double m[11] = {};  ///< sum (T - t0)^j, j = 0 .. 2 order
    double yv[6] = {};  ///< sum (T - t0)^k (y - y0), k = 0 .. order
    double yy = 0.0;    ///< sum (y - y0)^2
    void merge(const Sums& o) noexcept;
  };
  void close_block();

  std::size_t order_ = 1;
  std::size_t n_ = 0;
  bool started_ = false;
  double t0_ = 0.0, y0_ = 0.0;
  double tmin_ = 0.0, tmax_ = 0.0;
  std::vector<double> distinct_;  ///< up to order + 1 distinct temperatures
  std::size_t block_len_ = 256;   ///< samples per block, doubled when 1280 are full
  std::vector<Sums> blocks_;
  Sums current_;
};

}  // namespace cubecal
