/// @file
/// The spectral view of an analysis (`analyze --psd`, AnalyzeRequest::psd):
/// a channel's power spectral density, its power-law fit and the IEEE 952
/// terms the fit stands for, as `cubecal psd` makes them (pipeline/psd.hpp),
/// and each term beside the one the Allan curve gives.
/// docs/formulas/spectral.md §6.3.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/spectral/power_law_fit.hpp"
#include "cubecal/spectral/psd.hpp"

namespace cubecal::pipeline {

/// Log bands per decade of the spectrum an analysis keeps (for its plot):
/// `cubecal psd --bins-per-decade 20` gives the same.
inline constexpr std::size_t kSpectrumBinsPerDecade = 20;

/// The spectral view of a channel (AnalyzeRequest::psd): what `cubecal psd
/// --bins-per-decade 20` gives for it (pipeline/psd.hpp, PsdChannel), with the
/// Welch plan of the run. docs/formulas/spectral.md §6.3.
struct SpectralAnalysis {
  /// Averaged over kSpectrumBinsPerDecade log bands per decade; its
  /// bin_covariance is left empty (the fit has used it; analysis.json does not
  /// hold it).
  Psd spectrum;
  PowerLawFit fit;                        ///< terms empty when not made
  std::vector<PsdAllanTerm> allan_terms;  ///< the IEEE 952 terms of the fitted h_alpha
  std::string fit_error;                  ///< why no fit was made (a record too short for its band)
  double overlap = 0.5;                   ///< the fraction asked (spectrum.overlap: the samples)
  std::size_t pieces = 1;                 ///< contiguous pieces of the record (> 1 when split at gaps)
  std::size_t pieces_used = 1;            ///< pieces holding at least one Welch segment
};

/// One IEEE 952 term from the two views of a channel: the five-term fit of
/// the Allan curve (NoiseAnalysis::fit) and the power-law fit of the spectrum
/// (SpectralAnalysis::allan_terms), in the data unit and seconds.
struct TermViews {
  /// Which term.
  Term term = Term::N;
  /// From the Allan curve's five-term fit.
  TermEstimate allan;
  /// From the spectrum's power-law fit.
  TermEstimate spectrum;
  /// (spectrum - allan) / sqrt(sigma_spectrum^2 + sigma_allan^2); empty
  /// unless both views found the term (valid) with a positive combined sigma.
  std::optional<double> difference_sigmas;
};

/// N, B, K, Q as far as the spectrum's fit has them (none when no fit was
/// made), each beside the Allan curve's. docs/formulas/spectral.md §6.3.
std::vector<TermViews> compare_views(const NoiseFit& allan, const SpectralAnalysis& spectral);

}  // namespace cubecal::pipeline
