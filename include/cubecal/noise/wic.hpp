/// @file
/// Model selection for composite noise models: the Wavelet Information
/// Criterion (WIC) of the GMWM literature (Guerrier, Stebler, Skaloud,
/// Victoria-Feser; the gmwm package's rank_models), the prediction form of
/// Efron's covariance penalty (JASA 2004) on the wavelet-variance loss:
///   WIC = L + 2 tr(Omega cov(nu2_hat, nu2(theta_hat))),
///   L   = (nu2_hat - nu2(theta_hat))' Omega (nu2_hat - nu2(theta_hat)),
/// an estimate of the loss a fitted model makes on a new record of the same
/// process. Omega is the same for every candidate (diagonal, the chi-square
/// variance of each scale at a reference curve, wic_weights) and every
/// candidate is fitted with it fixed, so the losses compare and each is the
/// minimum its model reaches.
/// The optimism (the second term) is estimated by a parametric bootstrap
/// from each candidate's fit (each replicate simulated at the record's
/// length, its wavelet variance refitted from the fit); it grows with the
/// parameters that the curve can bend, which a count of parameters does not
/// see (a Gauss-Markov term at the end of the scales is nearly a random walk).
/// The selection itself, with the replicates on the threads, is
/// pipeline/model_selection.hpp. docs/formulas/noise-terms.md §8c.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {

/// A candidate's Wavelet Information Criterion and its two parts (dimensionless: the weighted loss).
struct WicScore {
  double loss = 0.0;           ///< L with the common Omega
  double optimism = 0.0;       ///< 2 tr(Omega cov(nu2_hat, nu2(theta_hat)))
  double wic = 0.0;            ///< loss + optimism
  std::size_t replicates = 0;  ///< bootstrap replicates that gave a fit
};

/// One candidate model of a WIC selection: its structure, fit and score.
struct CandidateFit {
  CompositeModel structure;  ///< as asked (parameters zero)
  /// Its GMWM fit with the common weights.
  GmwmFit fit;
  /// Its WIC.
  WicScore score;
};

/// The candidates a user gets without naming any: white noise with one or
/// more of quantization, random walk and one or two Gauss-Markov terms, the
/// processes a MEMS gyro or accelerometer record shows.
std::vector<CompositeModel> default_candidate_models();

/// "auto" -> default_candidate_models(); "WN+RW, WN+GM,WN+2*GM+RW" -> those
/// (a comma between models). Throws UsageError(Field::model) as
/// parse_composite_model does, and for the same model named twice.
std::vector<CompositeModel> parse_candidate_models(const std::string& text);

/// One replicate of a candidate's optimism: the fitted model simulated at
/// the record's length, its wavelet variance at the record's scales,
/// refitted from the fit (wic_replicate, sim/wic_replicate.hpp). Empty
/// vectors when the replicate gives no fit (it is left out and counted).
struct WicReplicate {
  std::vector<double> nu2;    ///< the replicate's empirical wavelet variance
  std::vector<double> model;  ///< the model's, refitted to it
};

/// The common weights: the chi-square standard deviation of each scale at a
/// reference curve (the fit of the largest candidate), s_j = ref_j
/// sqrt(2 / eta3_j), Omega = diag(1 / s_j^2). A reference, not the empirical
/// values: a scale with one or two degrees of freedom that came out low
/// would otherwise weigh without bound.
std::vector<double> wic_weights(const WaveletVariance& wv, const std::vector<double>& reference);

/// The score of a fit (made with GmwmOptions::fixed_sd = sd) from its
/// replicates (those with a fit). Throws UsageError(Field::model) for fewer than 2.
WicScore wic_score(const WaveletVariance& wv, const std::vector<double>& sd, const GmwmFit& fit,
                   const std::vector<WicReplicate>& replicates);

/// The same score with the optimism in its asymptotic form,
/// 2 tr(Omega V P'): V the covariance of the wavelet variance at the fitted
/// model, P the fit's hat matrix (gmwm_asymptotics.hpp). No simulation: what
/// `analyze` uses; the bootstrap also sees the fit's nonlinearity. Throws as
/// gmwm_asymptotics does (CalibrationError for a parameter the wavelet
/// variance does not determine). `inflation` scales V: 1 / efficiency for
/// the robust wavelet variance (the upper bound of its variance ratio).
/// pseudo_inverse: a fit with a parameter the curve does not determine is
/// scored on the directions it does (gmwm_asymptotics), not refused.
WicScore wic_score_asymptotic(const WaveletVariance& wv, const std::vector<double>& sd, const GmwmFit& fit,
                              std::size_t samples, double inflation = 1.0, bool pseudo_inverse = false);

/// Ranks candidates by WIC and puts the selected one first: the one with the
/// fewest parameters among those within 2 of the lowest WIC (Burnham &
/// Anderson's band of models the data support as well; a Gauss-Markov term
/// with a correlation time beyond the record is a random walk the WIC cannot
/// tell apart), ties by WIC. Returns nothing; the order is the result.
void rank_by_wic(std::vector<CandidateFit>& candidates);

}  // namespace cubecal
