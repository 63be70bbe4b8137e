/// @file
/// The selection of a composite noise model among candidates by the Wavelet
/// Information Criterion (noise/wic.hpp; docs/formulas/noise-terms.md §8c):
/// every candidate fitted by the GMWM, its optimism estimated by a parametric
/// bootstrap with the candidates and replicates on the threads, the
/// candidates ranked.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal::pipeline {

/// How the WIC selection runs: bootstrap replicates, seed, fit options, threads.
struct WicOptions {
  std::size_t replicates = 50;  ///< parametric-bootstrap replicates of the optimism (>= 2; 0: its asymptotic form)
  std::uint64_t seed = 1;       ///< replicate b of every candidate draws from seed + b (common random numbers)
  GmwmOptions gmwm;             ///< of every candidate's fit
  unsigned threads = 0;         ///< 0: all cores
  /// > 0: the wavelet variance `wv` is the robust one at this efficiency,
  /// and so is every replicate's (the asymptotic optimism's V scaled by its
  /// inverse).
  double robust_efficiency = 0.0;
};

/// The candidates ranked by WIC, and those that failed.
struct ModelSelection {
  std::vector<CandidateFit> ranked;  ///< by WIC, the selected model first
  std::vector<std::string> failed;   ///< candidates with no fit or no score, "WN+3*GM: why"
};

/// `samples` is the record's length (the bootstrap's). Candidates with more
/// parameters than the scales allow, or with no fit, go to `failed`. Throws
/// UsageError(Field::model) for no candidate or replicates == 1,
/// CalibrationError(degenerate) when no candidate gives a fit.
ModelSelection select_composite_model(const WaveletVariance& wv, std::size_t samples,
                                      const std::vector<CompositeModel>& candidates, const WicOptions& options = {});

}  // namespace cubecal::pipeline
