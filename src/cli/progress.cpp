#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>

#include "cubecal/io/recording.hpp"
#include "cubecal/io/recording_manifest.hpp"

namespace cubecal::cli {

Progress::Progress(bool worth_it, bool long_work)
    : terminal_(::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()), stage_start_(start_) {
  active_ = (worth_it && terminal_) || long_work;
}

Progress::~Progress() { done(); }

void Progress::stage(const std::string& what) {
  if (!active_) return;
  if (terminal_ && !stage_.empty()) std::fputc('\n', stderr);
  stage_ = what;
  last_percent_ = -1;
  const auto now = std::chrono::steady_clock::now();
  stage_start_ = now;
  const double t = std::chrono::duration<double>(now - start_).count();
  if (terminal_)
    std::fprintf(stderr, "\r\033[K[%6.1f s] %s", t, what.c_str());
  else
    std::fprintf(stderr, "cubecal: %s\n", what.c_str());
  std::fflush(stderr);
}

void Progress::fraction(double f) {
  if (!active_ || stage_.empty() || !(f >= 0.0)) return;
  f = std::min(f, 1.0);
  const int pct = static_cast<int>(f * 100.0);
  // A log gets a line per tenth; a terminal every percent.
  if (pct == last_percent_ || (!terminal_ && pct / 10 == last_percent_ / 10)) return;
  last_percent_ = pct;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start_).count();
  std::string eta;
  if (f >= 0.01 && f < 1.0) eta = ", " + format_duration(elapsed * (1.0 - f) / f) + " left";
  if (terminal_)
    std::fprintf(stderr, "\r\033[K%s %3d %%%s", stage_.c_str(), pct, eta.c_str());
  else
    std::fprintf(stderr, "cubecal: %s: %d %%%s\n", stage_.c_str(), pct, eta.c_str());
  std::fflush(stderr);
}

void Progress::count(double done, const char* unit) {
  if (!active_ || !terminal_ || stage_.empty()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_count_ < std::chrono::milliseconds(250)) return;
  last_count_ = now;
  const double elapsed = std::chrono::duration<double>(now - stage_start_).count();
  const auto si = [](double v) {
    return v >= 1e9   ? fmt::format("{:.2f} G", v / 1e9)
           : v >= 1e6 ? fmt::format("{:.1f} M", v / 1e6)
                      : fmt::format("{:.0f}", v);
  };
  std::string rate;
  if (elapsed > 0.5) rate = fmt::format(", {} {}/s", si(done / elapsed), unit);
  std::fprintf(stderr, "\r\033[K%s: %s %s%s", stage_.c_str(), si(done).c_str(), unit, rate.c_str());
  std::fflush(stderr);
}

void Progress::done() {
  if (!active_ || stage_.empty()) return;
  if (terminal_) std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  stage_.clear();
}

double long_work_seconds() {
  if (const char* v = std::getenv("CUBECAL_LONG_WORK_SECONDS")) {
    char* end = nullptr;
    const double s = std::strtod(v, &end);
    if (end != v && *end == '\0' && s >= 0.0 && std::isfinite(s)) return s;
  }
  return 30.0;
}

std::string format_duration(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds)) return "an unknown time";
  if (seconds < 0.1) return "under 0.1 s";
  if (seconds < 10.0) return fmt::format("{:.1f} s", seconds);
  const auto s = static_cast<long long>(std::llround(seconds));
  if (s < 60) return fmt::format("{} s", s);
  if (s < 3600) return fmt::format("{} min {} s", s / 60, s % 60);
  return fmt::format("{} h {} min", s / 3600, (s % 3600) / 60);
}

std::size_t file_size_or_zero(const std::string& path) {
  if (io::looks_like_recording(path)) {
    // A recording directory (cubecal record): its chunks, as the manifest counts them.
    try {
      std::size_t bytes = 0;
      for (const auto& seg : io::read_manifest(path).segments)
        for (const auto& c : seg.chunks) bytes += c.bytes;
      return bytes;
    } catch (const std::exception&) {
      return 0;  // the read that follows says what is wrong with it
    }
  }
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  return ec ? 0 : static_cast<std::size_t>(n);
}

}  // namespace cubecal::cli
