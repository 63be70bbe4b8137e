#include "record_targets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <chrono>
#include <exception>
#include <utility>

#include "cubecal/error.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::cli {

namespace {

std::string hms(double s) {
  const auto t = static_cast<long long>(std::ceil(s));
  return fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60);
}

// The status line's part: how many targets hold and the longest time still
// needed (or why it is not known).
std::string summary_line(const pipeline::LiveStatus& s) {
  if (!s.why.empty()) return "targets: " + face_words(s.why);
  std::size_t met = 0, total = 0;
  double longest = 0.0;
  std::string unknown;
  for (const auto& ch : s.channels)
    for (const auto& t : ch.terms) {
      if (!t.target) continue;
      ++total;
      if (t.met) {
        ++met;
        continue;
      }
      if (std::isfinite(t.remaining_s))
        longest = std::max(longest, t.remaining_s);
      else if (unknown.empty())
        unknown = fmt::format("{} {}: {}", to_string(t.term), ch.name, t.why.empty() ? ch.why : t.why);
    }
  std::string line = fmt::format("targets {}/{} met", met, total);
  if (met == total) return line;
  if (!unknown.empty()) return line + " (" + face_words(unknown) + ")";
  return line + ", " + hms(longest) + " still needed";
}

double unix_now(std::string& iso) {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  iso = io::utc_iso8601(static_cast<std::int64_t>(ts.tv_sec), ts.tv_nsec);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

RecordTargets parse_record_targets(const std::string& target, double ci, const std::string& every, bool stop_when_met) {
  RecordTargets t;
  try {
    if (!target.empty()) t.targets = parse_plan_targets(target);
  } catch (const UsageError& e) {
    throw UsageError("--target: " + e.text());  // the plan's words name no flag
  }
  if (!(ci > 0.0 && ci < 1.0))
    throw UsageError(Field::ci,
                     fmt::format("{} is not a confidence: give one between 0 and 1 (0.683: 1 sigma; 0.95)", ci));
  t.ci = ci;
  try {
    t.every_s = pipeline::parse_duration(every);
  } catch (const UsageError&) {
    throw UsageError("--status-every '" + printable_text(every) +
                     "' is not a duration: give recorded time such as 120s, 5m or 1h");
  }
  if (t.targets.empty() && stop_when_met)
    throw UsageError("--stop-when-met stops when the targets hold: give them with --target (e.g. B:10%,K:20%)");
  t.stop_when_met = stop_when_met;
  return t;
}

TargetWatch::TargetWatch(RecordTargets t, std::string out_dir, volatile std::sig_atomic_t* stop,
                         std::function<void()> flush)
    : t_(std::move(t)),
      dir_(std::move(out_dir)),
      stop_(stop),
      flush_(std::move(flush)),
      next_s_(t_.every_s),
      line_("targets: first status after " + hms(t_.every_s) + " recorded") {}

TargetWatch::~TargetWatch() {
  if (running_.valid()) running_.wait();
}

void TargetWatch::on_sample(std::span<const double> values, const io::RecordingManifest& m) {
  if (!live_) {
    const std::optional<Unit> unit = parse_unit(m.unit.value_or("counts"));
    pipeline::LiveStatusOptions o;
    o.targets = t_.targets;
    o.ci = t_.ci;
    live_ = std::make_unique<pipeline::LiveNoiseStatus>(m.columns, m.time_column, m.rate_hz,
                                                        unit.value_or(*parse_unit("counts")), o);
  }
  live_->push(values);
  if (met_.load(std::memory_order_relaxed) && t_.stop_when_met && !stopped_met_ && stop_ != nullptr) {
    stopped_met_ = true;
    *stop_ = 1;  // the loop ends cleanly after this read
  }
  if (live_->period() <= 0.0) {
    // No time column and no rate: said once, in the file and on the line.
    if (!wrote_without_period_ && !m.time_column) {
      wrote_without_period_ = true;
      start_status(m);
    }
    return;
  }
  if (live_->record_seconds() + 1e-9 < next_s_) return;
  if (running_.valid() && running_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  next_s_ = (std::floor(live_->record_seconds() / t_.every_s + 1e-9) + 1.0) * t_.every_s;
  start_status(m);
}

// A snapshot of the curves now (the samples handed to the kernel first),
// computed and written on the status's thread.
void TargetWatch::start_status(const io::RecordingManifest& m) {
  if (running_.valid()) running_.get();
  if (flush_) flush_();  // throws WriteFailure, as the run's own flush
  const int segment = m.segments.empty() ? 0 : m.segments.back().index;
  running_ = std::async(std::launch::async,
                        [this, snapshot = *live_, segment]() mutable { compute(std::move(snapshot), segment, false); });
}

void TargetWatch::finish(const io::RecordingManifest& m) {
  if (running_.valid()) running_.get();
  if (live_) compute(*live_, m.segments.empty() ? 0 : m.segments.back().index, true);
}

std::string TargetWatch::line() const {
  const std::lock_guard<std::mutex> lock(m_);
  return line_;
}

std::size_t TargetWatch::met_at_samples() const {
  const std::lock_guard<std::mutex> lock(m_);
  return met_at_;
}

double TargetWatch::met_at_record_s() const {
  const std::lock_guard<std::mutex> lock(m_);
  return met_at_s_;
}

std::vector<std::string> TargetWatch::take_notices() {
  const std::lock_guard<std::mutex> lock(m_);
  return std::exchange(notices_, {});
}

// One status: evaluated, written, its summary for the line. Never throws: a
// failure is a notice, and the recording goes on.
void TargetWatch::compute(pipeline::LiveNoiseStatus snapshot, int segment, bool final) {
  try {
    const pipeline::LiveStatus s = snapshot.evaluate();
    if (s.all_met) met_.store(true, std::memory_order_relaxed);
    nlohmann::json j = pipeline::to_json(s);
    std::size_t met_at = 0;
    double met_at_s = 0.0;
    {
      const std::lock_guard<std::mutex> lock(m_);
      if (s.all_met && met_at_ == 0) {
        met_at_ = s.samples;
        met_at_s_ = s.record_s;
      }
      met_at = met_at_;
      met_at_s = met_at_s_;
    }
    std::string iso;
    j["written_unix_s"] = unix_now(iso);
    j["written_utc"] = iso;
    j["segment"] = segment;
    j["status_every_s"] = t_.every_s;
    j["stop_when_met"] = t_.stop_when_met;
    j["final"] = final;
    j["met_at_samples"] = met_at > 0 ? nlohmann::json(met_at) : nlohmann::json(nullptr);
    j["met_at_record_s"] = met_at > 0 ? nlohmann::json(met_at_s) : nlohmann::json(nullptr);
    pipeline::write_status_file(dir_, j);
    const std::lock_guard<std::mutex> lock(m_);
    line_ = summary_line(s);
  } catch (const std::exception& e) {
    const std::lock_guard<std::mutex> lock(m_);
    if (!write_failed_) notices_.push_back(std::string(e.what()) + " (the recording goes on without its status)");
    write_failed_ = true;
  }
}

}  // namespace cubecal::cli
