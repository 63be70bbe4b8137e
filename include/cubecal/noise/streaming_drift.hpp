/// @file
/// The bias drift of drift.hpp taken a piece at a time: the same moving
/// averages (a window of `window` samples every `stride` samples), built from
/// the sums of stride-long blocks, so that the memory is a few blocks'
/// sums whatever the window and the record. The fixed bias (the record mean)
/// is subtracted at the end, when it is known.
#pragma once
#include <cstddef>
#include <deque>
#include <span>
#include <vector>

#include "cubecal/noise/drift.hpp"

namespace cubecal {

/// The bias drift of a record (bias_drift) from pieces of it, in memory proportional to the number of averages.
class StreamingDrift {
 public:
  /// window: samples per average (0: no drift series); stride: as
  /// bias_drift (0: window / 10, at least 1).
  StreamingDrift(std::size_t window, std::size_t stride = 0);

  /// Appends the samples `y` (data unit). Throws nothing beyond std::bad_alloc.
  void add(std::span<const double> y);

  /// The series of bias_drift(y, dt, window, stride, fixed_bias) over every
  /// sample added; empty when fewer than `window` samples came.
  DriftSeries finish(double dt, double fixed_bias) const;

 private:
  struct Block {
    double sum = 0.0;   ///< all stride samples, less the offset
    double head = 0.0;  ///< the first `rem_` of them
  };
  std::size_t window_ = 0, stride_ = 1;
  std::size_t whole_ = 0, rem_ = 0;  ///< window = whole_ * stride_ + rem_
  bool have_offset_ = false;
  double offset_ = 0.0;  ///< the first sample: keeps the sums at the size of the drift
  Block current_;
  std::size_t in_block_ = 0;  ///< samples in current_
  std::deque<Block> done_;    ///< the last whole_ completed blocks
  std::vector<double> sums_;  ///< window sums, less window x offset, in order
};

}  // namespace cubecal
