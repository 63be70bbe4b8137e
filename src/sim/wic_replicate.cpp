// One replicate of the WIC's parametric bootstrap (sim/wic_replicate.hpp;
// docs/formulas/noise-terms.md §8c).
#include "cubecal/sim/wic_replicate.hpp"

#include <exception>
#include <vector>

#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/robust_wavelet_variance.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {

WicReplicate wic_replicate(const CompositeModel& structure, const GmwmFit& fit, std::size_t samples, std::size_t scales,
                           std::uint64_t seed, const GmwmOptions& options, double robust_efficiency) {
  WicReplicate r;
  try {
    const std::vector<double> y = simulate_composite(fit.model, samples, seed);
    WaveletVariance w = robust_efficiency > 0.0 ? robust_wavelet_variance(y, 0.95, robust_efficiency, scales)
                                                : wavelet_variance(y, 0.95, scales);
    if (w.size() != scales) return r;
    GmwmOptions opt = options;
    opt.start = fit.model;
    GmwmFit f = fit_gmwm(w, structure, opt);
    r.nu2 = std::move(w.nu2);
    r.model = std::move(f.nu2_model);
  } catch (const std::exception&) {
    // No fit for this replicate (a draw where the model is not finite).
  }
  return r;
}

}  // namespace cubecal
