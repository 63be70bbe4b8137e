// The twin error of a composite model on a measured Allan curve (noise/twin_error.hpp).
#include "cubecal/noise/twin_error.hpp"

#include <algorithm>
#include <cmath>

#include "cubecal/noise/sensor_noise_model.hpp"

namespace cubecal {

TwinError twin_error(const CompositeModel& model, std::span<const StabilityPoint> curve, double max_tau_s) {
  TwinError e;
  for (const StabilityPoint& p : curve) {
    if (!(p.tau <= max_tau_s * (1.0 + 1e-12)) || !(p.dev > 0.0) || !std::isfinite(p.dev) || p.m == 0) continue;
    const double sigma = std::sqrt(avar(model, p.m));
    if (!std::isfinite(sigma)) continue;
    ++e.taus;
    if (sigma >= p.interval.lo && sigma <= p.interval.hi) ++e.inside;
    const double err = std::abs(sigma / p.dev - 1.0);
    if (p.tau <= 10.0 * (1.0 + 1e-12)) e.max_error_10s = std::max(e.max_error_10s, err);
    if (p.tau <= 100.0 * (1.0 + 1e-12)) e.max_error_100s = std::max(e.max_error_100s, err);
    if (err > e.max_error || e.taus == 1) {
      e.max_error = err;
      e.max_error_tau_s = p.tau;
    }
  }
  e.share_inside = e.taus ? static_cast<double>(e.inside) / static_cast<double>(e.taus) : 0.0;
  return e;
}

}  // namespace cubecal
