// The segment plan of the Welch estimator: docs/formulas/spectral.md §2.1.
#include "cubecal/spectral/welch_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMinSegment = 4;  // an explicit segment length
constexpr std::size_t kMinDefaultSegment = 16;
constexpr std::size_t kDefaultSegments = 8;  // the default L is at most n / 8

std::string count_text(std::size_t n) { return std::to_string(n); }

std::string hz_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::string_view to_string(Detrend d) noexcept {
  switch (d) {
    case Detrend::none: return "none";
    case Detrend::constant: return "constant";
    case Detrend::linear: return "linear";
  }
  return "constant";
}

std::optional<Detrend> parse_detrend(std::string_view name) {
  if (name == "none") return Detrend::none;
  if (name == "constant") return Detrend::constant;
  if (name == "linear") return Detrend::linear;
  return std::nullopt;
}

WelchPlan plan_welch(const WelchOptions& o, std::size_t longest, double rate_hz) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz))
    throw UsageError(Field::rate, "the sampling rate must be a positive number of Hz");
  if (!(o.overlap >= 0.0 && o.overlap < 1.0))
    throw UsageError(Field::overlap, "the overlap is a fraction of a segment, at least 0 and below 1 (0.5 is half)");
  WelchPlan p;
  if (o.segment_length > 0) {
    if (o.segment_length < kMinSegment)
      throw UsageError(Field::segment_length, "a segment needs at least " + count_text(kMinSegment) + " samples");
    if (o.segment_length > longest)
      throw UsageError(Field::segment_length, "segments of " + count_text(o.segment_length) +
                                                  " samples are longer than the record (" + count_text(longest) +
                                                  " samples" + " contiguous)");
    p.segment_length = o.segment_length;
  } else if (o.min_frequency_hz != 0.0) {
    if (!(o.min_frequency_hz > 0.0) || !std::isfinite(o.min_frequency_hz))
      throw UsageError(Field::min_frequency, "the lowest frequency must be a positive number of Hz");
    const double need = std::ceil(std::log2(rate_hz / o.min_frequency_hz) - 1e-12);
    const double length = std::exp2(std::max(need, 2.0));
    if (length > static_cast<double>(longest))
      throw UsageError(Field::min_frequency, "resolving " + hz_text(o.min_frequency_hz) + " Hz at " + hz_text(rate_hz) +
                                                 " Hz takes segments of " +
                                                 (need < 62.0 ? std::to_string(static_cast<long long>(length))
                                                              : "2^" + std::to_string(static_cast<long long>(need))) +
                                                 " samples, longer than the record (" + count_text(longest) +
                                                 " samples contiguous)");
    p.segment_length = static_cast<std::size_t>(length);
  } else {
    if (longest < kMinDefaultSegment)
      throw UsageError(Field::samples, "a spectrum needs at least " + count_text(kMinDefaultSegment) +
                                           " contiguous samples; the record has " + count_text(longest));
    std::size_t l = kMinDefaultSegment;
    while (2 * l <= longest / kDefaultSegments) l *= 2;
    p.segment_length = l;
  }
  p.overlap = static_cast<std::size_t>(std::floor(o.overlap * static_cast<double>(p.segment_length)));
  if (p.overlap >= p.segment_length) throw UsageError(Field::overlap, "the overlap leaves no step between segments");
  p.step = p.segment_length - p.overlap;
  return p;
}

std::size_t welch_segments(std::size_t n, const WelchPlan& plan) noexcept {
  if (n < plan.segment_length || plan.step == 0) return 0;
  return (n - plan.overlap) / plan.step;
}

}  // namespace cubecal
