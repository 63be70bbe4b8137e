/// @file
/// A Welch spectrum averaged over logarithmic frequency bands, for plots and
/// for the power-law fit: the raw bins with f_k in [10^(j/K), 10^((j+1)/K))
/// Hz are averaged into one entry (K bands per decade, edges at the same
/// frequencies for every record), keeping how many were averaged and the
/// EDF of their mean. docs/formulas/spectral.md §4.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/spectral/psd.hpp"

namespace cubecal {

/// A run of raw bins [first, first + count).
struct BinRun {
  /// The first raw bin of the run.
  std::size_t first = 0;
  /// Raw bins in the run.
  std::size_t count = 0;
};

/// The runs of raw bins that fall in each non-empty band between f_lo and
/// f_hi (inclusive), leaving out the DC bin and, for an even L, the Nyquist
/// bin (they hold half densities). Throws UsageError(Field::bins_per_decade) for
/// K = 0.
std::vector<BinRun> log_band_runs(const Psd& raw, std::size_t bins_per_decade, double f_lo, double f_hi);

/// The raw spectrum averaged over every band (f above zero, below Nyquist):
/// density the mean, frequency the geometric mean of the averaged bins'
/// frequencies, edf from BinCovariance. Throws std::invalid_argument when
/// `raw` is already binned.
Psd log_bin(const Psd& raw, std::size_t bins_per_decade);

}  // namespace cubecal
