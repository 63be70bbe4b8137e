/// @file
/// `cubecal model` as a library call: a composite noise model (WN, QN, RW,
/// DR, k Gauss-Markov terms; noise/composite_model.hpp) fitted to each
/// channel's Haar wavelet variance by the GMWM (noise/gmwm.hpp), with its
/// terms in the units people quote and, on request, parametric-bootstrap
/// uncertainties: the fitted model simulated `bootstrap` times at the
/// record's length, each replicate's wavelet variance refitted from the fit.
/// JSON form: model_fit_json.hpp. docs/formulas/noise-terms.md §8a-8b.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/noise/twin_selection.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/spectral/spectral_lines.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal::pipeline {

/// What `cubecal model` is asked to do with a record (the data already read).
struct ModelRequest {
  /// "WN+RW+2*GM"; several models joined by commas, or "auto" (the default
  /// candidates, noise/wic.hpp): each channel's is selected by the WIC
  /// (pipeline/model_selection.hpp); or "twin": each channel's twin, found by
  /// the forward search of noise/twin_selection.hpp among WN/MA1, QN, RW, DR,
  /// Gauss-Markov terms and the lines of its Welch spectrum.
  std::string model;
  TwinOptions twin;  ///< of the "twin" search
  std::size_t selection_replicates =
      50;                     ///< bootstrap replicates of each candidate's WIC optimism (0: its asymptotic form)
  std::vector<Unit> units;    ///< one per channel, one for all, or none
  double ci = 0.95;           ///< of the wavelet variance's intervals and the bootstrap's
  std::size_t bootstrap = 0;  ///< replicates (0: none)
  std::uint64_t seed = 1;     ///< of the bootstrap
  /// The robust wavelet variance (stats/robust_wavelet_variance.hpp) for the
  /// channel's and every bootstrap replicate's, at this Gaussian efficiency.
  bool robust = false;
  /// Gaussian efficiency of the robust wavelet variance (0 to 1).
  double robust_efficiency = 0.6;
  /// The GMWM fit's options.
  GmwmOptions gmwm;
  unsigned threads = 0;  ///< 0: all cores
  /// Called during the bootstrap with the replicates fitted so far and their
  /// total (channels x bootstrap): first (0, total) as it starts, then with
  /// counts that increase, last (total, total). Always from the calling
  /// thread (optional; must not throw).
  std::function<void(std::size_t done, std::size_t total)> bootstrap_progress;
};

/// One quantity of a fitted term: in the data unit and seconds (value) and
/// as people quote it (display: noise/units.hpp); with a bootstrap, its
/// standard deviation and percentile interval over the replicates.
struct ModelQuantity {
  std::string name;  ///< "N", "Q", "K", "R", "sigma_b", "T_c", "theta"
  /// The value, in `unit` (data unit and seconds).
  double value = 0.0;
  std::string unit;           ///< of value: u*sqrt(s), u*s, u/sqrt(s), u/s, u, s, Hz; "" for theta
  Quantity display;           ///< display.sigma: the bootstrap's standard deviation (0 without)
  double sd = 0.0;            ///< bootstrap standard deviation of value (0 without)
  Interval interval;          ///< bootstrap percentile interval of value at ci ({0, 0} without)
  Interval display_interval;  ///< the interval in display.unit
  /// The GMWM's asymptotic (sandwich) standard deviation of value by the
  /// delta method (noise/gmwm_asymptotics.hpp; docs/formulas/noise-terms.md
  /// §8d), and in display.unit; NaN where the wavelet variance does not
  /// determine the fit's parameters (a singular A'WA).
  double asymptotic_sd = 0.0;
  /// asymptotic_sd in display.unit.
  double display_asymptotic_sd = 0.0;
};

/// One fitted term of a composite model, in per-sample and physical units.
struct ModelTerm {
  /// Which process.
  ProcessKind kind = ProcessKind::wn;
  Process process;                        ///< per-sample parameters as fitted
  std::vector<ModelQuantity> quantities;  ///< WN: N; QN: Q; RW: K; DR: R; GM: sigma_b, T_c; MA1: N, theta; SIN: A, f
};

/// One row of a channel's model selection: a candidate and its WIC.
struct ModelCandidate {
  std::string model;  ///< "WN+RW"
  /// Parameters the candidate has.
  std::size_t parameters = 0;
  /// Its WIC.
  WicScore score;
  double objective = 0.0;  ///< of its fit with the common weights (GmwmFit::objective)
};

/// The composite model of one channel: its wavelet variance, the fit, the terms, and how it was chosen.
struct ModelChannel {
  /// The channel's name.
  std::string name;
  /// The channel's data unit.
  Unit unit;
  std::string model;   ///< the fitted model's name (the selected one with several candidates)
  WaveletVariance wv;  ///< tau in samples; tau_s = tau / rate
  /// The GMWM fit of the model.
  GmwmFit fit;
  std::vector<ModelCandidate> candidates;  ///< with several candidates: ranked by WIC, the selected first
  std::vector<std::string> failed;         ///< candidates with no fit or no score, and why
  /// The fitted terms, in the model's order.
  std::vector<ModelTerm> terms;
  std::size_t replicates = 0;  ///< bootstrap replicates that gave a fit
  /// "twin": the lines of the channel's Welch spectrum (the SIN terms'
  /// starts), why none could be looked for (a record too short for a
  /// spectrum), and how close the fitted model's curve lies to the measured
  /// wavelet variance (its 95 % intervals), with whether that is nearly
  /// every scale.
  std::vector<SpectralLine> lines;
  /// Why no lines could be looked for; empty when they were.
  std::string lines_error;
  /// How close the fitted curve is to the measured one (twin only).
  std::optional<TwinFidelity> fidelity;
  /// True when it lies inside the intervals at nearly every scale.
  bool faithful = false;
};

/// The result of `cubecal model`: one composite model per channel and how they were fitted.
struct ModelResult {
  /// The input's path, as given.
  std::string file;
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  /// Samples per channel.
  std::size_t samples = 0;
  std::string model;                     ///< as asked, canonical: "WN+RW+2*GM", or the candidates "WN+RW,WN+GM"
  std::size_t selection_replicates = 0;  ///< of each candidate's WIC (0: one model, or the asymptotic optimism)
  /// Confidence of the intervals.
  double ci = 0.95;
  /// Bootstrap replicates of the terms' uncertainties (0: none).
  std::size_t bootstrap = 0;
  /// Seed of the bootstrap.
  std::uint64_t seed = 1;
  bool robust = false;  ///< the robust wavelet variance, at robust_efficiency
  /// Gaussian efficiency of the robust wavelet variance.
  double robust_efficiency = 0.6;
  /// One per channel, in the record's order.
  std::vector<ModelChannel> channels;
};

/// ModelRequest::model asks for the twin ("twin", in any case, spaces around).
bool is_twin(const std::string& model);
/// A request for each channel's twin, everything else at its default.
ModelRequest twin_request();

/// Throws UsageError: "model" (the syntax, a model with more parameters than
/// the record has scales), "units" (a count neither 1 nor one per channel),
/// "bootstrap"/"ci"/"efficiency" (out of range), "segments" (a record cut at gaps: the
/// wavelet variance needs one contiguous piece); CalibrationError when no fit
/// is found.
ModelResult run_model(const io::Series& series, const ModelRequest& request);

}  // namespace cubecal::pipeline
