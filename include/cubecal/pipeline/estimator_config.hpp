/// @file
/// Noise parameters of an analysis in the configuration formats of state
/// estimators: Kalibr's imu.yaml, OpenVINS's kalibr_imu_chain.yaml, the IMU
/// block of a VINS-Mono/VINS-Fusion config and the imunoise block of a KF-GINS
/// config. Each file states in its comments the continuous-time definitions,
/// the units, where every number came from and the rules applied (one value
/// per sensor, terms not identified, inflation). docs/formulas/noise-terms.md
/// §8 gives the formulas. The simulator targets (gazebo, rotors, navego,
/// matlab, basilisk) export each channel's composite noise model instead:
/// pipeline/simulator_export.hpp, docs/twin-exports.md.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/pipeline/analyze.hpp"

namespace cubecal::pipeline {

/// The estimators and simulators whose noise-parameter files analyze writes (analyze --for).
enum class Estimator { kalibr, openvins, vins, kf_gins, gazebo, rotors, navego, matlab, basilisk };

/// "kalibr", "openvins", "vins", "kf-gins", "gazebo", "rotors", "navego",
/// "matlab", "basilisk"; nullopt for anything else.
std::optional<Estimator> parse_estimator(std::string_view name);
std::string_view estimator_name(Estimator e);  ///< as parse_estimator takes it
std::string estimator_names();                 ///< "kalibr|openvins|vins|kf-gins|gazebo|..."
/// The file written for each: imu.yaml, kalibr_imu_chain.yaml, vins_imu.yaml,
/// kf-gins_imunoise.yaml, gazebo_imu_noise.sdf, rotors_imu_plugin.sdf,
/// navego_imu.m, matlab_imu.m, basilisk_imu.py.
std::string_view estimator_file(Estimator e);

/// Where a number came from (noise/reported_terms.hpp).
using TermSource = cubecal::TermSource;

/// One channel's terms in SI units (rad/s or m/s^2 based), not inflated.
struct AxisNoise {
  /// The channel's name.
  std::string channel;
  double white = 0.0;  ///< noise density sigma_w = N, u/sqrt(Hz)
  /// Where white came from.
  TermSource white_source = TermSource::read_off;
  double white_tau_lo = 0.0;  ///< the tau range N was read over (read-off), s
  /// Upper end of that tau range (s).
  double white_tau_hi = 0.0;
  double walk = 0.0;  ///< bias random walk sigma_bw = K, u/s/sqrt(Hz)
  /// Where walk came from.
  TermSource walk_source = TermSource::fit;
  double walk_estimate = 0.0;        ///< walk an upper bound because K was not significant: the estimate
  double walk_estimate_sigma = 0.0;  ///< and its 1-sigma uncertainty (0 when K was not estimated at all)
  /// Where walk_estimate came from.
  TermSource walk_estimate_source = TermSource::fit;
  double bias_std = 0.0;  ///< bias as a first-order Gauss-Markov process: std (bias instability B), u
  double bias_tc = 0.0;   ///< and correlation time (T, the tau of the curve's minimum), s
  /// Where bias_std and bias_tc came from.
  TermSource bias_source = TermSource::read_off;
  double mean = 0.0;  ///< mean of the record, u
};

/// Channels with a rate unit (gyroscope) and an acceleration unit
/// (accelerometer), in column order; other kinds are not IMU channels.
struct ImuNoise {
  /// The gyroscope channels and the accelerometer channels, in column order.
  ///@{
  std::vector<AxisNoise> gyroscope, accelerometer;
  ///@}
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
};

/// The rules (docs/formulas/noise-terms.md §8.2) are those of every output
/// (noise/reported_terms.hpp): white = the read-off N (the -1/2 line at
/// tau = 1 s), else the upper bound min over tau of sigma(tau) sqrt(tau);
/// walk = K of the fit, else of the read-off, only when significant
/// (value > 2 sigma), else the upper bound min over tau of sigma(tau)
/// sqrt(3/tau); Gauss-Markov bias (KF-GINS): the read-off B with the time T
/// of the curve's minimum, else (no minimum within the record) the upper
/// bound sigma_min / 0.664 with the tau where the curve is lowest. Not the
/// Gauss-Markov model fit: without a minimum it runs to T_c = 2 dt.
/// Throws InputError naming the channel when its Allan deviation is zero at
/// every tau (a constant record has no noise to report).
ImuNoise imu_noise(const AnalysisResult& r);

/// Throws UsageError (option "estimators") when none of `units` is a rate or
/// an acceleration unit: no estimator file can be written from such channels.
/// The CLI calls it with the --unit list before the work starts.
void require_imu_units(const std::vector<Unit>& units);

/// What an estimator file records besides the terms.
struct EstimatorContext {
  std::string command;  ///< the command line, written in the header
  /// The IMU topic written where the format has one.
  std::string rostopic = "/imu0";
  double inflate = 1.0;  ///< >= 1: multiplies every density, random walk and bias std
};

/// One estimator file. `missing` names the sensor whose terms the file lacks
/// ("accelerometer", "gyroscope") because the record has no such channel;
/// the keys are then written commented out with the reason. Empty otherwise.
struct EstimatorFile {
  /// The file's name (estimator_file).
  std::string name;
  /// The file's text.
  std::string text;
  /// The sensor whose terms the file lacks; empty when none.
  std::string missing;
};

/// The file of `e`. Throws UsageError (option "estimators") when the record
/// has neither a rate nor an acceleration channel, or when ctx.inflate is
/// below 1 or not finite; InputError as imu_noise. A simulator target
/// (simulator_export.hpp) also when an IMU channel has no composite model.
EstimatorFile estimator_config(Estimator e, const AnalysisResult& r, const EstimatorContext& ctx);

}  // namespace cubecal::pipeline
