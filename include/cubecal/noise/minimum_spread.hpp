/// @file
/// The spread of an Allan curve's minimum over records (docs/formulas/planning.md §3):
/// how far the lowest point of a measured curve (bias instability B =
/// sigma_min / 0.664) and its tau (T) move from record to record.
///
/// The curve's shape is the five-term fit's where there is one (a measured
/// curve's own points already carry one record's noise). The points near the
/// minimum are estimates with the variance of their EDF
/// (for mixed noise, mixture_edf.hpp) and correlated as overlapping estimates
/// at neighbouring taus are (the long-record spectral approximation the
/// five-term fit uses). Their joint log-normal law is sampled with a fixed
/// seed (4000 curves, each point's law chi-squared by Wilson & Hilferty's
/// cube): the law of the lowest deviation and of the tau it lies at, whose
/// central intervals give B's and T's precisions (standard deviations would
/// follow the rare curves whose minimum lands a decade away, or a point of
/// few degrees of freedom far below its mean). The same
/// computation gives `analyze` its stated uncertainties of B and T
/// (reported_terms.hpp) and `cubecal plan` its precisions (record_plan.hpp).
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"

namespace cubecal {

/// The spread of the minimum of a curve.
struct MinimumSpread {
  bool valid = false;   ///< false for a curve of fewer than two points or no EDF
  std::size_t lo = 0;   ///< first point of the curve that can hold the minimum
  std::size_t hi = 0;   ///< last such point
  double at_end = 0.0;  ///< fraction of sampled curves whose lowest point is the curve's first or last
  /// The lowest deviation of each sampled curve with a minimum inside, over the model's, ascending.
  std::vector<double> b_quantiles;
  /// Half the width of the central interval of probability `ci` of the lowest deviation, over its median: B's
  /// relative precision at ci. Throws nothing.
  double b_half_width(double ci) const noexcept;
  /// Probability that the minimum lies at point lo + i (of the curves with a minimum inside).
  std::vector<double> t_probability;
  /// ln(tau / T) of the edges of the points' cells (half-way to the neighbours in ln tau; size hi - lo + 2).
  std::vector<double> t_edges;
  /// Half the width of the central interval of probability `ci` of ln(tau of the minimum / T), the law taken
  /// uniform over each point's cell: T's relative precision at ci. Throws nothing.
  double t_half_width(double ci) const noexcept;
};

/// The spread of the minimum of `curve` (an OADEV curve with EDFs; with its
/// averaging factors and terms, the EDFs of the mixture of noises that `fit`
/// (fit_noise_terms of the same curve) finds at each point). Deterministic.
/// Throws nothing beyond std::bad_alloc.
MinimumSpread minimum_spread(const AllanCurve& curve, const NoiseFit& fit);

}  // namespace cubecal
