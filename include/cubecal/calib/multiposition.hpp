/// @file
/// Multi-position calibration of an accelerometer and a gyroscope without a
/// turntable (Tedaldi, Pretto & Menegatti, ICRA 2014; the imu_tk code):
/// docs/formulas/multiposition.md.
///
/// Model of each triad (raw X in counts or any unit, calibrated X'):
///     X' = T K (X - B),   K = diag(s_x, s_y, s_z),
///     T = [[ 1,      -mis_yz,  mis_zy ],
///          [ mis_xz,  1,      -mis_zx ],
///          [-mis_xy,  mis_yx,  1      ]]      (imu_tk's names and signs).
/// The accelerometer defines the body frame: its mis_xz = mis_xy = mis_yx = 0
/// (T_a upper-triangular), 9 parameters (3 misalignments, 3 scales, 3 biases).
/// The gyroscope has 9 parameters (6 misalignments, 3 scales); its bias is the
/// mean over the initial static period, optionally refined (3 more).
///
/// Procedure:
/// 1. Static detection. v(i) = |(var_x, var_y, var_z)| of the accelerometer over
///    the centred window [i-h, i+h] (window = 2h+1 samples, unbiased variance);
///    a static interval is a maximal run of window centres with v(i) below the
///    threshold, [begin, end) (end is the first centre at or above it). The
///    threshold is th_mult x |var| of the initial static period (the whole
///    period, not windowed). Intervals shorter than interval_samples centres
///    are dropped.
/// 2. Accelerometer: for th_mult = 2..10 with at least min_intervals intervals,
///    Levenberg-Marquardt on r = g - |T K (a - B)| over the first
///    interval_samples samples of every interval (or the interval means),
///    starting from the same initial guess; the th_mult with the smallest final
///    cost is kept.
/// 3. Gyroscope: u_k = normalised mean of the calibrated accelerometer over
///    interval k. Between intervals k-1 and k the calibrated gyro
///    w = T K (w_raw - b) is integrated from the time of end_{k-1} to that of
///    begin_k (RK4 on the quaternion, q' = q (x) (0, w)/2, rates at both ends
///    of each step and their mean at the midpoint, as imu_tk), giving R (end
///    body frame to start body frame). Residual R^-1 u_{k-1} - u_k, 3 per pair;
///    Levenberg-Marquardt.
///
/// Costs are sums of squared residuals, sum r^2 (Ceres and imu_tk print half
/// of that). Uncertainties are 1 sigma from sigma0^2 (J^T J)^-1 at the
/// solution, sigma0^2 = cost / (residuals - parameters): they assume white,
/// independent residuals and say nothing of model error.
#pragma once
#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "cubecal/calib/static_detection.hpp"
#include "cubecal/math/matrix.hpp"
#include "cubecal/math/vec3.hpp"

namespace cubecal::multipos {

/// Samples per static interval by default (and its minimum length).
inline constexpr std::size_t kIntervalSamples = 100;
/// Fewest static intervals a calibration accepts by default.
inline constexpr std::size_t kMinIntervals = 12;

/// A triad's calibration model (imu_tk's): misalignment T, scale K and bias B, calibrated = T K (raw - B).
struct TriadCalibration {
  /// used by both triads
  ///@{
  double mis_yz = 0.0, mis_zy = 0.0, mis_zx = 0.0;
  ///@}
  /// gyroscope only (0 for the accelerometer)
  ///@{
  double mis_xz = 0.0, mis_xy = 0.0, mis_yx = 0.0;
  ///@}
  Vec3 scale{1.0, 1.0, 1.0};  ///< K (calibrated unit per raw unit)
  Vec3 bias{};                ///< B (raw unit)

  Mat3 misalignment() const noexcept;          ///< T
  Mat3 matrix() const noexcept;                ///< T K
  Vec3 apply(const Vec3& raw) const noexcept;  ///< T K (raw - B)
};

/// One triad record: samples and either time stamps (s, strictly increasing,
/// one per sample) or, when t is empty, a uniform rate.
struct TriadSeries {
  /// Samples of the triad (raw unit).
  std::span<const Vec3> x;
  /// Time stamps (s), one per sample; empty: uniform at rate_hz.
  std::span<const double> t;
  /// Sampling rate (Hz) when t is empty.
  double rate_hz = 0.0;
};

/// What a multi-position calibration is asked to do (calibrate_accelerometer, calibrate_gyroscope).
struct Options {
  double g = 9.80665;           ///< local gravity: |calibrated acceleration| (sets its unit)
  double init_static_s = 50.0;  ///< initial static period: samples with t < t_0 + this
  /// Samples of the static detector's moving window (odd, at least kMinWindow).
  std::size_t window = kDefaultWindow;
  std::size_t interval_samples = kIntervalSamples;  ///< per interval (and its minimum length)
  /// Fewest static intervals accepted.
  std::size_t min_intervals = kMinIntervals;
  /// Smallest multiple of the initial period's variance norm tried as the static threshold.
  int th_mult_min = 2;
  /// Largest multiple of the initial period's variance norm tried as the static threshold.
  int th_mult_max = 10;
  bool acc_use_means = false;  ///< one residual per interval (its mean) instead of its samples
  Vec3 acc_bias_guess{};       ///< initial B_a (raw unit), e.g. 32768 for offset-binary counts
  /// Initial s_a for all three axes (calibrated unit per raw unit). 0: g over
  /// the mean |a - B_a guess| of the initial static period.
  double acc_scale_guess = 0.0;
  double gyro_scale_guess = 1.0;  ///< initial s_g (rad/s per raw unit)
  bool refine_gyro_bias = false;  ///< 3 more gyro parameters (bias corrections)
  /// Most Levenberg-Marquardt iterations of each fit.
  std::size_t max_iterations = 200;
};

/// One th_mult tried.
struct Trial {
  /// The multiple of the initial variance norm tried.
  int th_mult = 0;
  /// The static threshold it gave (raw unit squared).
  double threshold = 0.0;
  std::size_t intervals = 0;  ///< of at least interval_samples
  bool fitted = false;        ///< enough intervals and a determined fit
  double cost = 0.0;          ///< final cost when fitted
};

/// Statistics of the residuals of a fit.
struct Residuals {
  /// Residuals counted.
  std::size_t count = 0;
  double cost = 0.0;  ///< sum r^2
  double rms = 0.0;   ///< sqrt(cost / count)
  double max = 0.0;   ///< max |r|
};

/// The accelerometer calibration (steps 1-2): the model, its parameters with their uncertainty, and the fit.
struct AccResult {
  /// The calibrated model.
  TriadCalibration model;
  TriadCalibration initial;  ///< the starting point (the "before" model)
  /// Parameters in the order mis_yz, mis_zy, mis_zx, s_x, s_y, s_z, b_x, b_y, b_z.
  std::vector<std::string> names;
  /// The parameters' values, in the order of names.
  std::vector<double> values;
  /// The parameters' standard deviations (1 sigma), in the order of names.
  std::vector<double> sigma;
  /// Covariance of the parameters (9 x 9, in the order of names):
  /// sigma0^2 (J^T J)^-1.
  Matrix covariance;
  /// Accelerometer samples in the initial static period (init_static_s).
  std::size_t init_samples = 0;
  /// Norm of the per-axis variances over the initial static period (raw unit squared).
  double init_variance_norm = 0.0;
  /// The chosen multiple of the initial variance norm.
  int th_mult = 0;
  /// The chosen static threshold (raw unit squared).
  double threshold = 0.0;
  /// Every multiple tried, in order.
  std::vector<Trial> trials;
  std::vector<IndexRange> intervals;  ///< used ones, for the chosen th_mult (accelerometer indices)
  /// r = g - |a'| over the fitted samples
  ///@{
  Residuals before, after;
  ///@}
  double sigma0 = 0.0;  ///< sqrt(cost / (residuals - 9))
  /// Levenberg-Marquardt iterations of the chosen fit.
  std::size_t iterations = 0;
  /// False when the fit stopped at max_iterations.
  bool converged = false;
};

/// The gyroscope calibration (step 3): the model, its parameters with their uncertainty, and the fit.
struct GyroResult {
  TriadCalibration model;    ///< bias: initial-period mean (+ refinement)
  TriadCalibration initial;  ///< scale guess, no misalignment, initial-period bias
  /// mis_yz, mis_zy, mis_zx, mis_xz, mis_xy, mis_yx, s_x, s_y, s_z
  /// [, db_x, db_y, db_z: bias corrections when refined].
  std::vector<std::string> names;
  /// The parameters' values, in the order of names.
  std::vector<double> values;
  /// 1 sigma and covariance: the fit's sigma0^2 (J^T J)^-1 plus the
  /// propagated accelerometer covariance (through the gravity directions) and,
  /// unless refined, the initial-bias standard error. sigma_fit: the first
  /// term alone (conditional on both).
  std::vector<double> sigma;
  /// The fit's own standard deviations (1 sigma), without the propagated terms.
  std::vector<double> sigma_fit;
  /// Covariance of the parameters, in the order of names (see sigma).
  Matrix covariance;
  /// Gyroscope samples in the initial static period (init_static_s).
  std::size_t init_samples = 0;
  Vec3 init_bias{};        ///< mean over the initial static period
  Vec3 init_bias_sigma{};  ///< its standard error (white noise)
  Vec3 bias_sigma{};       ///< of model.bias: init_bias_sigma, or from the fit when refined
  std::size_t pairs = 0;   ///< consecutive interval pairs (residual blocks)
  /// components of R^-1 u_{k-1} - u_k
  ///@{
  Residuals before, after;
  ///@}
  double angle_rms_before_deg = 0.0;  ///< RMS angle between R^-1 u_{k-1} and u_k
  /// RMS angle between R^-1 u_{k-1} and u_k after calibration (deg).
  double angle_rms_after_deg = 0.0;
  /// Largest angle between R^-1 u_{k-1} and u_k after calibration (deg).
  double angle_max_after_deg = 0.0;
  /// sqrt(cost / (residuals - parameters)).
  double sigma0 = 0.0;
  /// Levenberg-Marquardt iterations.
  std::size_t iterations = 0;
  /// False when the fit stopped at max_iterations.
  bool converged = false;
};

/// Both triads' calibrations of one multi-position run.
struct Result {
  /// The accelerometer's.
  AccResult acc;
  /// The gyroscope's.
  GyroResult gyro;
};

/// Accelerometer calibration (steps 1-2). Throws CalibrationError
/// (cubecal/error.hpp), with a message fit for the user:
///   bad_data           non-finite samples or time stamps, stamps of the wrong
///                      count or not increasing;
///   bad_option         no time stamps and no positive rate, an option out of
///                      range (g, init_static_s, window, th_mult range, ...);
///   too_few_points     no samples;
///   initial_static     the record is not longer than the initial static
///                      period, the period holds fewer samples than the
///                      window, or the accelerometer is constant over it;
///   scale_guess        the period reads the bias guess exactly (no automatic
///                      scale), or the initial guess gives non-finite residuals;
///   too_few_intervals  fewer than min_intervals static intervals for every
///                      th_mult;
///   degenerate         the poses do not determine the parameters.
AccResult calibrate_accelerometer(const TriadSeries& acc, const Options& opt);

/// Gyroscope calibration (step 3) given the accelerometer result on `acc`.
/// The gyro is matched to the accelerometer intervals by time. Throws
/// CalibrationError: bad_data, bad_option, too_few_points as above (for either
/// record); too_few_intervals (fewer than 2 intervals in acc_result, or
/// intervals that do not match the accelerometer record); initial_static (fewer
/// than 2 gyro samples in the initial period); bad_data (the gyro record does
/// not cover the motion between two intervals); scale_guess (non-finite
/// residuals at the guess, or a fit converged to a non-positive scale);
/// degenerate (the motions do not determine the parameters).
GyroResult calibrate_gyroscope(const TriadSeries& acc, const AccResult& acc_result, const TriadSeries& gyro,
                               const Options& opt);

/// Both.
Result calibrate(const TriadSeries& acc, const TriadSeries& gyro, const Options& opt);

}  // namespace cubecal::multipos
