/// @file
/// `cubecal analyze` as a library call: static characterization of every
/// channel of a record (the paper's sections 2 and 3): fixed bias, OADEV with
/// intervals, IEEE 952 noise terms (slope read-offs and weighted fit), the
/// paper's random-walk model and a Gauss-Markov alternative, bias drift,
/// covariance, and temperature dependence; on request the spectral view
/// beside the Allan curve (the power-law fit of `cubecal psd` and the IEEE 952
/// terms it stands for).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/stage_times.hpp"
#include "cubecal/math/matrix.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_exclusions.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/noise/twin_error.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/spectral_analysis.hpp"
#include "cubecal/pipeline/twin_check.hpp"

namespace cubecal::pipeline {

/// What `cubecal analyze` is asked to do with a record (the data already read into an io::Series).
struct AnalyzeRequest {
  std::vector<Unit> units;  ///< one per channel, or one for all
  TauGrid grid;             ///< default log:10 (set by the CLI)
  /// Confidence factor of every interval (0.683: 1 sigma).
  double ci = 0.683;
  std::optional<std::size_t> temp_index;  ///< index into Series::extra of the temperature
  /// Order of the temperature polynomial (1 to 5).
  std::size_t temp_order = 1;
  /// 0: 300 s for rate sensors, 1000 s otherwise (the paper). A window
  /// given must span at least one sample and fit in the record's longest
  /// gap-free part (UsageError otherwise, naming the record length or the
  /// sample period).
  double drift_window_s = 0.0;
  std::size_t cov_samples = 0;  ///< 0: whole record
  std::size_t max_samples = 0;  ///< samples used for the model fit (0: all; paper: 42000)
  std::vector<double> lsb;      ///< quantizer of the model, counts per unit: one for all or
                                ///< one per channel (empty or 0: no quantization)
  /// Threads (0: hardware concurrency).
  unsigned threads = 0;
  /// The spectral view (`analyze --psd`): run_psd of every channel with the
  /// defaults of `cubecal psd` (Welch, the power-law fit and its IEEE 952
  /// terms), the spectrum kept averaged over kSpectrumBinsPerDecade log bands
  /// per decade (spectral_analysis.hpp). Off by default: about 0.1 s per 2.6 M-sample channel.
  /// run_analyze_stream refuses it (UsageError "psd": Welch's segments are an
  /// eighth of the record, which a stream does not hold).
  bool psd = false;
  /// The composite noise model: run_model of the same samples the sensor
  /// models are fitted on (the first max_samples when asked), with this
  /// request's model, selection_replicates, bootstrap, seed and gmwm
  /// options; its units, ci and threads are the analysis's. By default each
  /// channel's twin ("twin": noise/twin_selection.hpp, docs/twins.md), which
  /// `simulate --model analysis.json` simulates; "auto" (selected by the WIC
  /// among the default candidates), "WN+RW+2*GM", candidates joined by
  /// commas; none: nullopt.
  std::optional<ModelRequest> composite = twin_request();
  /// false (the default twin): a record that cannot carry the composite model
  /// (cut at gaps, with missing samples, too short for a fit, or streamed:
  /// the wavelet variance's largest scales span half the record, which a
  /// stream does not hold) is analysed without it, and
  /// AnalysisResult::composite_skipped says why. true: such a record is
  /// refused (UsageError "composite"), as when a model was asked for.
  bool composite_required = false;
  /// `analyze --twin-check K`: K twins of every channel simulated at the
  /// record's length and their mean curve against the measured one
  /// (pipeline/twin_check.hpp); 0: none.
  std::size_t twin_check = 0;
  /// Seed of the twin check's simulations.
  std::uint64_t twin_check_seed = 1;
  /// run_analyze_stream: called from the caller's thread after every piece
  /// with the fraction of the input read (0 while its size is not known).
  /// run_analyze does not call it.
  std::function<void(double)> progress;
  /// Where the time goes (optional; run_analyze): the deviations' stages,
  /// fits, drift, covariance and temperature.
  StageTimes* times = nullptr;
};

/// The Allan curve of a channel (or of its compensated series) and the noise terms read from it.
struct NoiseAnalysis {
  /// The OADEV curve (tau in s, deviation in the data unit) with intervals.
  std::vector<StabilityPoint> adev;
  /// The terms read off the curve.
  SlopeReadOffs readoffs;
  /// The weighted five-term fit.
  NoiseFit fit;
};

/// The sensor models fitted to a channel's Allan curve (the paper's random walk, the Gauss-Markov alternative, the
/// composite model).
struct ModelAnalysis {
  /// True when the random-walk model was fitted.
  bool ok = false;
  std::string error;                 ///< why the random-walk model could not be fitted
  std::size_t samples = 0;           ///< samples the model was fitted on
  std::vector<StabilityPoint> adev;  ///< the curve it was fitted to
  /// The paper's random-walk model (per sample, data unit).
  RandomWalkModel random_walk;
  /// Its residual on the curve.
  ModelResidual random_walk_residual;
  /// True when the Gauss-Markov model was fitted.
  bool gm_ok = false;
  std::string gm_error;  ///< why no Gauss-Markov model is reported
  /// The Gauss-Markov model (data unit, s).
  GaussMarkovModel gauss_markov;
  /// Its residual on the curve.
  ModelResidual gauss_markov_residual;
  /// AnalyzeRequest::composite: the composite model fitted to the same
  /// samples (its wavelet variance, fit, terms in quoted units and, with a
  /// bootstrap, their uncertainties); none without (and for the compensated
  /// series).
  std::optional<ModelChannel> composite;
  ModelResidual composite_residual;  ///< its Allan variance on adev, as the two models'
  TwinError twin_error;              ///< of the composite model on adev (noise/twin_error.hpp)
};

/// How the composite models were fitted (AnalyzeRequest::composite), as
/// ModelResult states it; its intervals are at AnalysisResult::ci.
struct CompositeSettings {
  std::string model;                     ///< as asked, canonical: "WN+RW+2*GM", "auto" or the candidates
  std::size_t selection_replicates = 0;  ///< of each candidate's WIC (0: one model)
  std::size_t bootstrap = 0;             ///< replicates of the terms' uncertainties (0: none)
  /// Seed of the bootstrap replicates.
  std::uint64_t seed = 1;
  bool robust = false;  ///< the robust wavelet variance, at robust_efficiency
  /// Efficiency of the robust wavelet variance (0 to 1).
  double robust_efficiency = 0.6;
};

/// Temperature dependence of a channel (docs/formulas/drift-covariance-temperature.md §3-4).
struct TemperatureAnalysis {
  /// The coefficients reported and compensated with: estimated jointly with
  /// the random-walk bias (fit_temperature_random_walk) when `joint`, else
  /// the OLS fit below.
  TemperatureFit fit;
  /// True when the coefficients were estimated jointly with the random-walk bias.
  bool joint = false;
  std::string joint_error;     ///< why the OLS fit is reported (no random-walk model fits)
  TemperatureFit ols;          ///< ordinary least squares, batch-means sandwich covariance
  RandomWalkModel noise;       ///< joint: the noise model the coefficients are weighted with
                               ///< (fitted on the whole compensated record)
  std::size_t iterations = 0;  ///< joint: noise-model fits
  /// joint: the iteration converged.
  bool converged = false;
  NoiseAnalysis compensated;  ///< noise terms of the compensated series
  /// The sensor models fitted to the compensated series, as `model` is to the
  /// record (on its first max_samples samples when asked). From an
  /// analysis.json written before it was reported: not ok, with that said in
  /// error.
  ModelAnalysis compensated_model;
};

/// The analysis of one channel.
struct ChannelAnalysis {
  /// The channel's name (header name, or "col3").
  std::string name;
  /// The channel's data unit.
  Unit unit;
  /// The fixed bias: the mean (data unit).
  double mean = 0.0;
  /// The sample standard deviation (data unit).
  double stddev = 0.0;
  /// The Allan curve and its noise terms.
  NoiseAnalysis noise;
  /// The sensor models.
  ModelAnalysis model;
  DriftSeries drift;  ///< concatenated over segments; t from the record start
  /// The temperature dependence, when a temperature column was given.
  std::optional<TemperatureAnalysis> temperature;
  /// AnalyzeRequest::psd: the spectral view of the record (spectral_analysis.hpp);
  /// none without it.
  std::optional<SpectralAnalysis> spectral;
  /// A streamed run (analyze_stream.hpp): the stride of each point of
  /// noise.adev (1: every overlapping term); empty in memory.
  std::vector<std::size_t> adev_strides;
};

/// The result of `cubecal analyze`: every channel's analysis and the channels' covariance.
struct AnalysisResult {
  /// The input's path, as given.
  std::string file;
  /// Samples per channel.
  std::size_t samples = 0;
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  /// Duration of the record (s).
  double duration_s = 0.0;
  /// Contiguous segments the record was read in.
  std::size_t segments = 1;
  io::GapPolicy gaps = io::GapPolicy::error;  ///< how the record was read: split at gaps, or refused with one
  double ci = 0.683;                          ///< confidence of every interval (AnalyzeRequest::ci)
  /// The temperature column's name; empty without.
  std::string temp_name;
  /// One per channel, in the record's order.
  std::vector<ChannelAnalysis> channels;
  /// The covariance's channel names, in its order.
  std::vector<std::string> cov_names;
  /// The covariance of the channels (channels x channels, in the data's units
  /// squared), over the first cov_samples samples.
  Matrix covariance;
  /// Samples per channel the covariance is taken over (the record's head).
  std::size_t cov_samples = 0;
  /// Listed taus (an explicit --taus list) the Allan curves leave out, with
  /// the reason, and listed taus merged on one averaging factor; and listed
  /// taus on the curves but beyond the max_samples head the model is fitted on.
  TauListOutcome tau_list;
  /// Listed taus on the curves but beyond the samples the model is fitted on.
  std::vector<ExcludedTau> model_excluded_taus;
  /// A streamed run: the window bound (0: the record was held in memory).
  std::size_t window_bound = 0;
  /// AnalyzeRequest::composite: how each channel's model.composite was fitted.
  std::optional<CompositeSettings> composite;
  /// Why no composite model was fitted although the default asked for it
  /// (AnalyzeRequest::composite_required false); empty otherwise.
  std::string composite_skipped;
  /// Why the channels have no drift series: the default drift window
  /// (AnalyzeRequest::drift_window_s 0) is longer than the record's longest
  /// gap-free part; empty otherwise. (A window given that long is refused.)
  std::string drift_skipped;
  /// AnalyzeRequest::twin_check.
  std::optional<TwinCheck> twin_check;
};

/// Analyses every channel of `series` as `request` asks, the channels on the threads. Throws UsageError for a request
/// the record cannot serve ("units", "lsb", "temp_index", "composite", "psd", the grid), and CalibrationError where the
/// temperature fit cannot be made; a sensor model that cannot be fitted is reported in the result, not thrown.
AnalysisResult run_analyze(const io::Series& series, const AnalyzeRequest& request);

}  // namespace cubecal::pipeline
