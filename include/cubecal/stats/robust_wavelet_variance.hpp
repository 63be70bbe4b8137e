/// @file
/// The robust Haar wavelet variance: at each dyadic scale an M-estimator of
/// the scale of the MODWT Haar coefficients in place of their mean square
/// (Mondal & Percival, Ann. Inst. Stat. Math. 64, 2012; Guerrier, Molinari &
/// Victoria-Feser, Austrian J. Stat. 43, 2014: the robust GMWM), so that a
/// few outliers (spikes, dropped or corrupted samples) do not dominate the
/// moments the GMWM fit matches (noise/gmwm.hpp; docs/formulas/noise-terms.md
/// §8e).
///
/// At scale tau = 2m the coefficients W_t (stats/wavelet_variance.hpp) are
/// standardised by a scale s and nu2 = s^2 solves Huber's "proposal 2"
/// equation with Tukey's biweight psi_c(r) = r (1 - r^2/c^2)^2 (|r| <= c,
/// else 0):
///   (1/M) sum_t chi(W_t / s) = a(c),   chi = psi_c^2,   a(c) = E chi(Z),
/// Z standard normal: Fisher-consistent for coefficients that are Gaussian
/// about zero (white noise, quantization, random walk, Gauss-Markov terms;
/// not a deterministic drift). The constant c is chosen for an asymptotic
/// efficiency eff at the Gaussian relative to the mean of squares,
///   eff(c) = E[(Z^2 - 1) chi(Z)]^2 / (2 Var chi(Z)),
/// 0.6 by default as in the gmwm/wv packages (c = 4.4003: a coefficient
/// beyond 4.4 s is ignored). A small share e of far outliers among a
/// scale's coefficients biases the estimate low by 2 (a / slope) e = 2.0 e
/// (chi ignores them, the consistency constant does not); past about 26 %
/// (at 0.6) the equation has no root (biweight_variance). An isolated outlying
/// sample touches tau coefficients at scale tau, so a share p of outlying
/// samples is a share of about p tau of the coefficients: the protection
/// holds at the scales where p tau is small.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {

/// The biweight's tuning for an efficiency: c and the Gaussian moments of
/// chi = psi_c^2 the estimator and its variance need.
struct BiweightTuning {
  double efficiency = 0.0;  ///< at the Gaussian, relative to the mean of squares
  double c = 0.0;           ///< rejection point, in scales
  double a = 0.0;           ///< E chi(Z): the Fisher-consistency constant
  double slope = 0.0;       ///< E[(Z^2 - 1) chi(Z)] = E[Z chi'(Z)]
  double var_chi = 0.0;     ///< Var chi(Z)
};

/// Throws UsageError(Field::efficiency) for an efficiency outside (0, 1) or above
/// the 0.999998 that c <= 100 reaches (the classical estimator is the limit).
BiweightTuning biweight_tuning(double efficiency);
/// The Gaussian moments at a given c (> 0); efficiency = slope^2 / (2 var_chi).
BiweightTuning biweight_moments(double c);

/// The biweight M-estimate of the variance of zero-mean values from their
/// squares v = w^2. Newton's method on ln s^2 from the MAD scale, kept on the
/// root where the mean of chi falls with s (the one the Fisher consistency
/// picks). 0 when every v is 0. Where the equation has no root (the mean of
/// chi stays below a(c) at every s: more than about a quarter of the values
/// far out or exactly zero) the s that maximises the mean of chi, the
/// closest the equation comes (what the gmwm package's minimisation of
/// (mean chi - a)^2 returns there).
double biweight_variance(std::span<const double> v, const BiweightTuning& tuning);

/// The MODWT Haar coefficients at the scale of tau samples (even, 2 <= tau
/// <= N): W_t = (sum y[t+m .. t+2m-1] - sum y[t .. t+m-1]) / tau, m = tau/2,
/// for t = 0 .. N - tau, from compensated (Neumaier) prefix sums of the
/// mean-removed samples: each window sum is exact to a few roundings of the
/// window's values, however long the record and large its random walk or
/// drift (a plain running sum loses the digits of its own magnitude).
std::vector<double> haar_coefficients(std::span<const double> y, std::size_t tau);

/// The robust wavelet variance at the scales of wavelet_variance (same tau,
/// n; nu2 the biweight variance of the coefficients). edf = efficiency *
/// eta3: the robust estimator's variance is the classical one's times a
/// factor between 1 (strongly correlated coefficients) and 1 / efficiency
/// (uncorrelated ones), so the intervals (chi-square at that edf) and the
/// GMWM weights widen by the efficiency's cost, on the safe side. Throws as
/// wavelet_variance and UsageError(Field::efficiency) as biweight_tuning.
WaveletVariance robust_wavelet_variance(std::span<const double> y, double ci = 0.95, double efficiency = 0.6,
                                        std::size_t max_scales = 0);

}  // namespace cubecal
