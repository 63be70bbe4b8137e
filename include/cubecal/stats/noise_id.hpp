// Power-law noise identification at one averaging factor, as Stable32 does
// it: lag-1 autocorrelation (Riley & Greenhall 2004) when at least 30
// points remain after averaging, otherwise the B1 ratio (Barnes) refined by
// R(n) for the modified statistics, bounded by the autocorrelation result at
// the longest tau that still has 30 points (see noise_id.cpp).
#pragma once
#include <cstddef>
#include <span>

#include "cubecal/stats/statistic.hpp"

namespace cubecal {

struct NoiseId {
  int alpha = 0;          // exponent of the frequency PSD: +2 WPM ... -4 RRFM
  double alpha_est = 0;   // unrounded estimate (lag-1 ACF method only)
  // acf: lag-1 autocorrelation; b1 (b1_rn with R(n)): short series;
  // b1_bounded: B1 overruled by the ACF type at the longest reliable tau.
  enum class Method { acf, b1, b1_rn, b1_bounded } method = Method::acf;
};

// x: phase record of the whole series (as used by the statistic, in any
// unit); original: the type the user supplied, which decides whether the
// ACF runs on decimated phase or averaged frequency.
NoiseId identify_noise(std::span<const double> x, std::size_t m, DataType original, Stat stat);

// Lag-1 autocorrelation of a sequence (mean removed).
double lag1_autocorrelation(std::span<const double> z) noexcept;

}  // namespace cubecal
