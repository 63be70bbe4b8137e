/// @file
/// Periodic lines of a record found in its Welch spectrum (Psd of raw bins,
/// pipeline/welch_psd.hpp): a bin whose density stands above the local
/// background (the median of its neighbours, the line's own main lobe left
/// out) further than the chi-square law of its EDF allows at a false-alarm
/// probability spread over the bins, merged with its neighbours into one
/// peak. Each peak's power is what it adds over the background,
/// sum (d_k - b_k) df (the Welch density keeps a sinusoid's power A^2 / 2),
/// its frequency the power-weighted centre of those bins. The starting
/// frequencies and amplitudes of a composite model's SIN terms
/// (noise/composite_model.hpp). docs/formulas/noise-terms.md §8f.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/noise/spectral_line.hpp"
#include "cubecal/spectral/psd.hpp"

namespace cubecal {

/// How find_spectral_lines searches.
struct LineSearchOptions {
  double false_alarm = 1e-3;  ///< probability that white noise gives one line anywhere in the spectrum
  double min_ratio = 4.0;     ///< and at least this far above the background
  std::size_t max_lines = 6;  ///< the strongest, by power
  /// Bins below this are not searched: lines with fewer periods in a segment
  /// are the slow processes' business (the first bins of a random walk rise).
  std::size_t min_bin = 8;
};

/// The lines of `psd` (raw bins, bins_per_decade 0), strongest first. Throws
/// std::invalid_argument for a log-binned spectrum.
std::vector<SpectralLine> find_spectral_lines(const Psd& psd, const LineSearchOptions& options = {});

}  // namespace cubecal
