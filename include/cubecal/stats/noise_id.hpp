/// @file
/// Power-law noise identification at one averaging factor, as Stable32 does
/// it: lag-1 autocorrelation (Riley & Greenhall 2004) of the non-overlapping
/// frequency averages when at least 30 remain, otherwise Barnes' B1 ratio,
/// with R(n) = MVAR/AVAR separating white from flicker PM (see noise_id.cpp
/// for each choice and the tables that fixed it).
#pragma once
#include <cstddef>
#include <optional>
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

/// The pieces of noise identification on their own, in the published forms
/// (the Python module's AllanTools-shaped calls; identify_noise above is
/// Stable32's variant of each).

/// Riley & Greenhall (EFTF 2004) eq. (2): the lag-1 autocorrelation of x
/// about its mean, sum (x[n]-mean)(x[n+1]-mean) over sum (x[n]-mean)^2
/// (0 for fewer than 2 points or a constant x).
double lag1_acf(std::span<const double> x);

/// x minus its least-squares polynomial of degree deg (0 .. 8) in the index
/// 0, 1, ..., n-1 (a QR fit on the index scaled to [-1, 1]). Empty for
/// deg < 0 or deg > 8 or fewer than deg + 1 points.
std::vector<double> detrend(std::span<const double> x, int deg);

/// Expected B1 ratio for N points and phase-PSD bias exponent mu (Howe,
/// Beard, Greenhall & Riley, PTTI 2000, Table 3).
double b1_expected(double N, int mu);

/// Barnes' B1 ratio at averaging factor m of a phase record x: the sample
/// variance of the non-overlapping frequency averages over their two-sample
/// (Allan) variance. 0 when fewer than 2 averages or their Allan variance is 0.
double b1_ratio(std::span<const double> x, std::size_t m);

/// Expected R(n) = MVAR/AVAR at factor m for frequency-noise exponent alpha
/// (IEEE 1139-2008): 1/m for white PM; for flicker PM, with the phase
/// bandwidth f_h = 1/(2 tau0), (3 ln(256/27) / 2) / (1.038 + 3 ln(pi m));
/// 1 for the other types.
double rn_expected(double m, int alpha);

/// R(n) of a phase record x at factor m: MVAR over the non-overlapping AVAR
/// (0 when either has no term or AVAR is 0).
double rn_ratio(std::span<const double> x, std::size_t m);

/// Lag-1 autocorrelation noise identification in Riley & Greenhall's
/// published form: the result of lag1_noise_id.
struct Lag1NoiseId {
  int alpha_int = 0;  ///< the noise exponent, rounded (half to even)
  double alpha = 0;   ///< the unrounded estimate, -2 (rho + d) (+2 for phase data)
  int d = 0;          ///< differences taken
  double rho = 0;     ///< r1 / (1 + r1) of the last series
};

/// Riley & Greenhall's lag-1 identification at factor af: phase data
/// decimated by af (every af-th point) with its quadratic removed, frequency
/// data averaged over af (non-overlapping) with its line removed; then
/// differenced until d >= dmin and (rho < 0.25 or d >= dmax). nullopt when
/// fewer than 30 points remain after the decimation or averaging (or
/// differencing would leave fewer than 2).
std::optional<Lag1NoiseId> lag1_noise_id(std::span<const double> x, std::size_t af, DataType type, int dmin, int dmax);

}  // namespace cubecal
