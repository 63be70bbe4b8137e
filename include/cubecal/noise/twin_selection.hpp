/// @file
/// The twin of a sensor channel: the composite noise model
/// (noise/composite_model.hpp) that reproduces its Haar wavelet variance,
/// chosen among the shapes real MEMS sensors show — white noise or its
/// filtered form MA1, quantization, random walk, drift, up to four
/// Gauss-Markov terms (a flicker floor is their sum) and the periodic lines
/// of its spectrum (SIN terms started at the lines of
/// spectral/spectral_lines.hpp) — by a forward search on the Wavelet
/// Information Criterion (noise/wic.hpp) with its asymptotic optimism, and a
/// fidelity rule: among the models the search passed through, refitted with
/// common weights, the one the WIC ranks first (rank_by_wic) among those whose
/// curve lies inside the measured 95 % intervals at nearly every scale: at
/// most as many outside as the true model leaves with 99 % probability (the
/// 0.99 quantile of Binomial(J, 0.05): 3 of 18 scales).
/// docs/formulas/noise-terms.md §8f, docs/twins.md.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/spectral_line.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {

/// How the twin search runs.
struct TwinOptions {
  std::size_t max_gm = 4;            ///< Gauss-Markov terms
  std::size_t max_lines = 4;         ///< SIN terms, from the strongest line down
  std::size_t starts = 2;            ///< per candidate fit: the warm start from the model it grows, and scattered ones
  std::size_t max_iterations = 100;  ///< Levenberg-Marquardt steps per start of the search's fits
  double band = 2.0;                 ///< a step must lower the WIC by more than this
  /// The ranking picks the fewest parameters among the models within this
  /// of the lowest WIC (rank_by_wic's 2, widened: the search passes many
  /// near-equivalent shapes, a Gauss-Markov term beyond the record and a
  /// drift among them, and the fidelity rule guards against too few).
  double rank_band = 6.0;
  std::uint64_t seed = 1;  ///< of the scattered starts
};

/// How close a model's curve is to the measured one.
struct TwinFidelity {
  std::size_t scales = 0;      ///< compared
  std::size_t inside = 0;      ///< whose model value lies in the 95 % chi-square interval of the scale
  double share_inside = 0.0;   ///< inside / scales
  double max_error = 0.0;      ///< largest |sqrt(nu2_model / nu2) - 1|: the deviation's relative error
  double max_error_tau = 0.0;  ///< the scale (samples) where it is largest
};
/// How close the model's wavelet variance `nu2_model` (one per scale of `wv`) is to the measured one, over the scales
/// both have. Throws boost::math's domain error for a scale with a non-positive EDF.
TwinFidelity twin_fidelity(const WaveletVariance& wv, const std::vector<double>& nu2_model);
/// Inside at nearly every scale: at most as many outside as the true model
/// leaves with probability 0.99 (the 0.99 quantile of Binomial(J, 0.05)).
bool twin_faithful(const TwinFidelity& fidelity);

/// A model the twin search reached, fitted with the common weights and scored.
struct TwinCandidate {
  CompositeModel structure;  ///< with the SIN terms' starting frequencies and amplitudes
  GmwmFit fit;               ///< with the common weights
  /// Its WIC.
  WicScore score;
  /// How close its curve is to the measured one.
  TwinFidelity fidelity;
  std::size_t step = 0;  ///< of the search that reached it (0: the start)
};

/// The twin search's outcome: the candidates ranked, the selected one first.
struct TwinSelection {
  std::vector<TwinCandidate> ranked;  ///< the selected first, then the others by WIC
  std::vector<std::string> failed;    ///< models the search tried without a fit or a score, and why
  bool faithful = false;              ///< the selected one lies inside the intervals at nearly every scale
};

/// `samples`: the record's length (the WIC's covariance). Throws
/// UsageError(Field::model) for a wavelet variance of fewer than 3 scales (a
/// record too short for any model) and CalibrationError(degenerate) when not
/// even white noise fits.
TwinSelection select_twin(const WaveletVariance& wv, std::size_t samples, double rate_hz,
                          const std::vector<SpectralLine>& lines, const TwinOptions& options = {});

}  // namespace cubecal
