#include "cubecal/pipeline/analyze_stream.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/noise/streaming_covariance.hpp"
#include "cubecal/noise/streaming_drift.hpp"
#include "cubecal/noise/streaming_temperature.hpp"
#include "cubecal/stats/streaming_deviation.hpp"
#include "detail/analysis_parts.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

using cubecal::detail::for_channels;

namespace {

// One channel's curves as a stream builds them: the record's and, when
// the model is fitted on a head, the head's.
struct CurveStreams {
  StreamingDeviation record;
  std::optional<StreamingDeviation> head;
  std::size_t head_samples = 0;

  CurveStreams(std::span<const std::size_t> ms, std::size_t bound, std::size_t max_samples)
      : record(Stat::oadev, ms, bound), head_samples(max_samples) {
    if (max_samples > 0) head.emplace(Stat::oadev, ms, bound);
  }
  void push(std::span<const double> y) {
    record.push(y);
    if (head && head->samples() < head_samples) head->push(y.first(std::min(y.size(), head_samples - head->samples())));
  }
};

// A non-finite sample, said as the in-memory dev does.
[[noreturn]] void throw_sample_error(const std::string& column, const std::invalid_argument& e) {
  throw UsageError("column " + column + ": " + e.what() + " (remove or repair it before the analysis)");
}

}  // namespace

void check_analyze_streamable(const AnalyzeRequest& req, bool can_reopen) {
  if (req.psd)
    throw UsageError(Field::psd,
                     "the spectral view needs the whole record in memory (Welch's segments are an eighth of it), "
                     "which a streamed analysis does not hold: analyze the record in memory, with a larger memory "
                     "budget if it is above it");
  if (req.composite && req.composite_required)
    throw UsageError(Field::composite,
                     "the composite model's wavelet variance reaches scales of half the record, which a streamed "
                     "analysis does not hold: analyze the record in memory (with a larger memory budget if it is "
                     "above it), or fit the model with cubecal model");
  if (req.temp_index && !can_reopen)
    throw UsageError(Field::temp_index,
                     "a streamed temperature analysis reads the record twice (the compensated curves need the "
                     "coefficients first), and the standard input can be read only once: give the record as a file");
}

namespace {

// A streamed analysis: one pass over the record with every accumulator a
// piece at a time, and with a temperature a second pass for the
// compensated curves.
class StreamedAnalysis {
 public:
  StreamedAnalysis(io::SampleStream& in, const AnalyzeRequest& req, std::size_t bound)
      : in_(in),
        req_(req),
        bound_(bound),
        nch_(in.names().size()),
        dt_(1.0 / in.rate_hz()),
        dreq_(detail::oadev_request(req)),
        ms_(averaging_factors(req.grid, std::size_t{1} << 50, dt_)),
        temperature_(req.temp_index.has_value()),
        passes_(temperature_ ? 2 : 1),
        temps_(nch_),
        moments_(nch_) {}

  AnalysisResult run(const ReopenStream& reopen) {
    start_result();
    first_pass();
    finish_record();
    if (!temperature_) {
      if (req_.progress) req_.progress(1.0);
      return std::move(r_);
    }
    temperature_coefficients();
    compensated_pass(reopen);
    if (req_.progress) req_.progress(1.0);
    return std::move(r_);
  }

 private:
  void report(const io::SampleStream& s, std::size_t pass) const {
    if (!req_.progress) return;
    if (s.total_bytes() == 0) return req_.progress(0.0);  // a pipe: the caller counts its rows
    req_.progress((static_cast<double>(pass) +
                   std::min(1.0, static_cast<double>(s.bytes_read()) / static_cast<double>(s.total_bytes()))) /
                  static_cast<double>(passes_));
  }

  // The result's record and channels, and the accumulators of the first pass.
  void start_result() {
    AnalysisResult& r = r_;
    const std::size_t nch = nch_;
    const AnalyzeRequest& req = req_;
    if (req.composite)
      r.composite_skipped =
          "the wavelet variance reaches scales of half the record, which a streamed analysis does "
          "not hold (analyze the record in memory, or fit the model with cubecal model)";
    r.file = in_.file();
    r.rate_hz = in_.rate_hz();
    r.segments = 1;
    r.gaps = io::GapPolicy::error;
    r.ci = req.ci;
    r.window_bound = bound_;
    r.channels.resize(nch);
    for (std::size_t c = 0; c < nch; ++c) {
      r.channels[c].name = in_.names()[c];
      r.channels[c].unit = detail::unit_of(req, c);
    }
    for (std::size_t c = 0; c < nch; ++c) {
      curves_.emplace_back(ms_, bound_, req.max_samples);
      drifts_.emplace_back(detail::drift_window(req, r.channels[c].unit, dt_));
      if (temperature_) temps_[c].emplace(req.temp_order);
    }
    if (req.cov_samples > 0) cov_head_.emplace(nch, req.cov_samples);
    if (temperature_) r.temp_name = in_.extra_names().at(*req.temp_index);
  }

  // The one pass: every accumulator a piece at a time.
  void first_pass() {
    io::SampleChunk chunk;
    std::vector<std::span<const double>> spans(nch_);
    while (in_.next(chunk)) {
      for_channels(nch_, req_.threads, [&](std::size_t c) {
        const std::vector<double>& y = chunk.channels[c];
        try {
          curves_[c].push(y);
        } catch (const std::invalid_argument& e) {
          throw_sample_error(in_.names()[c], e);
        }
        drifts_[c].add(y);
        if (temps_[c]) temps_[c]->add(y, chunk.extra.at(*req_.temp_index));
      });
      for (std::size_t c = 0; c < nch_; ++c) spans[c] = chunk.channels[c];
      moments_.add(spans);
      if (cov_head_) cov_head_->add(spans);
      report(in_, 0);
    }
  }

  // The record's curves, sensor models, moments, drift and covariance.
  void finish_record() {
    AnalysisResult& r = r_;
    const AnalyzeRequest& req = req_;
    const double dt = dt_;
    const std::size_t n = moments_.count();
    n_ = n;
    r.samples = n;
    r.duration_s = static_cast<double>(n) * dt;
    if (n < 3)
      throw InputError(in_.file(), 0, 0, "series too short: " + std::to_string(n) + " samples, at least 3 needed",
                       "a longer record is needed");
    r.tau_list = tau_list_outcome(req.grid, Stat::oadev, DataType::freq, n, dt, "the record");
    detail::check_drift_window(req, r, n, n, dt);
    head_ = req.max_samples > 0 && req.max_samples < n;
    const bool head = head_;
    if (head) {
      const TauListOutcome head_list = tau_list_outcome(req.grid, Stat::oadev, DataType::freq, req.max_samples, dt,
                                                        "the part the model is fitted on");
      for (const ExcludedTau& e : head_list.excluded) {
        const bool on_curve = std::none_of(r.tau_list.excluded.begin(), r.tau_list.excluded.end(),
                                           [&](const ExcludedTau& f) { return f.tau == e.tau; });
        if (on_curve) r.model_excluded_taus.push_back(e);
      }
    }

    for_channels(nch_, req.threads, [&](std::size_t c) {
      ChannelAnalysis& ch = r.channels[c];
      StreamingDeviation::Result dev = curves_[c].record.finish(dt, dreq_.options);
      if (dev.points.empty())
        throw UsageError("series too short for oadev: " + std::to_string(n) +
                         " samples, and no averaging factor of the tau grid fits (record longer data or choose "
                         "smaller taus)");
      ch.adev_strides = std::move(dev.strides);
      ch.noise = detail::noise_of(std::move(dev.points));
      ch.model.adev = head ? curves_[c].head->finish(dt, dreq_.options).points : ch.noise.adev;
      ch.model.samples = head ? req.max_samples : n;
      detail::fit_models(ch.model, dt, detail::model_lsb(req, c));
      ch.mean = moments_.mean(c);
      ch.stddev = std::sqrt(moments_.variance(c));
      ch.drift = drifts_[c].finish(dt, ch.mean);
    });
    curves_.clear();
    drifts_.clear();
    r.cov_names = in_.names();
    r.cov_samples = cov_head_ ? cov_head_->count() : n;
    r.covariance = cov_head_ ? cov_head_->matrix() : moments_.matrix();
  }

  // The coefficients by least squares.
  void temperature_coefficients() {
    AnalysisResult& r = r_;
    for (std::size_t c = 0; c < nch_; ++c) {
      TemperatureAnalysis t;
      try {
        t.ols = temps_[c]->finish();
      } catch (const CalibrationError& e) {
        throw UsageError(Field::temp_index, r.temp_name + ": " + e.text());
      } catch (const std::invalid_argument& e) {
        throw UsageError(Field::temp_index, r.temp_name + ": " + e.what());
      }
      t.fit = t.ols;
      t.joint_error = face_words(
          "the joint estimate with the bias random walk refits the noise model on the whole compensated record at "
          "every iteration and is not streamed: the least-squares fit is reported (leave out {stream} for it)");
      r.channels[c].temperature = std::move(t);
    }
  }

  // The second pass: the compensated curves (and the model's head of them).
  void compensated_pass(const ReopenStream& reopen) {
    AnalysisResult& r = r_;
    const AnalyzeRequest& req = req_;
    const double dt = dt_;
    const std::size_t n = n_;
    const bool head = head_;
    io::SampleChunk chunk;
    const std::unique_ptr<io::SampleStream> again = reopen();
    std::vector<CurveStreams> compensated;
    for (std::size_t c = 0; c < nch_; ++c) compensated.emplace_back(ms_, bound_, req.max_samples);
    std::vector<std::vector<double>> scratch(nch_);
    while (again->next(chunk)) {
      const std::vector<double>& temp = chunk.extra.at(*req.temp_index);
      for_channels(nch_, req.threads, [&](std::size_t c) {
        scratch[c].resize(chunk.channels[c].size());
        compensate_temperature(chunk.channels[c], temp, r.channels[c].temperature->fit, scratch[c]);
        compensated[c].push(scratch[c]);
      });
      report(*again, 1);
    }
    if (compensated.empty() || compensated[0].record.samples() != n)
      throw InputError(in_.file(), 0, 0,
                       "changed while it was analysed: the second pass read " +
                           std::to_string(compensated.empty() ? 0 : compensated[0].record.samples()) +
                           " samples, the first " + std::to_string(n),
                       "analyse a record that is not being written");
    for_channels(nch_, req.threads, [&](std::size_t c) {
      TemperatureAnalysis& t = *r.channels[c].temperature;
      t.compensated = detail::noise_of(compensated[c].record.finish(dt, dreq_.options).points);
      t.compensated_model.adev = head ? compensated[c].head->finish(dt, dreq_.options).points : t.compensated.adev;
      t.compensated_model.samples = head ? req.max_samples : n;
      detail::fit_models(t.compensated_model, dt, detail::model_lsb(req, c));
    });
  }

  io::SampleStream& in_;
  const AnalyzeRequest& req_;
  const std::size_t bound_;
  const std::size_t nch_;
  const double dt_;
  const DevRequest dreq_;
  const std::vector<std::size_t> ms_;
  const bool temperature_;
  const std::size_t passes_;
  AnalysisResult r_;
  std::vector<CurveStreams> curves_;
  std::vector<StreamingDrift> drifts_;
  std::vector<std::optional<StreamingTemperatureFit>> temps_;
  StreamingCovariance moments_;
  std::optional<StreamingCovariance> cov_head_;
  std::size_t n_ = 0;
  bool head_ = false;
};

}  // namespace

AnalysisResult run_analyze_stream(io::SampleStream& in, const AnalyzeRequest& req, std::size_t bound,
                                  const ReopenStream& reopen) {
  check_analyze_streamable(req, static_cast<bool>(reopen));
  detail::check_channel_lists(req, in.names().size());
  return StreamedAnalysis(in, req, bound).run(reopen);
}

}  // namespace cubecal::pipeline
