/// @file
/// The Generalized Method of Wavelet Moments (Guerrier, Skaloud, Stebler,
/// Victoria-Feser, JASA 2013): the parameters of a composite noise model
/// (composite_model.hpp) that bring its theoretical Haar wavelet variance
/// closest to the empirical one (stats/wavelet_variance.hpp),
///   theta = argmin sum_j ((nu2_j - nu2_j(theta)) / s_j)^2,
/// with s_j the standard deviation of nu2_j under the chi-square law of its
/// EDF (eta3) taken at the model's value: a diagonal weight matrix, which
/// keeps the estimator consistent (the JASA paper's Proposition 1 holds for
/// any positive-definite weight), iteratively reweighted so that a point
/// that came out low is not favoured. docs/formulas/noise-terms.md §8b.
///
/// The parameters are fitted in logarithms (variances, and a = -ln phi of
/// each Gauss-Markov term), an MA1's theta as atanh(theta) and a SIN term's
/// omega as logit(omega / pi), so every one stays in its range; the Gauss-Markov terms come out ordered by correlation
/// time. Levenberg-Marquardt from several starting points read off the
/// wavelet variance (the white noise or MA1 from the first scale, with theta
/// 0.2 and then scattered over (-0.8, 0.8), the random walk and drift from
/// the last, the Gauss-Markov terms spread over the scales, a SIN term at the
/// frequency and amplitude its structure carries: a line's wavelet variance
/// is multimodal in omega, so a structure built from a spectrum's peaks
/// gives each SIN its Process::omega and value as the start); the best is
/// kept.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {

/// How the GMWM fit searches (starts, iterations, weights).
struct GmwmOptions {
  std::size_t starts = 32;           ///< starting points (the first read off the curve, the rest scattered around it)
  std::size_t max_iterations = 300;  ///< Levenberg-Marquardt steps per start
  std::size_t reweightings = 6;      ///< passes of the weights taken from the model
  std::uint64_t seed = 1;            ///< of the scattered starts
  /// A model of the same structure to start from instead (e.g. the fit a
  /// parametric bootstrap replicates): the only start tried.
  std::optional<CompositeModel> start;
  /// Models of the same structure tried as starts besides the `starts`
  /// scattered ones (a model grown from a smaller fit: the twin's search).
  std::vector<CompositeModel> warm_starts;
  /// Fixed weights instead of the reweighting: the standard deviation of
  /// each scale, kept throughout (one per scale; the WIC's common Omega,
  /// noise/wic.hpp). Empty: the reweighted fit above.
  std::vector<double> fixed_sd;
};

/// A GMWM fit of a composite model to a Haar wavelet variance.
struct GmwmFit {
  CompositeModel model;           ///< the structure asked for, with the fitted parameters
  std::vector<double> nu2_model;  ///< the model's wavelet variance at each scale of the input
  std::vector<double> sd;         ///< the weights' standard deviations at each scale
  double objective = 0.0;         ///< sum ((nu2 - nu2_model) / sd)^2
  bool converged = false;         ///< the last Levenberg-Marquardt run met a convergence test
};

/// Throws UsageError(Field::model) for a model with no process or more parameters
/// than scales (or a start of another structure, or outside the parameters'
/// ranges), and CalibrationError(degenerate) when no start gives a finite fit.
GmwmFit fit_gmwm(const WaveletVariance& wv, const CompositeModel& structure, const GmwmOptions& options = {});

}  // namespace cubecal
