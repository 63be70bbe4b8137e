/// @file
/// The empirical Haar wavelet variance of frequency samples at the dyadic
/// scales tau = 2, 4, 8, ... samples (Percival & Walden, Wavelet Methods for
/// Time Series Analysis, 2000, §8.3: the unbiased MODWT estimator), the
/// moments the GMWM fit of composite noise models matches
/// (noise/gmwm.hpp; docs/formulas/noise-terms.md §8a).
///
/// The MODWT Haar coefficient at scale tau is half the difference of two
/// adjacent means of m = tau / 2 samples, so the estimator over the
/// M = N - tau + 1 coefficients that need no boundary is exactly half the
/// overlapping Allan variance at m: it is computed by the OADEV kernels.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/confidence.hpp"

namespace cubecal {

/// The Haar wavelet variance of a record at dyadic scales, with its EDF and intervals.
struct WaveletVariance {
  std::vector<double> tau;     ///< scale, samples: 2, 4, 8, ...
  std::vector<double> nu2;     ///< Haar wavelet variance, unit^2
  std::vector<std::size_t> n;  ///< coefficients, N - tau + 1
  /// Percival & Walden's third EDF approximation, eta3 = max(M / tau, 1):
  /// no noise type needed, which a composite process does not have.
  std::vector<double> edf;
  std::vector<Interval> interval;  ///< chi-square interval of nu2 at the confidence asked for
  /// Scales (taus) estimated.
  std::size_t size() const noexcept { return tau.size(); }
};

/// Scales 2^1 .. 2^J with J the largest for which 2^J <= N / 2 (at least
/// N / 2 + 1 coefficients), or fewer when max_scales > 0 asks so. Throws
/// UsageError(Field::samples) for fewer than 4 samples or ci outside (0, 1), and
/// std::invalid_argument naming a sample that is not finite.
WaveletVariance wavelet_variance(std::span<const double> y, double ci = 0.95, std::size_t max_scales = 0);

/// The same estimator at the scales tau = 2 m of the averaging factors m
/// given (ascending, 1 <= m <= N / 4), dyadic or not: half the overlapping
/// Allan variance at each m. The twin's fit (noise/twin_selection.hpp) adds
/// the factors 3 * 2^k between the dyadic ones, where a periodic line's
/// curve swings between them. Throws as wavelet_variance, and
/// UsageError(Field::scales) for factors not ascending or out of that range.
WaveletVariance wavelet_variance_at(std::span<const double> y, std::span<const std::size_t> factors, double ci = 0.95);

/// The dyadic factors 1, 2, 4, ... up to max_m and the factors 3 * 2^k
/// between them: 1, 2, 3, 4, 6, 8, 12, ...
std::vector<std::size_t> octave_and_half_factors(std::size_t max_m);

}  // namespace cubecal
