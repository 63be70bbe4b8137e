#include "cubecal/pipeline/davar_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>

#include "cubecal/error.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

namespace {

constexpr const char* kSpanHelp = "a duration (1h, 30min, 90s, 2d) or a whole number of samples (36000)";

std::optional<double> number_of(std::string_view s) {
  double v = 0.0;
  const char* b = s.data();
  const char* e = b + s.size();
  const auto [p, ec] = std::from_chars(b, e, v);
  if (b == e || ec != std::errc() || p != e || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string samples_text(std::size_t n, double rate_hz) {
  const double s = static_cast<double>(n) / rate_hz;
  char b[96];
  std::snprintf(b, sizeof b, "%zu samples (%.6g s)", n, s);
  return b;
}

std::size_t min_window(DataType type) { return type == DataType::freq ? 4 : 5; }

}  // namespace

DavarSpan parse_davar_span(const std::string& text, Field option) {
  DavarSpan span;
  span.text = text;
  std::string_view s = text;
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  static constexpr std::pair<const char*, double> kUnits[] = {
      {"min", 60.0}, {"s", 1.0}, {"m", 60.0}, {"h", 3600.0}, {"d", 86400.0}};
  for (const auto& [unit, seconds] : kUnits) {
    const std::string_view u = unit;
    if (s.size() > u.size() && s.substr(s.size() - u.size()) == u) {
      const auto v = number_of(s.substr(0, s.size() - u.size()));
      if (!v || !(*v > 0.0)) throw UsageError(option, "'" + text + "' is not " + kSpanHelp);
      span.seconds = *v * seconds;
      return span;
    }
  }
  const auto v = number_of(s);
  if (!v || !(*v >= 1.0) || *v != std::floor(*v) || *v > 1e15)
    throw UsageError(option, "'" + text + "' is not " + kSpanHelp + " (a number without a unit counts samples)");
  span.samples = static_cast<std::size_t>(*v);
  return span;
}

std::size_t span_samples(const DavarSpan& span, double rate_hz, Field option) {
  if (span.samples > 0) return span.samples;
  const double n = std::round(span.seconds * rate_hz);
  if (!(n >= 1.0))
    throw UsageError(option, span.text + " is shorter than one sample at " + std::to_string(rate_hz) + " Hz");
  if (n > 1e15) throw UsageError(option, span.text + " is longer than any record");
  return static_cast<std::size_t>(n);
}

DavarResult run_davar(const io::Series& series, const DavarRequest& request) {
  if (series.segments.size() > 1)
    throw UsageError(Field::gaps,
                     series.file + ": the record has " + std::to_string(series.segments.size() - 1) +
                         " gap(s); davar slides one window along one contiguous record: read it with {gaps} "
                         "skip (a gap of whole periods is then missing samples, left out of each window's "
                         "terms), or cut it at its gaps");
  DavarResult r;
  r.file = series.file;
  r.rate_hz = series.rate_hz;
  r.samples = series.samples();
  r.type = request.type;
  r.grid = request.grid;
  const std::size_t N = r.samples;
  if (request.window) {
    r.window = span_samples(*request.window, series.rate_hz, Field::window);
    r.window_text = request.window->text;
  } else {
    r.window = N / 10 >= min_window(request.type) ? N / 10 : N;
    r.window_text =
        (r.window == N ? "the whole record: " : "a tenth of the record: ") + samples_text(r.window, r.rate_hz);
  }
  if (request.step) {
    r.step = span_samples(*request.step, series.rate_hz, Field::step);
    r.step_text = request.step->text;
  } else {
    r.step = std::max<std::size_t>(1, r.window / 10);
    r.step_text = "a tenth of the window: " + samples_text(r.step, r.rate_hz);
  }
  r.tau_list =
      tau_list_outcome(request.grid, Stat::oadev, request.type, std::min(r.window, N), series.tau0, "a window");

  DavarOptions opt;
  opt.window = r.window;
  opt.step = r.step;
  opt.grid = request.grid;
  opt.method = request.method;
  opt.intervals = request.intervals;
  opt.skip_missing = series.gaps == io::GapPolicy::skip;  // NaN: a missing sample (--gaps skip)
  const std::size_t C = series.channels.size();
  r.channels.resize(C);
  // The first channel alone: a request the record cannot satisfy fails once,
  // before the other channels start.
  if (C > 0) r.channels[0] = {series.names[0], davar(series.channels[0], request.type, series.tau0, opt)};
  const int threads = static_cast<int>(request.threads > 0 ? request.threads
                                                           : static_cast<unsigned>(std::max(1, omp_get_max_threads())));
  cubecal::detail::for_channels(1, C, cubecal::detail::Team{threads}, [&](std::size_t c) {
    r.channels[c] = {series.names[c], davar(series.channels[c], request.type, series.tau0, opt)};
  });
  return r;
}

nlohmann::json to_json(const DavarResult& r) {
  using nlohmann::json;
  json j;
  j["command"] = "davar";
  j["statistic"] = "oadev";
  j["file"] = r.file;
  j["rate_hz"] = r.rate_hz;
  j["type"] = std::string(to_string(r.type));
  j["samples"] = r.samples;
  std::size_t missing = 0;
  for (const auto& ch : r.channels) missing += ch.matrix.missing;
  j["missing_samples"] = missing;
  const double tau0 = r.rate_hz > 0 ? 1.0 / r.rate_hz : 0.0;
  j["window"] = {{"samples", r.window}, {"seconds", static_cast<double>(r.window) * tau0}, {"asked", r.window_text}};
  j["step"] = {{"samples", r.step}, {"seconds", static_cast<double>(r.step) * tau0}, {"asked", r.step_text}};
  const DavarMatrix* first = r.channels.empty() ? nullptr : &r.channels.front().matrix;
  j["windows"] = first ? first->windows() : 0;
  j["window_points"] = first ? first->window_points : 0;
  json iv;
  iv["enabled"] = first && first->intervals;
  if (first && first->intervals) {
    iv["ci"] = first->ci;
    iv["edf"] = first->edf_method == EdfMethod::simple ? "simple" : "greenhall";
    iv["alpha"] = first->fixed_alpha ? json(*first->fixed_alpha) : json("identified per cell");
  }
  j["intervals"] = iv;
  json excluded = json::array();
  for (const auto& e : r.tau_list.excluded) excluded.push_back({{"tau", e.tau}, {"reason", e.reason}});
  j["excluded_taus"] = excluded;
  json chans = json::array();
  for (const auto& ch : r.channels) {
    const DavarMatrix& mx = ch.matrix;
    json c;
    c["name"] = ch.name;
    c["t_start"] = mx.start;
    c["t"] = mx.centre;
    c["m"] = mx.m;
    c["tau"] = mx.tau;
    c["n"] = mx.n;
    c["missing_samples"] = mx.missing;
    const std::size_t K = mx.windows();
    auto rows = [&](const auto& v) {
      json a = json::array();
      for (std::size_t t = 0; t < mx.taus(); ++t)
        a.push_back(std::vector<std::decay_t<decltype(v[0])>>(v.begin() + static_cast<std::ptrdiff_t>(t * K),
                                                              v.begin() + static_cast<std::ptrdiff_t>((t + 1) * K)));
      return a;
    };
    c["dev"] = rows(mx.dev);  // a cell without a value (no whole term): null
    if (!mx.terms.empty()) c["terms"] = rows(mx.terms);
    if (mx.intervals) {
      c["lo"] = rows(mx.lo);
      c["hi"] = rows(mx.hi);
      c["edf"] = rows(mx.edf);
      json alpha = rows(mx.alpha);
      for (std::size_t t = 0; t < mx.taus(); ++t)
        for (std::size_t k = 0; k < K; ++k)
          if (std::isnan(mx.dev[mx.cell(t, k)])) alpha[t][k] = nullptr;
      c["alpha"] = std::move(alpha);
    }
    chans.push_back(std::move(c));
  }
  j["channels"] = std::move(chans);
  return j;
}

}  // namespace cubecal::pipeline
