/// @file
/// The paper's sensor noise model (eq. 1-3, 14-16: docs/paper.md §2.2;
/// docs/formulas/noise-terms.md §4) and the bounded
/// alternative its conclusion asks for, fitted to a measured Allan curve.
///
/// Random-walk model: w_k = true + beta + b_k + sigma_n * n_k, with
/// b_{k+1} = b_k + sigma_mu * dt * n'_k (Euler step of db/dt = mu), then
/// quantized: int(w * lsb) / lsb. Its Allan variance at tau = m dt is exact:
///   sigma^2 = (sigma_n^2 + q^2) dt / tau ... white part, q^2 = 1/(12 lsb^2) when quantized
///           + sigma_mu^2 dt^2 * dt (2 m^2 + 1) / (6 m)  ... discrete random walk
/// (continuous limit sigma_n^2 dt / tau + sigma_mu^2 dt tau / 3).
///
/// Gauss-Markov model: b_{k+1} = phi b_k + w_k, phi = exp(-dt/T), stationary
/// sigma_b; exact discrete AVAR (docs/formulas/noise-terms.md §5.2) plus the
/// same white part.
#pragma once
#include <cstddef>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/stats/allan_curve.hpp"

namespace cubecal {

/// The paper's model: white noise plus a random-walk bias (and quantization).
struct RandomWalkModel {
  double sigma_n = 0.0;   ///< white noise per sample, u
  double sigma_mu = 0.0;  ///< bias random-walk rate, u/s (increment sigma_mu * dt per step)
  double dt = 0.0;        ///< sample period, s
  double lsb = 0.0;       ///< counts per unit; 0: no quantization
};

/// White noise plus a first-order Gauss-Markov bias (and quantization).
struct GaussMarkovModel {
  double sigma_n = 0.0;  ///< white noise per sample, u
  double sigma_b = 0.0;  ///< stationary bias standard deviation, u
  double tau_c = 0.0;    ///< correlation time T_c, s
  /// Sample period, s.
  double dt = 0.0;
  /// Counts per unit; 0: no quantization.
  double lsb = 0.0;
};

/// Exact discrete Allan variance of the models at averaging factor m.
double avar(const RandomWalkModel& model, std::size_t m) noexcept;
/// The Gauss-Markov model's exact discrete Allan variance at averaging factor m (u^2). Throws nothing.
double avar(const GaussMarkovModel& model, std::size_t m) noexcept;
/// A composite noise model's (composite_model.hpp, per-sample parameters),
/// and one of its processes' share of it: twice the Haar wavelet variance at
/// the scale tau = 2m, exact for the sampled processes (NaN for m = 0 or a
/// parameter outside its range).
double avar(const CompositeModel& model, std::size_t m) noexcept;
/// One process's share (u^2 per sample). NaN for m = 0 or a parameter outside its range; throws nothing.
double avar(const Process& process, std::size_t m) noexcept;

/// The paper's adjustment (docs/paper.md §2.4; docs/formulas/noise-terms.md
/// §4.5): the model's Allan curve tangent to the measured
/// white-noise arm and with the same minimum. `curve` is the measured OADEV
/// (tau in s); `dt` the sample period; `lsb` > 0 removes the quantization
/// share from sigma_n. Throws CalibrationError (cubecal/error.hpp): bad_data
/// (curve arrays of different lengths, taus or deviations not positive and
/// finite, taus not ascending); too_few_points (fewer than 3 points);
/// bad_option (dt not positive, lsb negative, or a white noise below the
/// quantization noise of lsb); degenerate (no minimum inside the tau range,
/// no white-noise arm, no random-walk arm).
RandomWalkModel fit_random_walk_model(const AllanCurve& curve, double dt, double lsb = 0.0);

/// Weighted least squares of the Gauss-Markov model (white + first-order GM)
/// to the measured curve: sigma_n, sigma_b, T_c. Throws CalibrationError:
/// bad_data, too_few_points (fewer than 3 points), bad_option (dt, lsb).
GaussMarkovModel fit_gauss_markov_model(const AllanCurve& curve, double dt, double lsb = 0.0);

/// How well a model reproduces the curve: RMS over the curve's points of
/// log(model dev / measured dev), and the weighted chi-squared in variance.
struct ModelResidual {
  /// RMS over the curve's points of log(model dev / measured dev).
  double rms_log = 0.0;
  /// Weighted chi-squared in variance (weights from the points' EDF).
  double chi2 = 0.0;
};
/// Throws CalibrationError (bad_data, bad_option) for a curve or a model
/// period the fits would reject.
ModelResidual residual(const RandomWalkModel& model, const AllanCurve& curve);
/// The Gauss-Markov model's residual on the curve. Throws CalibrationError (bad_data, bad_option) as for the
/// random-walk model.
ModelResidual residual(const GaussMarkovModel& model, const AllanCurve& curve);
/// A composite model's, its parameters per sample of period dt.
ModelResidual residual(const CompositeModel& model, double dt, const AllanCurve& curve);

}  // namespace cubecal
