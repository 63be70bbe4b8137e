// The covariance of the empirical Haar wavelet variance (stats/
// wavelet_variance.hpp) of a composite noise model (composite_model.hpp):
// what the GMWM's weight matrix, its sandwich covariance (gmwm_asymptotics.hpp)
// and the WIC's optimism need (docs/formulas/noise-terms.md §8d).
//
// For a Gaussian record of N samples the estimator at scale tau_j = 2 m_j is
// nu2_j = (1 / M_j) sum_a W_{j,a}^2 over the M_j = N - tau_j + 1 MODWT Haar
// coefficients W_{j,a} = (mean x[a+m..a+2m) - mean x[a..a+m)) / 2, and
//   cov(nu2_j, nu2_k) = 2 / (M_j M_k) sum_{a,b} c_jk(b - a)^2
//                     + 4 mu_j mu_k / (M_j M_k) sum_{a,b} c_jk(b - a),
// c_jk(h) = cov(W_{j,a}, W_{k,a+h}) the cross-covariance of the coefficients
// and mu_j = omega tau_j / 4 their mean under a drift. The double sum is taken
// exactly over the overlapping pairs (a lag h occurs n_jk(h) times, a
// trapezoid): no long-record approximation, which at the last scales
// (tau ~ N / 2) would be 10-20 % off. Lags where c_jk has a kink are summed
// one by one, the Gauss-Markov tails in closed form, and the smooth pieces
// between by discrete Gauss quadrature on graded panels, exact for the
// polynomial part (WN, QN, RW) and to ~1e-12 for the exponentials.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/math/matrix.hpp"
#include "cubecal/noise/composite_model.hpp"

namespace cubecal {

// c_jk(h) = cov(W_{j,a}, W_{k,a+h}) for the scales tau_j, tau_k (samples,
// even, >= 2) of the model's random part (a drift only shifts the mean).
// The coefficients are indexed by the first sample of their window.
// Throws UsageError(Field::model) for a parameter outside its range and
// UsageError(Field::scales) for a scale that is not an even number >= 2.
double haar_coefficient_covariance(const CompositeModel& model, double tau_j, double tau_k, long long h);

// The J x J covariance of the empirical Haar wavelet variance at
// the scales tau (samples: even, >= 2, at most `samples`, any order) from a
// record of `samples` samples of the model, taken as Gaussian. Throws as
// haar_coefficient_covariance does, and UsageError(Field::scales) for a scale
// longer than the record.
Matrix wavelet_variance_covariance(const CompositeModel& model, std::span<const double> tau, std::size_t samples);

}  // namespace cubecal
