/// @file
/// Which bias instability to trust when the slope read-off (sigma_min / 0.664)
/// and the weighted five-term fit disagree.
///
/// The read-off takes the lowest point of the curve as the flicker floor. The
/// white noise (N) and the random walk (K) still add to the variance there, so
/// it is biased high when they shape the minimum; the fit models N, B, K
/// together and separates them, as long as the five power laws describe the
/// curve. When they do not (a correlated, Gauss-Markov bias makes a bump the
/// fit cannot follow: a large rms residual), the fit's B is not reliable and
/// the read-off, measured on the curve itself, is the number to use (an upper
/// bound on B).
#pragma once
#include <string>
#include <string_view>

#include "cubecal/noise/noise_terms.hpp"

namespace cubecal {

/// The read-off and the fit disagree when their ratio is beyond this (20 %).
inline constexpr double kBiasDisagreement = 0.2;
/// A fit whose rms relative residual exceeds this (20 %) does not describe the curve.
inline constexpr double kFitMisses = 0.2;

/// Which bias-instability estimate to trust: both (they agree), the read-off, the fit, or neither.
enum class BiasTrust { agree, read_off, fit, neither };

/// The verdict on the two estimates of the bias instability B, and why.
struct BiasVerdict {
  BiasTrust trust = BiasTrust::neither;  ///< agree: within kBiasDisagreement of each other
  bool compared = false;                 ///< both valid
  double ratio = 0.0;                    ///< fit B / read-off B (both valid)
  bool beyond_sigma = false;             ///< |difference| > their combined 1-sigma uncertainty
  double other_terms_share = 0.0;        ///< share of the fitted variance at tau_min from terms other than B
  std::string reason;                    ///< one sentence; empty when they agree
};

/// Compares the read-off and the fitted B (data unit) and says which to trust. Throws nothing.
BiasVerdict judge_bias_instability(const SlopeReadOffs& read_off, const NoiseFit& fit);

std::string_view to_string(BiasTrust t) noexcept;  ///< "agree", "read_off", "fit", "neither"

}  // namespace cubecal
