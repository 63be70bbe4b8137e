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
#include "detail/for_channels.hpp"

namespace cubecal::pipeline {

using detail::for_channels;

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

AnalysisResult run_analyze_stream(io::SampleStream& in, const AnalyzeRequest& req, std::size_t bound,
                                  const ReopenStream& reopen) {
  check_analyze_streamable(req, static_cast<bool>(reopen));
  const std::size_t nch = in.names().size();
  detail::check_channel_lists(req, nch);
  const double dt = 1.0 / in.rate_hz();
  const DevRequest dreq = detail::oadev_request(req);
  const std::vector<std::size_t> ms = averaging_factors(req.grid, std::size_t{1} << 50, dt);
  const bool temperature = req.temp_index.has_value();
  const std::size_t passes = temperature ? 2 : 1;
  const auto report = [&](const io::SampleStream& s, std::size_t pass) {
    if (!req.progress) return;
    if (s.total_bytes() == 0) return req.progress(0.0);  // a pipe: the caller counts its rows
    req.progress((static_cast<double>(pass) +
                  std::min(1.0, static_cast<double>(s.bytes_read()) / static_cast<double>(s.total_bytes()))) /
                 static_cast<double>(passes));
  };

  AnalysisResult r;
  if (req.composite)
    r.composite_skipped =
        "the wavelet variance reaches scales of half the record, which a streamed analysis does "
        "not hold (analyze the record in memory, or fit the model with cubecal model)";
  r.file = in.file();
  r.rate_hz = in.rate_hz();
  r.segments = 1;
  r.gaps = io::GapPolicy::error;
  r.ci = req.ci;
  r.window_bound = bound;
  r.channels.resize(nch);
  for (std::size_t c = 0; c < nch; ++c) {
    r.channels[c].name = in.names()[c];
    r.channels[c].unit = detail::unit_of(req, c);
  }

  // The one pass: every accumulator a piece at a time.
  std::vector<CurveStreams> curves;
  std::vector<StreamingDrift> drifts;
  std::vector<std::optional<StreamingTemperatureFit>> temps(nch);
  for (std::size_t c = 0; c < nch; ++c) {
    curves.emplace_back(ms, bound, req.max_samples);
    drifts.emplace_back(detail::drift_window(req, r.channels[c].unit, dt));
    if (temperature) temps[c].emplace(req.temp_order);
  }
  StreamingCovariance moments(nch);
  std::optional<StreamingCovariance> cov_head;
  if (req.cov_samples > 0) cov_head.emplace(nch, req.cov_samples);
  if (temperature) r.temp_name = in.extra_names().at(*req.temp_index);
  io::SampleChunk chunk;
  std::vector<std::span<const double>> spans(nch);
  while (in.next(chunk)) {
    for_channels(nch, req.threads, [&](std::size_t c) {
      const std::vector<double>& y = chunk.channels[c];
      try {
        curves[c].push(y);
      } catch (const std::invalid_argument& e) {
        throw_sample_error(in.names()[c], e);
      }
      drifts[c].add(y);
      if (temps[c]) temps[c]->add(y, chunk.extra.at(*req.temp_index));
    });
    for (std::size_t c = 0; c < nch; ++c) spans[c] = chunk.channels[c];
    moments.add(spans);
    if (cov_head) cov_head->add(spans);
    report(in, 0);
  }
  const std::size_t n = moments.count();
  r.samples = n;
  r.duration_s = static_cast<double>(n) * dt;
  if (n < 3)
    throw InputError(in.file(), 0, 0, "series too short: " + std::to_string(n) + " samples, at least 3 needed",
                     "a longer record is needed");
  r.tau_list = tau_list_outcome(req.grid, Stat::oadev, DataType::freq, n, dt, "the record");
  const bool head = req.max_samples > 0 && req.max_samples < n;
  if (head) {
    const TauListOutcome head_list =
        tau_list_outcome(req.grid, Stat::oadev, DataType::freq, req.max_samples, dt, "the part the model is fitted on");
    for (const ExcludedTau& e : head_list.excluded) {
      const bool on_curve = std::none_of(r.tau_list.excluded.begin(), r.tau_list.excluded.end(),
                                         [&](const ExcludedTau& f) { return f.tau == e.tau; });
      if (on_curve) r.model_excluded_taus.push_back(e);
    }
  }

  for_channels(nch, req.threads, [&](std::size_t c) {
    ChannelAnalysis& ch = r.channels[c];
    StreamingDeviation::Result dev = curves[c].record.finish(dt, dreq.options);
    if (dev.points.empty())
      throw UsageError("series too short for oadev: " + std::to_string(n) +
                       " samples, and no averaging factor of the tau grid fits (record longer data or choose "
                       "smaller taus)");
    ch.adev_strides = std::move(dev.strides);
    ch.noise = detail::noise_of(std::move(dev.points));
    ch.model.adev = head ? curves[c].head->finish(dt, dreq.options).points : ch.noise.adev;
    ch.model.samples = head ? req.max_samples : n;
    detail::fit_models(ch.model, dt, detail::model_lsb(req, c));
    ch.mean = moments.mean(c);
    ch.stddev = std::sqrt(moments.variance(c));
    ch.drift = drifts[c].finish(dt, ch.mean);
  });
  curves.clear();
  drifts.clear();
  r.cov_names = in.names();
  r.cov_samples = cov_head ? cov_head->count() : n;
  r.covariance = cov_head ? cov_head->matrix() : moments.matrix();
  if (!temperature) {
    if (req.progress) req.progress(1.0);
    return r;
  }

  // The coefficients by least squares, then the second pass: the
  // compensated curves (and the model's head of them).
  for (std::size_t c = 0; c < nch; ++c) {
    TemperatureAnalysis t;
    try {
      t.ols = temps[c]->finish();
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
  const std::unique_ptr<io::SampleStream> again = reopen();
  std::vector<CurveStreams> compensated;
  for (std::size_t c = 0; c < nch; ++c) compensated.emplace_back(ms, bound, req.max_samples);
  std::vector<std::vector<double>> scratch(nch);
  while (again->next(chunk)) {
    const std::vector<double>& temp = chunk.extra.at(*req.temp_index);
    for_channels(nch, req.threads, [&](std::size_t c) {
      scratch[c].resize(chunk.channels[c].size());
      compensate_temperature(chunk.channels[c], temp, r.channels[c].temperature->fit, scratch[c]);
      compensated[c].push(scratch[c]);
    });
    report(*again, 1);
  }
  if (compensated.empty() || compensated[0].record.samples() != n)
    throw InputError(in.file(), 0, 0,
                     "changed while it was analysed: the second pass read " +
                         std::to_string(compensated.empty() ? 0 : compensated[0].record.samples()) +
                         " samples, the first " + std::to_string(n),
                     "analyse a record that is not being written");
  for_channels(nch, req.threads, [&](std::size_t c) {
    TemperatureAnalysis& t = *r.channels[c].temperature;
    t.compensated = detail::noise_of(compensated[c].record.finish(dt, dreq.options).points);
    t.compensated_model.adev = head ? compensated[c].head->finish(dt, dreq.options).points : t.compensated.adev;
    t.compensated_model.samples = head ? req.max_samples : n;
    detail::fit_models(t.compensated_model, dt, detail::model_lsb(req, c));
  });
  if (req.progress) req.progress(1.0);
  return r;
}

}  // namespace cubecal::pipeline
