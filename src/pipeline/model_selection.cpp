// The WIC selection of a composite model (pipeline/model_selection.hpp;
// docs/formulas/noise-terms.md §8c).
#include "cubecal/pipeline/model_selection.hpp"

#include <omp.h>

#include <algorithm>
#include <exception>
#include <optional>

#include "cubecal/error.hpp"
#include "cubecal/sim/wic_replicate.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

ModelSelection select_composite_model(const WaveletVariance& wv, std::size_t samples,
                                      const std::vector<CompositeModel>& candidates, const WicOptions& options) {
  if (candidates.empty()) throw UsageError(Field::model, "no candidate model to select from");
  if (options.replicates == 1)
    throw UsageError(Field::model, "the WIC's bootstrap needs at least 2 replicates (0: its asymptotic form)");
  const int threads = options.threads > 0 ? static_cast<int>(options.threads) : omp_get_max_threads();
  const std::size_t nc = candidates.size(), reps = options.replicates;

  // The common weights from the fit of the largest candidate (the most
  // parameters; the next when it gives none), reweighted as a lone fit is.
  std::vector<std::size_t> by_size(nc);
  for (std::size_t c = 0; c < nc; ++c) by_size[c] = c;
  std::stable_sort(by_size.begin(), by_size.end(), [&](std::size_t a, std::size_t b) {
    return parameter_count(candidates[a]) > parameter_count(candidates[b]);
  });
  std::vector<double> sd;
  std::string no_reference;
  for (std::size_t c : by_size) {
    try {
      sd = wic_weights(wv, fit_gmwm(wv, candidates[c], options.gmwm).nu2_model);
      break;
    } catch (const std::exception& e) {
      if (no_reference.empty()) no_reference = model_name(candidates[c]) + ": " + e.what();
    }
  }
  if (sd.empty())
    throw CalibrationError(CalibrationReason::degenerate, "GMWM: no candidate model gave a fit (" + no_reference + ")");
  GmwmOptions fixed = options.gmwm;
  fixed.fixed_sd = sd;

  // Every candidate fitted with those weights kept.
  std::vector<std::optional<GmwmFit>> fits(nc);
  std::vector<std::string> why(nc);
  cubecal::detail::for_channels(nc, cubecal::detail::Team{threads}, [&](std::size_t c) {
    try {
      fits[c] = fit_gmwm(wv, candidates[c], fixed);
    } catch (const std::exception& e) {  // UsageError: more parameters than scales; CalibrationError: no fit
      why[c] = e.what();
    }
  });

  // Replicate b of every candidate from seed + b: common random numbers.
  std::vector<WicReplicate> draws(nc * reps);
  cubecal::detail::for_channels(nc * reps, cubecal::detail::Team{threads}, [&](std::size_t k) {
    const std::size_t c = k / reps, b = k % reps;
    if (fits[c])
      draws[k] = wic_replicate(candidates[c], *fits[c], samples, wv.size(), options.seed + b, fixed,
                               options.robust_efficiency);
  });

  ModelSelection sel;
  for (std::size_t c = 0; c < nc; ++c) {
    if (!fits[c]) {
      sel.failed.push_back(model_name(candidates[c]) + ": " + why[c]);
      continue;
    }
    const std::vector<WicReplicate> mine(draws.begin() + static_cast<std::ptrdiff_t>(c * reps),
                                         draws.begin() + static_cast<std::ptrdiff_t>((c + 1) * reps));
    try {
      CandidateFit cf{candidates[c], std::move(*fits[c]), {}};
      cf.score = reps > 0
                     ? wic_score(wv, sd, cf.fit, mine)
                     : wic_score_asymptotic(wv, sd, cf.fit, samples,
                                            options.robust_efficiency > 0.0 ? 1.0 / options.robust_efficiency : 1.0);
      sel.ranked.push_back(std::move(cf));
    } catch (const std::exception& e) {  // too few replicates; a parameter the curve does not determine
      sel.failed.push_back(model_name(candidates[c]) + ": " + e.what());
    }
  }
  if (sel.ranked.empty())
    throw CalibrationError(CalibrationReason::degenerate,
                           "GMWM: no candidate model gave a fit (" + sel.failed.front() + ")");
  rank_by_wic(sel.ranked);
  return sel;
}

}  // namespace cubecal::pipeline
