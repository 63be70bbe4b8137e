// `cubecal model` as a library call: a composite noise model (WN, QN, RW,
// DR, k Gauss-Markov terms; noise/composite_model.hpp) fitted to each
// channel's Haar wavelet variance by the GMWM (noise/gmwm.hpp), with its
// terms in the units people quote and, on request, parametric-bootstrap
// uncertainties: the fitted model simulated `bootstrap` times at the
// record's length, each replicate's wavelet variance refitted from the fit.
// JSON form: model_fit_json.hpp. docs/formulas/noise-terms.md §8a-8b.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal::pipeline {

struct ModelRequest {
  std::string model;             // "WN+RW+2*GM"
  std::vector<Unit> units;       // one per channel, one for all, or none
  double ci = 0.95;              // of the wavelet variance's intervals and the bootstrap's
  std::size_t bootstrap = 0;     // replicates (0: none)
  std::uint64_t seed = 1;        // of the bootstrap
  GmwmOptions gmwm;
  unsigned threads = 0;          // 0: all cores
};

// One quantity of a fitted term: in the data unit and seconds (value) and
// as people quote it (display: noise/units.hpp); with a bootstrap, its
// standard deviation and percentile interval over the replicates.
struct ModelQuantity {
  std::string name;              // "N", "Q", "K", "R", "sigma_b", "T_c"
  double value = 0.0;
  std::string unit;              // of value: u*sqrt(s), u*s, u/sqrt(s), u/s, u, s
  Quantity display;              // display.sigma: the bootstrap's standard deviation (0 without)
  double sd = 0.0;               // bootstrap standard deviation of value (0 without)
  double lo = 0.0, hi = 0.0;     // bootstrap percentile interval of value at ci (0 without)
  double display_lo = 0.0, display_hi = 0.0;  // the interval in display.unit
};

struct ModelTerm {
  ProcessKind kind = ProcessKind::wn;
  Process process;               // per-sample parameters as fitted
  std::vector<ModelQuantity> quantities;  // WN: N; QN: Q; RW: K; DR: R; GM: sigma_b, T_c
};

struct ModelChannel {
  std::string name;
  Unit unit;
  WaveletVariance wv;            // tau in samples; tau_s = tau / rate
  GmwmFit fit;
  std::vector<ModelTerm> terms;
  std::size_t replicates = 0;    // bootstrap replicates that gave a fit
};

struct ModelResult {
  std::string file;
  double rate_hz = 0.0;
  std::size_t samples = 0;
  std::string model;             // canonical name, e.g. "WN+RW+2*GM"
  double ci = 0.95;
  std::size_t bootstrap = 0;
  std::uint64_t seed = 1;
  std::vector<ModelChannel> channels;
};

// Throws UsageError: "model" (the syntax, a model with more parameters than
// the record has scales), "units" (a count neither 1 nor one per channel),
// "bootstrap"/"ci" (out of range), "segments" (a record cut at gaps: the
// wavelet variance needs one contiguous piece); CalibrationError when no fit
// is found.
ModelResult run_model(const io::Series& series, const ModelRequest& request);

}  // namespace cubecal::pipeline
