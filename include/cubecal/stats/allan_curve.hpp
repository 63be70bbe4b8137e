/// @file
/// A measured Allan-deviation curve as the noise-term estimators take it:
/// parallel arrays, tau ascending, with the confidence interval and the
/// equivalent degrees of freedom of each point.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/stability.hpp"

namespace cubecal {

/// A measured Allan deviation curve: tau (s), deviation and its interval (data unit), EDF; what the noise-term fits
/// read.
struct AllanCurve {
  std::vector<double> tau;         ///< s, ascending
  std::vector<double> dev;         ///< sigma(tau), data unit
  std::vector<Interval> interval;  ///< confidence interval of dev
  std::vector<double> edf;         ///< equivalent degrees of freedom (> 0)
  /// Averaging factor of each point, and the terms each averages (StabilityPoint::n): what the
  /// EDF of a mixture of noise types needs (noise/mixture_edf.hpp). Empty when not known.
  std::vector<std::size_t> m;
  /// Terms averaged at each point (for OADEV, phase points - 2 m). Empty when not known.
  std::vector<std::size_t> terms;
  /// Points on the curve.
  std::size_t size() const noexcept { return tau.size(); }
};

/// The curve of a deviation's points (tau, dev, lo, hi, edf taken over). Throws nothing beyond std::bad_alloc.
AllanCurve to_allan_curve(const std::vector<StabilityPoint>& points);

/// Relative 1-sigma uncertainty of point i: half the interval over dev, or
/// 1/sqrt(2 edf) without an interval, 0 when neither is known.
double relative_uncertainty(const AllanCurve& c, std::size_t i) noexcept;

/// relative_uncertainty of every point, made non-decreasing in tau (a point
/// is never taken as more precise than a shorter-tau one: the read-offs'
/// uncertainties, noise_terms.hpp). Throws nothing beyond std::bad_alloc.
std::vector<double> running_relative_uncertainty(const AllanCurve& c);

/// Of points first..last, those measured at most `factor` times less
/// precisely than the best of them. A line tangent to the curve from below is
/// found among these only (factor 3): the minimum over long-tau points, a few degrees of
/// freedom each, is a low fluctuation, not the tangent (it biased a 70 min
/// record's white noise 4 % low).
std::vector<std::size_t> well_measured(const AllanCurve& c, std::size_t first, std::size_t last, double factor = 3.0);

}  // namespace cubecal
