/// @file
/// Power-law model of a measured spectrum: the coefficients h_alpha of
/// S_y(f) = sum_alpha h_alpha f^alpha (one-sided) with their covariance, the
/// frequency range where each term holds (is at least half the model), and a
/// single slope over a band. docs/formulas/spectral.md §5.
///
/// The fit is made on the raw Welch spectrum averaged over logarithmic bands
/// (log_bins.hpp), with the full covariance of the band averages
/// (bin_covariance.hpp) scaled by the model: generalized least squares,
/// iterated to its fixed point, which for independent bands is the maximum
/// of the gamma (chi-squared) likelihood of the densities; non-negative
/// coefficients (an active set, as the Allan five-term fit).
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/math/matrix.hpp"
#include "cubecal/spectral/psd.hpp"

namespace cubecal {

/// What the power-law fit of a spectrum fits, and over which band (Hz).
struct PowerLawFitOptions {
  /// The exponents alpha of the model, distinct, each within [-4, 4]. The
  /// default covers the IEEE 952 noises of a rate: rate random walk (-2),
  /// bias instability (-1), angle random walk (0), angle quantization (+2).
  std::vector<int> exponents{-2, -1, 0, 2};
  /// The band fitted. 0: from raw bin 10 (below it a tapered window leaks
  /// more than about 1.5 % of a steep f^-2 spectrum into the bin, and
  /// detrending reaches the lowest bins), and up to the last bin below
  /// Nyquist.
  double min_frequency_hz = 0.0;
  /// Upper end of the band fitted (Hz); 0: up to the last bin below Nyquist.
  double max_frequency_hz = 0.0;
  std::size_t bins_per_decade = 10;  ///< bands the raw bins are averaged over
};

/// One term h f^alpha of a power-law fit.
struct PowerLawTerm {
  /// The exponent alpha.
  int alpha = 0;
  double h = 0.0;      ///< unit^2 / Hz^(1 + alpha)
  double sigma = 0.0;  ///< 1-sigma uncertainty of h
  bool valid = false;  ///< false: h at its bound 0 (no such noise seen)
  /// Where h f^alpha is at least half of the model, within the fitted band;
  /// both 0 when it is nowhere.
  double f_lo = 0.0;
  /// Upper end of that band (Hz).
  double f_hi = 0.0;
};

/// The power-law model S(f) = sum h_alpha f^alpha fitted to a spectrum by generalized least squares on its log bands.
struct PowerLawFit {
  std::vector<PowerLawTerm> terms;  ///< in the order of the options' exponents
  Matrix covariance;                ///< of the h, terms.size() square (zero rows for terms at the bound)
  double f_lo = 0.0;                ///< the fitted band: first raw frequency used (Hz)
  double f_hi = 0.0;                ///< the fitted band: last raw frequency used (Hz)
  std::size_t bands = 0;            ///< log bands fitted
  double chi2 = 0.0;                ///< generalized residual sum of squares at the solution
  std::size_t dof = 0;              ///< bands - free coefficients
  /// max(1, chi2 / dof): the covariance is scaled by it (a model that misses
  /// the data widens its own uncertainties).
  double scale = 1.0;

  /// The term of exponent `alpha`, or null when the fit has none. Throws nothing.
  const PowerLawTerm* term(int alpha) const noexcept;
  double density(double f) const noexcept;  ///< sum h_alpha f^alpha
};

/// Throws UsageError(Field::exponents) for an empty, repeated or out-of-range
/// exponent, UsageError(Field::fit_range) when the band holds fewer log bands than
/// exponents + 1 (a longer segment or a wider band helps), and
/// std::invalid_argument for a spectrum without its bin covariance.
PowerLawFit fit_power_law(const Psd& raw, const PowerLawFitOptions& options = {});

/// One power law over [f_lo, f_hi]: ln S = ln A + slope ln(f / f_ref), by
/// generalized least squares on the log band averages (each ln D corrected
/// for its chi-squared bias psi(nu/2) - ln(nu/2), variance trigamma(nu/2),
/// covariance between bands from BinCovariance).
struct SlopeFit {
  /// The fitted slope of ln S against ln f (dimensionless).
  double slope = 0.0;
  /// 1 sigma of the slope.
  double slope_sigma = 0.0;
  double f_ref = 0.0;  ///< Hz: the geometric mean of the bands' frequencies
  double level = 0.0;  ///< A = S(f_ref), unit^2/Hz
  /// 1 sigma of the level (unit^2/Hz).
  double level_sigma = 0.0;
  /// Log bands fitted.
  std::size_t bands = 0;
  /// Generalized residual sum of squares at the solution.
  double chi2 = 0.0;
  /// bands - 2.
  std::size_t dof = 0;
};

/// Throws UsageError(Field::fit_range) for fewer than 3 bands in [f_lo, f_hi].
SlopeFit fit_slope(const Psd& raw, double f_lo, double f_hi, std::size_t bins_per_decade = 10);

}  // namespace cubecal
