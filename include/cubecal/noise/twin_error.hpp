/// @file
/// How far a composite model's Allan deviation (noise/sensor_noise_model.hpp:
/// avar(CompositeModel, m), exact at every averaging factor) lies from a
/// measured OADEV curve: the twin error that `analyze` reports per channel
/// and `analyze --twin-check` measures on simulated twins. docs/twins.md.
#pragma once
#include <cstddef>
#include <limits>
#include <span>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/stats/stability.hpp"

namespace cubecal {

/// How far a model's Allan curve is from a measured one, point by point.
struct TwinError {
  std::size_t taus = 0;          ///< points of the curve compared (tau <= max_tau_s)
  std::size_t inside = 0;        ///< whose model deviation lies in the point's interval [lo, hi]
  double share_inside = 0.0;     ///< inside / taus
  double max_error = 0.0;        ///< largest |sigma_model / sigma_measured - 1|
  double max_error_tau_s = 0.0;  ///< where
  /// The same over the taus up to 10 s and up to 100 s: the last points of a
  /// curve rest on a few averages, and a simulator's user reads these.
  double max_error_10s = 0.0;
  /// The largest relative error over the taus up to 100 s.
  double max_error_100s = 0.0;
};

/// The model's parameters are per sample of the curve's period (each point's
/// m is its averaging factor). Points whose deviation is not positive and
/// finite are left out.
TwinError twin_error(const CompositeModel& model, std::span<const StabilityPoint> curve,
                     double max_tau_s = std::numeric_limits<double>::infinity());

}  // namespace cubecal
