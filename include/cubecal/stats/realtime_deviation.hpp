/// @file
/// The overlapping Allan, overlapping Hadamard and time deviations of a phase
/// record updated with each sample (Dobrogowski's recursions, 2007), readable
/// after any sample: what AllanTools' realtime classes compute.
///
/// Each averaging factor m keeps the sum of squares of its terms so far (the
/// second or third differences of the phase at lag m; for TDEV the sum of m
/// consecutive second differences, kept as a running window sum that is
/// summed anew every m samples, so that no rounding drifts over the record).
/// A sample costs one term per factor. The phase is kept from the sample
/// that the largest factor's next term needs on (3 m + 1 samples), less the
/// first sample (a constant every difference cancels); or, kept whole, so
/// that factors added later take every term of the record so far.
///
/// Unlike StreamingDeviation's pyramid, every factor is computed at stride 1
/// (fully overlapping) whatever its size, and the result is there after each
/// sample; the memory is that of the largest factor's span.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// Deviations updated sample by sample (see the file's description).
class RealtimeDeviation {
 public:
  /// stat: Stat::oadev, Stat::ohdev or Stat::tdev (std::invalid_argument
  /// otherwise); factors: the averaging factors, each at least 1 (in any
  /// order, repeats allowed: each gives its own point); keep_all: keep the
  /// whole record, so that add_factor may be called later.
  RealtimeDeviation(Stat stat, std::span<const std::size_t> factors, bool keep_all = false);

  /// One phase sample (any unit; the deviations come out in it, over tau0
  /// for OADEV and OHDEV). std::invalid_argument for a NaN or infinite value.
  void add_phase(double x);
  /// Phase samples in order, as add_phase each.
  void add_phase(std::span<const double> x);

  /// A new factor (at least 1), its terms over the record so far taken at
  /// once; only when the record is kept whole (std::logic_error otherwise).
  void add_factor(std::size_t m);

  /// Phase samples added. Throws nothing.
  std::size_t samples() const noexcept { return samples_; }
  /// The averaging factors, in the order given and added. Throws nothing.
  const std::vector<std::size_t>& factors() const noexcept { return m_; }
  /// The statistic. Throws nothing.
  Stat stat() const noexcept { return stat_; }
  /// Phase samples held: about the largest factor's span (up to twice it
  /// plus 4096), or all of them when kept whole. Throws nothing.
  std::size_t kept() const noexcept { return hist_.size(); }
  /// The last phase sample (0 before the first). Throws nothing.
  double last_phase() const noexcept { return last_; }

  /// Terms summed so far for factor j (0 while the record is shorter than
  /// 2 m + 1 samples for OADEV, 3 m + 1 for OHDEV, 3 m for TDEV). Throws
  /// nothing for j < factors().size().
  std::size_t terms(std::size_t j) const noexcept { return state_[j].terms; }
  /// The deviation of factor j at sample period tau0 (s): OADEV and OHDEV
  /// (fractional frequency, phase unit per second), TDEV (phase unit); 0
  /// while it has no term. Throws nothing for j < factors().size().
  double deviation(std::size_t j, double tau0) const noexcept;

 private:
  struct Factor {
    double energy = 0.0, energy_c = 0.0;  ///< sum of squared terms (compensated)
    std::size_t terms = 0;
    double window = 0.0;  ///< TDEV: the running sum of m second differences
  };

  double at(std::size_t i) const noexcept { return hist_[i - first_]; }  ///< sample i, less the first
  double second_difference(std::size_t i, std::size_t m) const noexcept;
  double term(std::size_t i, std::size_t m) const noexcept;  ///< OADEV or OHDEV term ending at sample i
  void advance(std::size_t j);                               ///< factor j's terms ending at the newest sample
  void add_term(Factor& f, double t) noexcept;
  void trim();

  Stat stat_;
  int order_;  ///< 2 Allan, 3 Hadamard and TDEV
  bool keep_all_;
  std::vector<std::size_t> m_;
  std::vector<Factor> state_;
  std::size_t span_ = 0;  ///< samples the largest factor's terms reach back: order m + 1
  std::vector<double> hist_;
  std::size_t first_ = 0;  ///< index of hist_[0] in the record
  std::size_t samples_ = 0;
  double origin_ = 0.0, last_ = 0.0;
};

}  // namespace cubecal
