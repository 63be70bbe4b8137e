/// @file
/// A one-sided power spectral density as the Welch estimator gives it
/// (pipeline/welch_psd.hpp), or averaged over logarithmic bands
/// (spectral/log_bins.hpp): frequencies, densities in the channel unit^2/Hz,
/// and how well each density is known. docs/formulas/spectral.md §1-§4.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/spectral/welch_options.hpp"

namespace cubecal {

/// A one-sided power spectral density of a record (Welch's estimate, pipeline/welch_psd.hpp), with how it was made and
/// the EDF of each density.
struct Psd {
  /// The record's sampling rate (Hz).
  double rate_hz = 0.0;
  /// The window each segment was multiplied by.
  Window window = Window::hann;
  /// What was removed from each segment.
  Detrend detrend = Detrend::constant;
  std::size_t segment_length = 0;   ///< L: samples per segment (the transform length)
  std::size_t overlap = 0;          ///< samples shared by consecutive segments
  std::size_t segments = 0;         ///< segments averaged, over every piece of the record
  std::size_t samples_used = 0;     ///< samples inside at least one segment
  double enbw_hz = 0.0;             ///< equivalent noise bandwidth of one bin: rate sum w^2 / (sum w)^2
  std::size_t bins_per_decade = 0;  ///< 0: the raw bins of the transform; else averaged over log bands

  /// One entry per raw bin k = 0..floor(L/2) (f_k = k rate / L), or per
  /// logarithmic band (the geometric mean of its raw frequencies).
  std::vector<double> frequency;       ///< Hz
  std::vector<double> density;         ///< unit^2/Hz, one-sided (the DC and Nyquist bins hold half, as scipy)
  std::vector<double> edf;             ///< equivalent degrees of freedom of each density (§3)
  std::vector<std::size_t> first_bin;  ///< the raw bin k of the entry's first bin
  std::vector<std::size_t> bins;       ///< raw bins averaged into the entry (1 for the raw spectrum)

  /// The covariance of two raw densities d bins apart over the square of
  /// their expectation, for a spectrum white across both, d = 0..floor(L/2)
  /// (§3: g(d)); filled by the estimator, kept by log binning.
  std::vector<double> bin_covariance;

  /// Entries (bins or bands). Throws nothing.
  std::size_t size() const noexcept { return frequency.size(); }
  /// The raw bin spacing rate / L (Hz); 0 when there are no segments. Throws nothing.
  double resolution_hz() const noexcept { return segment_length ? rate_hz / static_cast<double>(segment_length) : 0.0; }
};

}  // namespace cubecal
