/// @file
/// Chi-squared confidence interval of a deviation (SP 1065 eq. 45).
#pragma once

namespace cubecal {

/// A confidence interval [lo, hi] of an estimate ({0, 0}: none).
struct Interval {
  /// Lower bound.
  double lo = 0.0;
  /// Upper bound.
  double hi = 0.0;
  friend bool operator==(const Interval&, const Interval&) = default;
};

/// Two-sided interval at confidence ci (e.g. 0.683) for a deviation with
/// `edf` degrees of freedom. edf <= 0 gives {0, 0}.
Interval chi2_interval(double dev, double edf, double ci);

}  // namespace cubecal
