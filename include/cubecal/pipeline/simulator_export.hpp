/// @file
/// A channel's composite noise model (its twin, AnalysisResult's
/// model.composite: noise/composite_model.hpp) in the noise configuration of
/// the simulators IMU teams run: gz-sensors' Gaussian noise with dynamic
/// bias (an SDF `<sensor type="imu">`), the RotorS / PX4 sitl_gazebo
/// gazebo_imu_plugin (an SDF `<plugin>`), NaveGo's IMU structure (a .m
/// script), MATLAB's imuSensor (gyroparams/accelparams, a .m script) and
/// Basilisk's imuSensor module (a Python snippet). docs/twin-exports.md
/// derives each target's noise equations from its source and the mapping.
///
/// No target expresses every process of a twin. Each export is the closest
/// projection of the twin onto the shapes the target can express (white
/// noise plus one Gauss-Markov bias; white noise, random walk and one
/// Gauss-Markov bias; one first-order process), fitted on the curve: the
/// GMWM (noise/gmwm.hpp) of the target's structure to the twin's theoretical
/// Haar wavelet variance at the channel's scales, weighted by the chi-square
/// spread of the measured one (nu2_twin sqrt(2 / edf)), started from the
/// twin's matching terms. What is left is the twin error, the largest
/// relative error of the Allan deviation the simulator gives against the
/// twin's, max over the scales of |sqrt(nu2_projection / nu2_twin) - 1|
/// (AVAR(m) = 2 WV(2m), so the ratio is that of the Allan deviations at
/// m = tau / 2). Terms with no place (SIN lines, an MA1's correlation, QN,
/// DR) are named as dropped.
#pragma once
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/estimator_config.hpp"

namespace cubecal::pipeline {

/// One channel's projection onto one target's noise model.
struct ExportProjection {
  /// The channel's name.
  std::string channel;
  /// "gazebo", "rotors", "navego", "matlab" (R2023b and later: a first-order
  /// BiasInstabilityCoefficients filter), "matlab-pre-R2023b" (the releases
  /// whose bias instability filter is fixed: white noise and random walk
  /// only), "basilisk".
  std::string target;
  std::string structure;  ///< the target's shape fitted: "WN+GM", "WN+RW+GM", "WN+RW", "WN", "RW", "GM"
  /// The projection: per-sample parameters at dt = 1 / rate_hz, in the
  /// channel's unit (as the twin), the processes of `structure`.
  CompositeModel model;
  std::vector<double> tau;       ///< the channel's scales, samples
  std::vector<double> nu2_twin;  ///< the twin's theoretical Haar wavelet variance at them, unit^2
  std::vector<double> nu2;       ///< the projection's
  double twin_error = 0.0;       ///< max over tau of |sqrt(nu2 / nu2_twin) - 1|
  double twin_error_tau = 0.0;   ///< the scale where it is largest, samples
  /// The same over the scales up to 10 s and up to 100 s (tau dt): the last
  /// scales rest on one or two degrees of freedom.
  double twin_error_10s = 0.0;
  /// The largest relative error over the scales up to 100 s.
  double twin_error_100s = 0.0;
  /// The twin's terms the target has no place for: "SIN 12.5 Hz (A = 0.01
  /// deg/s)", "MA1's theta = 0.3", "QN", "DR", a GM without a Gauss-Markov
  /// term in the structure.
  std::vector<std::string> dropped;
};

/// The simulator targets: gazebo, rotors, navego, matlab, basilisk.
bool is_simulator(Estimator e) noexcept;

/// The projections of every gyroscope (rate unit) and accelerometer
/// (acceleration unit) channel, in column order; for matlab two per channel,
/// "matlab" then "matlab-pre-R2023b". One per channel shares parameters with
/// the other axes of its sensor where the target does: rotors (one value per
/// sensor: the fit to the envelope of the sensor's axes, the largest of their
/// curves at each scale) and matlab (one BiasInstabilityCoefficients filter
/// per sensor: a common phi, fitted to the axes jointly). The fits' target is
/// the twin's expressible part (WN, an MA1 at its white level, RW, GM); the
/// twin error is against the whole twin. Throws
/// std::invalid_argument for an estimator that is not a simulator,
/// UsageError(Field::estimators) when the record has no IMU channel or an IMU
/// channel carries no composite model.
std::vector<ExportProjection> simulator_projections(Estimator e, const AnalysisResult& r);

/// The file of a simulator target (estimator_config dispatches to it).
/// Throws UsageError(Field::estimators) as simulator_projections, and
/// UsageError(Field::inflate) for ctx.inflate below 1 or not finite.
EstimatorFile simulator_config(Estimator e, const AnalysisResult& r, const EstimatorContext& ctx);

}  // namespace cubecal::pipeline
