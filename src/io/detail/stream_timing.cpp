#include "stream_timing.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "cubecal/error.hpp"
#include "cubecal/stats/sampling.hpp"
#include "shortest_text.hpp"

namespace cubecal::io::detail {

namespace {

const auto& stamp = shortest_text;

void check_increasing(const std::vector<double>& t, std::size_t first, bool have_last, double last,
                      const PlaceError& at) {
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double prev = i > 0 ? t[i - 1] : last;
    if ((i == 0 && !have_last) || t[i] > prev) continue;
    throw at(first + i, "time stamp " + stamp(t[i]) + " s is not after the previous one " + stamp(prev) + " s",
             t[i] == prev ? "duplicated time stamp: remove the repeated row or fix the logger clock"
                          : "sort the file or fix the logger clock");
  }
}

}  // namespace

void StreamTiming::start(const std::vector<double>& head, const PlaceError& at) {
  rate_hz_ = opt_.rate_hz;
  if (!timing_) {
    // A rate given beside stamps must be theirs (check_rate_agrees).
    if (!opt_.check_rate_against_time || opt_.rate_hz <= 0.0 || head.size() < 2) return;
    const double period = median_interval(head);
    if (!(period > 0.0) || !std::isfinite(period) || std::fabs(opt_.rate_hz * period - 1.0) <= opt_.tolerance) return;
    throw UsageError(Field::rate, file_ + ": the rate " + period_text(opt_.rate_hz) +
                                      " Hz contradicts the time column '" + time_name_ + "' (" +
                                      period_text(1.0 / period) + " Hz, median interval " + period_text(period) +
                                      " s): leave the rate out to take it from the time stamps, "
                                      "or fix the time column");
  }
  check_increasing(head, 0, false, 0.0, at);
  if (opt_.rate_hz > 0.0) return;
  if (head.size() < 2)
    throw InputError(file_, 0, 0, "cannot infer the sampling rate from a single time stamp", "give {rate} HZ");
  const double raw = 1.0 / median_interval(head);
  if (!(raw >= kMinRateHz && raw <= kMaxRateHz))
    throw at(1,
             "time stamps " + stamp(1.0 / raw) + " s apart give a rate of " + stamp(raw) + " Hz, outside the range " +
                 stamp(kMinRateHz) + " to " + stamp(kMaxRateHz) + " Hz",
             "the time column must be in seconds");
  const double scale = std::pow(10.0, 8.0 - std::floor(std::log10(raw)));
  rate_hz_ = std::round(raw * scale) / scale;
  from_time_ = true;
}

void StreamTiming::check(const std::vector<double>& t, std::size_t first, const PlaceError& at) {
  if (t.empty()) return;
  if (!timing_) {  // the rate given: stamps may repeat (coarse clocks) but not go back, as read_series
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double prev = i > 0 ? t[i - 1] : last_;
      if ((i > 0 || have_last_) && t[i] < prev)
        throw at(first + i, "time stamp " + stamp(t[i]) + " s is before the previous one " + stamp(prev) + " s",
                 "sort the file or fix the logger clock");
    }
    last_ = t.back();
    have_last_ = true;
    return;
  }
  check_increasing(t, first, have_last_, last_, at);
  const double period = 1.0 / rate_hz_;
  const std::string ignore = opt_.time_col.empty() ? ", or give {rate} HZ to ignore the time stamps" : "";
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double prev = i > 0 ? t[i - 1] : last_;
    if (i == 0 && !have_last_) continue;
    const double dt = t[i] - prev;
    if (std::fabs(dt - period) <= opt_.tolerance * period) continue;
    if (dt >= kGapPeriods * period)
      throw at(first + i,
               "gap of " + duration_text(dt) + " s (" + std::to_string(std::llround(dt / period)) + " periods of " +
                   period_text(period) + " s) after t = " + stamp(prev) + " s",
               "a streamed record is not split: cut it at the gap, or read it into memory with {gaps} split");
    throw at(first + i,
             "jitter: interval " + duration_text(dt) + " s differs from the period " + period_text(period) + " s by " +
                 number_text(100.0 * std::fabs(dt - period) / period, std::chars_format::general, 3) + " %",
             "cut the record at irregular intervals, or read it into memory with {gaps} split" + ignore);
  }
  last_ = t.back();
  have_last_ = true;
}

}  // namespace cubecal::io::detail
