/// @file
/// TWOSTEP attitude-independent magnetometer calibration (Alonso & Shuster
/// 2002; docs/formulas/magnetometer.md §1): bias only, or bias + symmetric D.
///
/// Model: B_k = (I+D)^-1 (O^T A_k H_k + b + eps_k), eps_k ~ N(0, s^2 I);
/// scalar measurement z_k = |B_k|^2 - |H_k|^2, noise variance
/// sigma_k^2 = 4 s^2 |H_k|^2 + 6 s^4, mean mu_k = -3 s^2.
/// Step 1 is the centred linear estimate; step 2 is Fisher scoring on the
/// whole likelihood, needed for the full model when |H_k| is constant (the
/// centred problem is then singular along the common-gain direction) and
/// giving the maximum-likelihood estimate in every case. Covariance: the
/// inverse Fisher information at convergence.
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/math/matrix.hpp"

namespace cubecal::mag {

/// Options of TWOSTEP (Alonso & Shuster).
struct TwostepOptions {
  bool full = false;            ///< false: bias only (3 parameters); true: b and D (9)
  double noise = 0.0;           ///< s, per axis (input units); 0: estimate from the residuals
  bool mean_correction = true;  ///< mu_k = -3 s^2; false: mu_k = 0 (for noise-free tests)
  /// Stop when eta = dx^T F dx < eta_tol (dx the last step, F the Fisher
  /// information: the step in units of its own standard error, squared).
  double eta_tol = 1e-12;
  /// Most step-2 iterations.
  std::size_t max_iterations = 100;
};

/// A TWOSTEP solution: the bias (and D), their covariances and the fit's statistics (input units).
struct TwostepResult {
  /// True for the full model (b and D), false for bias only.
  bool full = false;
  Vec3 b{};          ///< TWOSTEP bias b (in the frame corrected by I + D)
  Mat3 D{};          ///< symmetric D (zero for bias only)
  Vec3 centred_b{};  ///< step-1 estimates
  /// The step-1 estimate of D.
  Mat3 centred_D{};
  /// theta = b (bias only) or [c; E11 E22 E33 E12 E13 E23], c = (I+D) b,
  /// E = 2D + D^2 (full).
  ///@{
  std::vector<double> theta, centred_theta;
  Matrix theta_cov;  ///< P = F^-1 at convergence
  /// Covariance of (b1 b2 b3) or (b1 b2 b3 D11 D22 D33 D12 D13 D23): P for
  /// bias only, J P J^T with J = d(b, D)/d(c, E) for the full model.
  Matrix cov;
  /// Hard-iron form h_cal = (I+D)(h - offset): offset = (I+D)^-1 b, and the
  /// covariance of (offset, W11 W22 W33 W12 W13 W23) with W = I + D (3x3 for
  /// bias only, where offset = b).
  Vec3 offset{};
  Matrix offset_cov;
  /// Smallest / largest eigenvalue of the centred information matrix: about
  /// 1e-17 for the full model when |H_k| is constant (step 1 degenerate).
  double centred_condition = 0.0;
  /// True when step 1 is degenerate (centred_condition tiny): step 2 starts from the bias-only estimate.
  bool centred_degenerate = false;
  double noise = 0.0;  ///< s used
  /// True when s was estimated from the residuals.
  bool noise_estimated = false;
  double chi2 = 0.0;              ///< sum (z_k - model_k - mu_k)^2 / sigma_k^2
  std::size_t dof = 0;            ///< N - parameters
  std::optional<double> p_value;  ///< only when the noise was given
  std::size_t iterations = 0;     ///< step-2 iterations
  double eta = 0.0;               ///< last eta
  /// False when step 2 stopped at max_iterations.
  bool converged = false;
};

/// B: measured points; H_norm: |H_k|, one value for all points (lab run) or
/// one per point. Throws CalibrationError (cubecal/error.hpp): too_few_points
/// (fewer points than parameters + 1); field_norm (H_norm neither one value
/// nor one per point, or a norm not positive); bad_option (negative noise,
/// eta_tol or max_iterations not positive); bad_data (non-finite points);
/// degenerate (all points equal, a singular information matrix, I + E
/// singular or, full, not positive definite).
TwostepResult twostep(std::span<const Vec3> B, std::span<const double> H_norm, const TwostepOptions& opt = {});

}  // namespace cubecal::mag
