/// @file
/// The noise terms cubecal reports as its result: one N, K only when it is
/// significant, B only when the curve has a minimum. The console table,
/// analysis.json, the estimator files (imu.yaml, --for) and the HTML report
/// all take them from here, so that each prints the same number.
///
///   N  the slope read-off: the -1/2 line read at tau = 1 s, with the tau
///      range it was read over (noise_terms.hpp), its sigma that of a mean of
///      correlated estimates; when the curve has no -1/2
///      region, the upper bound min over tau of sigma(tau) sqrt(tau)
///      (AVAR >= N^2 / tau).
///   K  the weighted five-term fit's K, else the read-off's (the first of the
///      two that is significant: value > 2 sigma); when neither is, the upper
///      bound min over tau of sigma(tau) sqrt(3 / tau) (AVAR >= K^2 tau / 3).
///      A coefficient whose uncertainty exceeds half its value is not a
///      measurement of K. A K from the fit states its spread over records
///      (planned_random_walk_sigma, record_plan.hpp), not the sandwich sigma
///      of the coefficients this fit freed.
///   B  the read-off sigma_min / 0.664 when the curve's minimum lies inside
///      the record, its sigma the spread of the minimum over records
///      (minimum_spread.hpp), as T's, the tau of the minimum; else "no minimum within the record" and the upper bound
///      sigma_min / 0.664 at the end of the record where the curve is lowest
///      (AVAR >= (0.664 B)^2 at every tau).
#pragma once
#include <string_view>

#include "cubecal/noise/noise_terms.hpp"

namespace cubecal {

/// Where a reported number came from.
enum class TermSource {
  fit,          ///< the weighted five-term fit (NoiseFit)
  read_off,     ///< the slope read-off (SlopeReadOffs)
  upper_bound,  ///< not identified (or not significant) in the record: the largest value the curve allows
};
std::string_view to_string(TermSource s) noexcept;  ///< "fit", "read-off", "UPPER BOUND"

/// A term is significant when it was estimated and its value exceeds twice
/// its 1-sigma uncertainty.
inline constexpr double kSignificanceSigmas = 2.0;
/// True when `t` is valid and its value exceeds kSignificanceSigmas times its sigma. Throws nothing.
bool significant(const TermEstimate& t) noexcept;

/// One reported noise term: its estimate and where it came from.
struct ReportedTerm {
  /// Fit, read-off, or upper bound.
  TermSource source = TermSource::upper_bound;
  TermEstimate estimate;  ///< the estimate (source fit or read_off); for an upper bound, the bound with
                          ///< sigma 0 and valid true, tau_lo..tau_hi where the curve sets it
  /// The value, in the term's unit. Throws nothing.
  double value() const noexcept { return estimate.value; }
  /// True for an upper bound. Throws nothing.
  bool bound() const noexcept { return source == TermSource::upper_bound; }
};

/// The terms every output reports for a channel: N, K when significant (else its bound), and B (or no minimum).
struct ReportedTerms {
  /// White noise N (u sqrt(s)).
  ReportedTerm N;
  /// Random walk K (u / sqrt(s)), or its upper bound.
  ReportedTerm K;
  /// The K estimate that was judged (fit when it found the term, else the
  /// read-off); valid false when neither found one. K.bound() with
  /// K_candidate.valid means "estimated, but not significant".
  TermEstimate K_candidate;
  /// Where K_candidate came from.
  TermSource K_candidate_source = TermSource::fit;
  /// Bias instability B (u), or its upper bound.
  ReportedTerm B;
  /// T, the tau of the curve's minimum (s), when it has one (else 0).
  double T = 0.0;
  /// T's relative uncertainty: the standard deviation of ln T over records
  /// (minimum_spread.hpp), at the curve's confidence like every sigma here; 0 without a minimum.
  double T_rel_sigma = 0.0;
  bool no_minimum = false;  ///< the curve has no minimum within the record (still falling at its last
                            ///< tau, or rising from its first): B is an upper bound
  bool constant = false;    ///< every deviation is zero: nothing to report
};

/// Empty or all-zero curves give constant = true and every term invalid.
ReportedTerms reported_terms(const SlopeReadOffs& read_off, const NoiseFit& fit, const AllanCurve& curve);

}  // namespace cubecal
