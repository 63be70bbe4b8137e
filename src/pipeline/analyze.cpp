#include "cubecal/pipeline/analyze.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <utility>

#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/noise/covariance.hpp"
#include "cubecal/noise/temperature_random_walk.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/pipeline/spectral_analysis.hpp"
#include "detail/analysis_parts.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

using detail::fit_models;
using detail::noise_of;
using detail::oadev_request;

namespace {

// Samples missing between the segments of a record, for the bias random walk
// of the joint temperature fit (none without a time column).
std::vector<BiasGap> bias_gaps(const io::Series& s) {
  std::vector<BiasGap> gaps;
  for (std::size_t g = 1; g < s.segments.size(); ++g) {
    BiasGap gap;
    gap.index = s.segments[g].begin;
    if (!s.time.empty() && s.segments[g - 1].end > 0)
      gap.steps =
          std::max(0.0, std::round((s.time[s.segments[g].begin] - s.time[s.segments[g - 1].end - 1]) / s.tau0) - 1.0);
    gaps.push_back(gap);
  }
  return gaps;
}

// One channel: OLS (its errors are the user's: a constant temperature, too
// few distinct values), then the joint estimate with the random walk, whose
// noise model is the paper's random-walk model fitted to the Allan curve of
// the compensated whole record (request grid); where no such model fits
// (no minimum in the curve, no random-walk arm), the OLS fit is reported
// with the reason. Then the compensated series: its noise terms, and the
// sensor models on it as on the record.
TemperatureAnalysis analyze_temperature_of(std::size_t c, const io::Series& s, const AnalyzeRequest& req,
                                           const std::string& temp_name, const std::vector<BiasGap>& gaps, double lsb,
                                           const std::optional<ModelChannel>& twin) {
  const auto& temp = s.extra.at(*req.temp_index);
  const double dt = s.tau0;
  const std::size_t first = s.segments.front().size();
  const bool head = req.max_samples > 0 && req.max_samples < first;
  TemperatureAnalysis t;
  try {
    t.ols = fit_temperature(s.channels[c], temp, req.temp_order);
  } catch (const CalibrationError& e) {
    // The temperature column cannot explain the drift: the column is what to change.
    throw UsageError(Field::temp_index, temp_name + ": " + e.text());
  } catch (const std::invalid_argument& e) {
    throw UsageError(Field::temp_index, temp_name + ": " + e.what());
  }
  const CompensatedNoiseModel noise_model = [&](std::span<const double> y) {
    const DevResult d = run_dev({s.names[c]}, {y}, s.rate_hz, s.segments, oadev_request(req));
    return fit_random_walk_model(to_allan_curve(d.channels[0].points), dt, lsb);
  };
  try {
    TemperatureRandomWalkFit j =
        fit_temperature_random_walk(s.channels[c], temp, req.temp_order, t.ols, noise_model, gaps);
    t.fit = std::move(j.fit);
    t.noise = j.noise;
    t.iterations = j.iterations;
    t.converged = j.converged;
    t.joint = true;
  } catch (const CalibrationError& e) {
    t.fit = t.ols;
    t.joint_error = std::string("no random-walk model fits the compensated series (") + face_words(e.text()) +
                    "): the least-squares fit is reported";
  } catch (const std::invalid_argument& e) {
    t.fit = t.ols;
    t.joint_error = std::string("no random-walk model fits the compensated series (") + e.what() +
                    "): the least-squares fit is reported";
  }
  std::vector<double> comp = compensate_temperature(s.channels[c], temp, t.fit);
  const DevResult cdev =
      run_dev({s.names[c]}, {std::span<const double>(comp)}, s.rate_hz, s.segments, oadev_request(req));
  t.compensated = noise_of(cdev.channels[0]);
  if (head) {
    const DevResult hd = run_dev({s.names[c]}, {std::span<const double>(comp.data(), req.max_samples)}, s.rate_hz, {},
                                 oadev_request(req));
    t.compensated_model.adev = hd.channels[0].points;
  } else {
    t.compensated_model.adev = cdev.channels[0].points;
  }
  t.compensated_model.samples = head ? req.max_samples : s.samples();
  fit_models(t.compensated_model, dt, lsb);
  if (twin && s.segments.size() == 1) {
    // The twin of the compensated series (what `simulate` adds the
    // temperature term to), on the samples the models are fitted on: the
    // record's twin refitted from its parameters (its structure kept: the
    // temperature's share lies at the longest scales).
    io::Series one;
    one.file = s.file;
    one.rate_hz = s.rate_hz;
    one.tau0 = s.tau0;
    one.names = {s.names[c]};
    comp.resize(t.compensated_model.samples);  // its last use: the series takes it
    one.channels.push_back(std::move(comp));
    one.segments = {IndexRange{0, t.compensated_model.samples}};
    ModelRequest mreq = *req.composite;
    mreq.model = twin->model;
    mreq.gmwm.start = twin->fit.model;
    mreq.bootstrap = 0;
    mreq.units = {detail::unit_of(req, c)};
    mreq.ci = req.ci;
    mreq.threads = 1;
    try {
      ModelResult m = run_model(one, mreq);
      t.compensated_model.composite = std::move(m.channels.front());
      detail::composite_residual(t.compensated_model, dt);
    } catch (const std::exception&) {
      if (req.composite_required) throw;
      // No refit: the record's own twin stands, and `simulate` takes it
      // without the temperature term (it carries the swing as noise).
    }
  }
  return t;
}

// Every channel, on the threads one each: a channel's deviations run on its
// thread (the whole grid in one task, whose factors share their passes over
// the record), and its compensated series lives only while they are
// computed, so that no more than one per thread is alive besides the
// record. Exceptions must not leave the parallel region: the first
// channel's in order is rethrown after it.
template <class LsbOf>
void analyze_temperature(AnalysisResult& r, const io::Series& s, const AnalyzeRequest& request, const LsbOf& lsb_of) {
  const StageTimer timer(request.times, Stage::temperature);
  AnalyzeRequest req = request;
  req.times = nullptr;  // the compensated series' deviations are the temperature stage's
  req.threads = 1;
  const std::size_t nch = s.channels.size();
  r.temp_name = s.extra_names.at(*req.temp_index);
  const std::vector<BiasGap> gaps = bias_gaps(s);
  const int threads = request.threads > 0 ? static_cast<int>(request.threads) : omp_get_max_threads();
  cubecal::detail::for_channels(nch, cubecal::detail::Team{threads}, [&](std::size_t c) {
    r.channels[c].temperature =
        analyze_temperature_of(c, s, req, r.temp_name, gaps, lsb_of(c), r.channels[c].model.composite);
  });
}

// The composite noise model (AnalyzeRequest::composite) must see one
// contiguous piece: the record, or the head the sensor models are fitted on.
void check_composite(const io::Series& s, const AnalyzeRequest& req) {
  if (!req.composite || !req.composite_required) return;
  if (!is_twin(req.composite->model)) (void)parse_candidate_models(req.composite->model);  // a typo fails first
  const std::size_t first = s.segments.front().size();
  const bool head = req.max_samples > 0 && req.max_samples <= first;
  if (s.segments.size() > 1 && !head)
    throw UsageError(Field::composite, s.file + ": the record is cut into " + std::to_string(s.segments.size()) +
                                           " pieces at gaps, and the composite model's wavelet variance needs one "
                                           "contiguous piece: fit it on the first " +
                                           std::to_string(first) + " samples ({max_samples}), or repair the gaps");
}

// The composite model of every channel: run_model of the samples the sensor
// models are fitted on (the record, or its first max_samples), at the
// analysis's units, confidence and threads.
void fit_composite_required(AnalysisResult& r, const io::Series& s, const AnalyzeRequest& req) {
  const StageTimer timer(req.times, Stage::fits);
  ModelRequest mreq = *req.composite;
  mreq.units.clear();
  for (const ChannelAnalysis& ch : r.channels) mreq.units.push_back(ch.unit);
  mreq.ci = req.ci;
  mreq.threads = req.threads;
  const bool head = req.max_samples > 0 && req.max_samples < s.samples();
  ModelResult m;
  try {
    if (head) {
      io::Series h;
      h.file = s.file;
      h.rate_hz = s.rate_hz;
      h.tau0 = s.tau0;
      h.names = s.names;
      for (const auto& y : s.channels)
        h.channels.emplace_back(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(req.max_samples));
      h.segments = {IndexRange{0, req.max_samples}};
      m = run_model(h, mreq);
    } else {
      m = run_model(s, mreq);
    }
  } catch (const std::invalid_argument& e) {
    // A missing sample (NaN under --gaps skip): the wavelet variance takes none.
    throw UsageError(Field::composite,
                     s.file + ": " + e.what() +
                         "; the composite model's wavelet variance needs every sample (read the record "
                         "with {gaps} split and fit a piece)");
  }
  r.composite = CompositeSettings{m.model, m.selection_replicates, m.bootstrap, m.seed, m.robust, m.robust_efficiency};
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    r.channels[c].model.composite = std::move(m.channels[c]);
    detail::composite_residual(r.channels[c].model, s.tau0);
  }
}

// The default twin: fitted where the record allows, else the analysis
// says why not (AnalyzeRequest::composite_required).
void fit_composite(AnalysisResult& r, const io::Series& s, const AnalyzeRequest& req) {
  if (req.composite_required) return fit_composite_required(r, s, req);
  const std::size_t first = s.segments.front().size();
  const bool head = req.max_samples > 0 && req.max_samples <= first;
  if (s.segments.size() > 1 && !head) {
    r.composite_skipped = "the record is cut into " + std::to_string(s.segments.size()) +
                          " pieces at gaps; the wavelet variance needs one contiguous piece";
    return;
  }
  try {
    fit_composite_required(r, s, req);
  } catch (const std::exception& e) {  // UsageError: too short, missing samples; CalibrationError: no fit
    r.composite.reset();
    for (ChannelAnalysis& ch : r.channels) {
      ch.model.composite.reset();
      ch.model.composite_residual = {};
      ch.model.twin_error = {};
    }
    r.composite_skipped = e.what();
  }
}

// Channel c of a psd run as an analysis keeps it: the log bands without
// their bin covariance (used by the fit, not kept).
SpectralAnalysis spectral_of(PsdResult& p, std::size_t c) {
  PsdChannel& ch = p.channels[c];
  SpectralAnalysis s;
  s.spectrum = std::move(ch.spectrum);
  s.spectrum.bin_covariance = {};
  s.fit = std::move(ch.fit);
  s.allan_terms = std::move(ch.allan_terms);
  s.fit_error = std::move(ch.fit_error);
  s.overlap = p.overlap;
  s.pieces = p.pieces;
  s.pieces_used = p.pieces_used;
  return s;
}

}  // namespace

namespace {

// The result's record, and its channels' names and units.
AnalysisResult analysis_of_record(const io::Series& s, const AnalyzeRequest& req) {
  const std::size_t nch = s.channels.size();
  AnalysisResult r;
  r.file = s.file;
  r.samples = s.samples();
  r.rate_hz = s.rate_hz;
  r.duration_s = static_cast<double>(r.samples) * s.tau0;
  r.segments = s.segments.size();
  r.gaps = s.gaps;
  r.ci = req.ci;

  r.channels.resize(nch);
  for (std::size_t c = 0; c < nch; ++c) {
    auto& ch = r.channels[c];
    ch.name = s.names[c];
    ch.unit = detail::unit_of(req, c);
  }
  return r;
}

// The Allan curves the sensor models are fitted on: the record's, or
// those of its first max_samples samples when asked (the paper reduced its
// 72 h record to 42000 samples to get a V-shaped curve).
void model_curves(AnalysisResult& r, const io::Series& s, const AnalyzeRequest& req, const DevResult& dev) {
  const std::size_t nch = s.channels.size();
  const double dt = s.tau0;
  const std::size_t first = s.segments.front().size();
  if (req.max_samples > 0 && req.max_samples < first) {
    std::vector<std::vector<double>> head;
    for (const auto& ch : s.channels)
      head.emplace_back(ch.begin(), ch.begin() + static_cast<std::ptrdiff_t>(req.max_samples));
    const DevResult hd = run_dev(s.names, head, s.rate_hz, oadev_request(req));
    const TauListOutcome head_list =
        tau_list_outcome(req.grid, Stat::oadev, DataType::freq, req.max_samples, dt, "the part the model is fitted on");
    for (const ExcludedTau& e : head_list.excluded) {
      const bool on_curve = std::none_of(r.tau_list.excluded.begin(), r.tau_list.excluded.end(),
                                         [&](const ExcludedTau& f) { return f.tau == e.tau; });
      if (on_curve) r.model_excluded_taus.push_back(e);
    }
    for (std::size_t c = 0; c < nch; ++c) {
      r.channels[c].model.adev = hd.channels[c].points;
      r.channels[c].model.samples = req.max_samples;
    }
  } else {
    for (std::size_t c = 0; c < nch; ++c) {
      r.channels[c].model.adev = dev.channels[c].points;
      r.channels[c].model.samples = r.samples;
    }
  }
}

// A channel's sensor models, its mean and spread, and its bias drift per
// contiguous segment (a window never spans a gap).
void fit_and_drift(ChannelAnalysis& ch, const std::vector<double>& y, const io::Series& s, const AnalyzeRequest& req,
                   double lsb) {
  const double dt = s.tau0;
  StageTimer fitting(req.times, Stage::fits);
  fit_models(ch.model, dt, lsb);
  fitting.stop();
  const StageTimer drifting(req.times, Stage::drift);
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  double ss = 0.0;
  for (double v : y) ss += (v - mean) * (v - mean);
  ch.mean = mean;
  ch.stddev = y.size() > 1 ? std::sqrt(ss / static_cast<double>(y.size() - 1)) : 0.0;

  // Drift per contiguous segment: a window never spans a gap.
  const std::size_t window = detail::drift_window(req, ch.unit, dt);
  ch.drift.window = window;
  ch.drift.mean = mean;
  for (const auto& seg : s.segments) {
    std::span<const double> part(y.data() + seg.begin, seg.size());
    const DriftSeries d = bias_drift(part, dt, window, 0, mean);
    const double t0 = s.time.empty() ? static_cast<double>(seg.begin) * dt : s.time[seg.begin] - s.time.front();
    for (std::size_t i = 0; i < d.t.size(); ++i) {
      ch.drift.t.push_back(t0 + d.t[i]);
      ch.drift.drift.push_back(d.drift[i]);
    }
  }
}

// Covariance of the selected channels (eq. 12).
void analyze_covariance(AnalysisResult& r, const io::Series& s, const AnalyzeRequest& req) {
  const StageTimer timer(req.times, Stage::covariance);
  std::vector<std::span<const double>> spans;
  for (const auto& c : s.channels) spans.emplace_back(c);
  r.cov_names = s.names;
  r.cov_samples = req.cov_samples > 0 ? std::min(req.cov_samples, r.samples) : r.samples;
  r.covariance = covariance_matrix(spans, r.cov_samples);
}

}  // namespace

AnalysisResult run_analyze(const io::Series& s, const AnalyzeRequest& req) {
  const std::size_t nch = s.channels.size();
  detail::check_channel_lists(req, nch);
  check_composite(s, req);
  auto lsb_of = [&](std::size_t c) { return detail::model_lsb(req, c); };
  AnalysisResult r = analysis_of_record(s, req);
  std::size_t longest = s.segments.empty() ? s.samples() : 0;
  for (const auto& seg : s.segments) longest = std::max(longest, seg.size());
  detail::check_drift_window(req, r, longest, s.samples(), s.tau0);

  // Allan deviations of all channels in one parallel run.
  const DevResult dev = run_dev(s, oadev_request(req));
  StageTimer reading_off(req.times, Stage::fits);  // read-offs and the 5-term fit
  for (std::size_t c = 0; c < nch; ++c) r.channels[c].noise = noise_of(dev.channels[c]);
  reading_off.stop();
  r.tau_list = dev.tau_list;

  model_curves(r, s, req, dev);
  cubecal::detail::for_channels(nch, cubecal::detail::Team{req.threads > 0 ? static_cast<int>(req.threads) : 0},
                                [&](std::size_t c) { fit_and_drift(r.channels[c], s.channels[c], s, req, lsb_of(c)); });

  if (req.composite) fit_composite(r, s, req);
  if (req.twin_check > 0) {
    const StageTimer timer(req.times, Stage::fits);
    r.twin_check = twin_check(r, req.twin_check, req.twin_check_seed, req.threads);
  }

  // The spectral view: `cubecal psd` of the record (its pieces at gaps as
  // the curves have them), the spectrum kept in log bands for the plot.
  if (req.psd) {
    PsdRequest preq;
    preq.bins_per_decade = kSpectrumBinsPerDecade;
    for (const auto& ch : r.channels) preq.units.push_back(ch.unit);
    preq.threads = req.threads;
    PsdResult p = run_psd(s, preq);
    for (std::size_t c = 0; c < nch; ++c) r.channels[c].spectral = spectral_of(p, c);
  }

  // Covariance of the selected channels (eq. 12).
  if (nch > 0) analyze_covariance(r, s, req);

  // Temperature: the coefficients jointly with the random-walk bias, then the
  // noise terms and the sensor models again on the compensated series.
  if (req.temp_index) analyze_temperature(r, s, req, lsb_of);
  return r;
}

}  // namespace cubecal::pipeline
