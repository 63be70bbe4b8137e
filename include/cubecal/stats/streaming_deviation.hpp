/// @file
/// The Allan and Hadamard deviations of a frequency record pushed through in
/// pieces, in memory that does not grow with the record: the streamed form of
/// StabilityRecord for records larger than memory.
///
/// A decimation pyramid: level L holds sums of 2^L consecutive samples (level
/// 0 the samples themselves, less a constant offset). Each averaging factor m
/// lives on one level with m = k 2^L: level 0 while its terms span at most
/// `window_bound` samples (2m for OADEV and ADEV, 3m for OHDEV and HDEV), else
/// the finest level whose k does so, m rounded to the nearest multiple of 2^L.
/// A level keeps the last span of its values and sums the squared differences
/// of adjacent k-windows (window sums as differences of a local prefix sum of
/// the buffer, never a running phase over the record) for every start on the
/// level: the overlapping statistics are exact at stride 1 (level 0, equal to
/// the in-memory kernels up to rounding) and partially overlapping, stride
/// 2^L, above; the non-overlapping ones are exact at any level. The cost per
/// sample is the number of level-0 factors plus a constant; the memory is
/// about 2 window_bound doubles per level that has received that many values.
///
/// Noise identification uses the same lag-1 autocorrelation of the
/// non-overlapping averages at m as identify_noise (their sums are
/// accumulated per factor), and the EDF Greenhall's algorithm with the actual
/// stride (edf_for_stride). Where fewer than 30 averages remain, Barnes' B1
/// ratio from the same sums, as identify_noise; only its R(n) step (white
/// or flicker PM, which needs MVAR of the record) is not taken: flicker PM
/// stays. MDEV, TDEV and TOTDEV are not streamed.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/lag_sums.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// True for the statistics StreamingDeviation computes: adev, oadev, hdev, ohdev.
bool streams(Stat stat) noexcept;

/// One averaging factor as streamed: m (a multiple of 2^level) and the
/// stride of its terms (1 on level 0 for the overlapping statistics, 2^level
/// above; m for the non-overlapping ones).
struct StreamedFactor {
  /// The averaging factor (input samples).
  std::size_t m = 0;
  /// The pyramid level it is computed on (factor 2^level decimation).
  std::size_t level = 0;
  /// Input samples between consecutive terms.
  std::size_t stride = 1;
};

/// The factors of `ms` (ascending) as a pyramid with this window bound
/// computes them: rounded to their level, merged when two round to the same m.
std::vector<StreamedFactor> streamed_factors(Stat stat, std::span<const std::size_t> ms, std::size_t window_bound);

/// Bytes one channel's accumulator holds at most for this window bound, on a
/// record of up to 2^40 samples.
std::size_t streaming_bytes(std::size_t window_bound) noexcept;

/// A deviation computed from pieces of a record pushed in order, in memory bounded by the window bound (a decimation
/// pyramid).
class StreamingDeviation {
 public:
  /// stat: streams(stat) (std::invalid_argument if not); ms: the grid's
  /// factors, ascending (those the record turns out too short for give no
  /// point); window_bound: a power of two, at least 16.
  StreamingDeviation(Stat stat, std::span<const std::size_t> ms, std::size_t window_bound);

  /// Frequency samples, in order. Throws std::invalid_argument naming the
  /// sample's index in the record for a NaN or infinite value.
  void push(std::span<const double> y);

  /// Samples pushed so far. Throws nothing.
  std::size_t samples() const noexcept { return samples_; }
  /// The factors computed, as streamed_factors gives them. Throws nothing.
  const std::vector<StreamedFactor>& factors() const noexcept { return factors_; }
  /// The statistic. Throws nothing.
  Stat stat() const noexcept { return stat_; }

  /// The points of every factor the record held (n > 0), as
  /// StabilityRecord::evaluate over the grid gives them (the run rule
  /// applied); strides[j] is the stride of points[j].
  struct Result {
    /// One point per factor the record held.
    std::vector<StabilityPoint> points;
    /// strides[j]: the stride of points[j] (input samples).
    std::vector<std::size_t> strides;
  };
  /// The result at sample period tau0 (s), after the last push; call once,
  /// at the end. Throws no cubecal error (nothing of its own).
  Result finish(double tau0, const StabilityOptions& opt);

 private:
  using Lag = LagSums;  ///< lag-1 sums of one difference order of the averages
  struct Factor {
    std::size_t k = 0;                    ///< window on its level
    double energy = 0.0, energy_c = 0.0;  ///< overlapping sum of squares (compensated)
    std::size_t terms = 0;
    double pass_energy = 0.0;         ///< this pass's share, summed over its tiles
    std::size_t first = 0, last = 0;  ///< this pass's starts of overlapping terms
    Lag lag[4];                       ///< orders 0..3 of the non-overlapping window sums
    std::size_t averages = 0;
    /// The averages' window sums z[0 .. count), orders 0..dmax; z and
    /// scratch (count + 1 values each) are overwritten.
    void push_averages(double* z, std::size_t count, int dmax, double* scratch) noexcept;
  };
  struct Level {
    /// capacity values once used: buf[0 .. kept) the prefix sums of the
    /// span kept from the last pass (from 0, about its mean `mean`), then
    /// the values not yet processed.
    std::vector<double> buf;
    double mean = 0.0;
    std::size_t fill = 0;  ///< values in buf
    std::size_t kept = 0;
    std::size_t base = 0;  ///< index on the level of buf[0]
    std::size_t span = 0;  ///< values a term spans (difference order x largest k)
    std::size_t capacity = 0;
    std::vector<std::size_t> factors;  ///< indices into factors_
    bool odd = false;                  ///< a value waits for its pair
    double pending = 0.0;
    std::size_t total = 0;    ///< values received
    std::vector<double> out;  ///< pair sums on their way to the next level: out[0 .. out_n)
    std::size_t out_n = 0;
  };

  void append(std::size_t level, const double* v, std::size_t count);
  static void grow(Level& lv, std::size_t need);
  void process(std::size_t level);

  Stat stat_;
  int order_;  ///< difference order: 2 Allan, 3 Hadamard
  bool overlapping_;
  std::size_t samples_ = 0;
  bool have_offset_ = false;
  double offset_ = 0.0;
  std::vector<StreamedFactor> factors_;
  std::vector<Factor> state_;
  std::vector<Level> levels_;
  std::vector<double> prefix_;     ///< scratch
  std::vector<double> zs_, diff_;  ///< scratch
};

}  // namespace cubecal
