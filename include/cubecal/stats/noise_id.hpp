/// @file
/// Power-law noise identification at one averaging factor, as Stable32 does
/// it: lag-1 autocorrelation (Riley & Greenhall 2004) of the non-overlapping
/// frequency averages when at least 30 remain, otherwise Barnes' B1 ratio,
/// with R(n) = MVAR/AVAR separating white from flicker PM (see noise_id.cpp
/// for each choice and the tables that fixed it).
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// The power-law noise type identified at one averaging factor, as Stable32 identifies it.
struct NoiseId {
  int alpha = 0;         ///< exponent of the frequency PSD: +2 WPM ... -4 RRFM
  double alpha_est = 0;  ///< unrounded estimate (lag-1 ACF method only)
  double b1 = 0;         ///< B1 ratio (b1 and b1_rn methods)
  double rn = 0;         ///< R(n) = MVAR/AVAR (b1_rn method only)
  /// acf: lag-1 autocorrelation; b1: B1 ratio (fewer than 30 averages);
  /// b1_rn: B1 said white or flicker PM, R(n) chose which.
  /// The method that decided.
  enum class Method { acf, b1, b1_rn } method = Method::acf;  ///< the method that decided
};

/// x: phase record of the whole series (in any unit; frequency input is
/// integrated first). The identification works on the frequency averages
/// at m whichever type the user supplied.
NoiseId identify_noise(std::span<const double> x, std::size_t m, Stat stat);

/// identify_noise at every factor of ms, the same results to the bit, the
/// averages of every factor taken in one walk over x.
std::vector<NoiseId> identify_noise(std::span<const double> x, std::span<const std::size_t> ms, Stat stat);

/// The lag-1 step of identify_noise on its own: r1[d] is Stable32's lag-1
/// autocorrelation of the d-th differences of the averages (d from 0 to
/// difference_order(stat)), differencing stops at the first delta =
/// r1/(1+r1) below 0.25. For callers that accumulate the sums themselves
/// (the streamed deviations).
NoiseId noise_from_lag1(std::span<const double> r1, Stat stat);

/// The B1 step of identify_noise on its own (fewer than 30 averages): b1 is
/// the sample variance of the non-overlapping averages at m over their
/// two-sample variance, phase_points the length of the phase record. R(n)
/// is not applied (it needs the record): mu = -2 comes out as flicker PM,
/// which identify_noise then separates from white PM.
NoiseId noise_from_b1(double b1, std::size_t phase_points, std::size_t m, std::size_t averages, Stat stat);

}  // namespace cubecal
