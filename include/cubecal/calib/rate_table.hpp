/// @file
/// Gyro calibration on a rate table (docs/formulas/rate-table.md; the paper's
/// eq. 6-13, docs/paper.md §2.6): scale factors, misalignment and bias from the gyro means of
/// several constant-rate plateaus.
///
/// What is fitted is the FORWARD model, noise on the observed side:
///     w_g,j = S w_j + b_g + n_j          (plateau j, gyro mean w_g,j, true rate w_j)
/// stacked as Y = X Theta with row j of X = [w_j^T 1], row j of Y = w_g,j^T,
/// Theta = [S^T; b_g^T] (4x3), solved by QR. Fitting the paper's inverse form
/// directly would put the gyro noise in the regressors and bias the fit.
/// The paper's form follows by inversion:
///     w = A w_g + beta,   A = S^-1,   beta = -S^-1 b_g        (docs/formulas/rate-table.md §2)
///
/// Uncertainty: the plateau noise R (3x3, across axes) is estimated from the
/// fit residuals with P - 4 degrees of freedom, so it includes whatever the
/// within-plateau spread misses (bias drift between plateaus, table rate
/// errors); Cov(vec Theta) = R (x) (X^T X)^-1. A and beta get theirs by the
/// delta method (dA = -A dS A, dbeta = -A dS beta - A db_g). With exactly 4
/// plateaus there are no residual degrees of freedom and R falls back to the
/// within-plateau variances std^2 / n (white noise only).
///
/// Earth rate: a gyro on a rate table also senses the Earth's rotation
/// Omega_E = 7.2921159e-5 rad/s (15.04 deg/h). It is ignored by default, as in
/// the paper, whose table compensated it. A constant Earth-rate vector in the
/// sensor frame only moves the bias (b_g absorbs S Omega_E), never S; to refer
/// the bias to an inertial frame, add it to every reference rate with
/// RateTableOptions::earth_rate.
#pragma once
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/calib/plateaus.hpp"
#include "cubecal/math/matrix.hpp"
#include "cubecal/math/vec3.hpp"

namespace cubecal {

/// The Earth's rotation rate Omega_E (rad/s).
inline constexpr double kEarthRateRadPerS = 7.2921159e-5;

/// Omega_E along `axis` (sensor frame) in a rate unit worth `unit_per_rad_s`
/// (180/pi for deg/s, 1 for rad/s). `axis` is the direction of the Earth's
/// rotation axis in the sensor frame, or its projection (e.g. sin(latitude)
/// times the local vertical when only the vertical component stays constant
/// as the table turns); it is not normalised.
std::array<double, 3> earth_rate_along(const std::array<double, 3>& axis, double unit_per_rad_s);

/// Options of the rate-table calibration.
struct RateTableOptions {
  /// Added to every plateau's reference rate (data unit); zero by default.
  std::array<double, 3> earth_rate{};
};

/// Size of the plateau residuals (data unit).
struct ResidualStats {
  double max_abs = 0.0;  ///< largest |residual| over all plateaus and axes, data unit
  double rms = 0.0;      ///< root mean square over all plateaus and axes, data unit
};

/// A gyro triad calibrated on a rate table (the paper's least squares): both forms of the model, their covariances and
/// the residuals.
///
/// forward_cov and inverse_cov: 12 x 12 covariances of the parameters ordered
/// per gyro output axis k = 0, 1, 2 as index 4k + m: m = 0..2 the row k of the
/// matrix (S or A), m = 3 the k-th bias (b_g or beta). This is vec Theta,
/// Theta's columns stacked.
struct RateTableCalibration {
  /// Plateaus fitted.
  std::size_t plateaus = 0;
  std::size_t dof = 0;               ///< plateaus - 4
  bool noise_from_residuals = true;  ///< false: R from the within-plateau variances (dof 0)
  Mat3 noise_cov{};                  ///< R: covariance of a plateau mean's error, data unit^2

  /// Forward model w_g = S w + b_g.
  Mat3 S{};
  std::array<double, 3> bias{};  ///< b_g, data unit
  /// 1 sigma of each entry of S.
  Mat3 S_sigma{};
  /// 1 sigma of b_g (data unit).
  std::array<double, 3> bias_sigma{};
  Matrix forward_cov;  ///< of (S, b_g), ordering above

  /// Inverse (the paper's) form w = A w_g + beta.
  Mat3 A{};
  std::array<double, 3> beta{};  ///< data unit
  /// 1 sigma of each entry of A.
  Mat3 A_sigma{};
  /// 1 sigma of beta (data unit).
  std::array<double, 3> beta_sigma{};
  Matrix inverse_cov;  ///< of (A, beta), ordering above

  /// What datasheets quote, from the forward S:
  /// scale-factor error of axis i: S_ii - 1 (x1e6 for ppm, x100 for %);
  std::array<double, 3> scale_factor_error{};
  /// 1 sigma of scale_factor_error.
  std::array<double, 3> scale_factor_error_sigma{};
  /// misalignment[i][j] (i != j, rad): the angle by which the sensitive axis
  /// of gyro axis i leans toward reference axis j, atan(S_ij / S_ii) (row i of
  /// S is that axis's sensitivity to each reference axis). Positive when a
  /// rate about +j reads positive on axis i. Not symmetric: misalignment[i][j]
  /// and misalignment[j][i] are independent (6 angles; a pure rotation of the
  /// sensor gives them opposite signs). The diagonal is zero.
  Mat3 misalignment{};
  /// 1 sigma of each misalignment angle (rad).
  Mat3 misalignment_sigma{};

  /// Plateau residuals: before calibration (identity, no bias) w_g,j - w_j;
  /// after, A w_g,j + beta - w_j (per plateau, in input order).
  ResidualStats residual_before;
  /// Residual size after calibration (data unit).
  ResidualStats residual_after;
  /// The residuals after calibration, per plateau in input order (data unit).
  std::vector<std::array<double, 3>> residuals_after;

  /// The paper's eq. 12 (docs/formulas/rate-table.md §4.2): covariance of
  /// the calibrated error A w_g + beta - w over every sample of every plateau
  /// (pooled from the plateaus' means and covariances, unbiased), data
  /// unit^2. The paper's eq. 13 is this matrix (docs/paper.md §2.6).
  Mat3 error_covariance{};
};

/// Calibrates from plateaus that carry a reference rate (has_ref). Throws
/// CalibrationError (cubecal/error.hpp): too_few_points (fewer than 4
/// plateaus); bad_data (a plateau without a reference, non-finite values or
/// no samples); degenerate (plateau rates not affinely independent in 4 ways,
/// rank [w 1] < 4, e.g. all about one axis; or a singular fitted S).
RateTableCalibration calibrate_rate_table(std::span<const Plateau> plateaus, const RateTableOptions& opt = {});

}  // namespace cubecal
