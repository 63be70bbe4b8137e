/// @file
/// One replicate of the parametric bootstrap behind the WIC's optimism
/// (noise/wic.hpp): a candidate's fitted model simulated at the record's
/// length (sim/composite_simulator.hpp), the replicate's wavelet variance,
/// and the model refitted to it. The simulator's side of the WIC, so that the
/// noise models need no simulator. docs/formulas/noise-terms.md §8c.
#pragma once
#include <cstddef>
#include <cstdint>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/wic.hpp"

namespace cubecal {

/// The fitted model simulated at the record's length (seed), its wavelet
/// variance at the record's `scales`, refitted from the fit. Empty vectors
/// when the replicate gives no fit (it is left out and counted).
/// robust_efficiency > 0: the replicate's wavelet variance is the robust one
/// at that efficiency (stats/robust_wavelet_variance.hpp), as the record's.
WicReplicate wic_replicate(const CompositeModel& structure, const GmwmFit& fit, std::size_t samples, std::size_t scales,
                           std::uint64_t seed, const GmwmOptions& options = {}, double robust_efficiency = 0.0);

}  // namespace cubecal
