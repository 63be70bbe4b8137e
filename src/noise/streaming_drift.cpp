#include "cubecal/noise/streaming_drift.hpp"

#include <algorithm>

namespace cubecal {

StreamingDrift::StreamingDrift(std::size_t window, std::size_t stride) : window_(window) {
  stride_ = stride > 0 ? stride : std::max<std::size_t>(window / 10, 1);
  whole_ = window / stride_;
  rem_ = window % stride_;
}

void StreamingDrift::add(std::span<const double> y) {
  if (window_ == 0 || y.empty()) return;
  if (!have_offset_) {
    offset_ = y[0];
    have_offset_ = true;
  }
  // The window starting at block j is blocks j .. j + whole_ - 1 and the
  // first rem_ samples of block j + whole_: it is complete when that head
  // is (or, without a head, when its last block is).
  const auto window_sum = [&](double head) {
    double s = head;
    for (const Block& b : done_) s += b.sum;
    return s;
  };
  std::size_t i = 0;
  while (i < y.size()) {
    // Up to the end of the head, then to the end of the block.
    const std::size_t stop = in_block_ < rem_ ? rem_ : stride_;
    const std::size_t take = std::min(stop - in_block_, y.size() - i);
    double s = 0.0;
    for (std::size_t j = i; j < i + take; ++j) s += y[j] - offset_;
    current_.sum += s;
    if (in_block_ < rem_) current_.head += s;
    in_block_ += take;
    i += take;
    if (rem_ > 0 && in_block_ == rem_ && done_.size() == whole_) sums_.push_back(window_sum(current_.head));
    if (in_block_ == stride_) {
      done_.push_back(current_);
      if (done_.size() > whole_) done_.pop_front();
      current_ = Block{};
      in_block_ = 0;
      if (rem_ == 0 && done_.size() == whole_) sums_.push_back(window_sum(0.0));
    }
  }
}

DriftSeries StreamingDrift::finish(double dt, double fixed_bias) const {
  DriftSeries d;
  d.window = window_;
  d.mean = fixed_bias;
  const double inv = 1.0 / static_cast<double>(window_);
  const double half = 0.5 * static_cast<double>(window_ > 0 ? window_ - 1 : 0) * dt;
  for (std::size_t j = 0; j < sums_.size(); ++j) {
    d.t.push_back(static_cast<double>(j * stride_) * dt + half);
    d.drift.push_back(sums_[j] * inv + (offset_ - fixed_bias));
  }
  return d;
}

}  // namespace cubecal
