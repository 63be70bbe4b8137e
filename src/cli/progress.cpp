#include "progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace cubecal::cli {

Progress::Progress(bool worth_it)
    : active_(worth_it && ::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { done(); }

void Progress::stage(const std::string& what) {
  if (!active_) return;
  if (!stage_.empty()) std::fputc('\n', stderr);
  stage_ = what;
  last_percent_ = -1;
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "\r\033[K[%6.1f s] %s", t, what.c_str());
  std::fflush(stderr);
}

void Progress::fraction(double f) {
  if (!active_) return;
  const int pct = static_cast<int>(f * 100.0);
  if (pct == last_percent_) return;
  last_percent_ = pct;
  std::fprintf(stderr, "\r\033[K%s %3d %%", stage_.c_str(), pct);
  std::fflush(stderr);
}

void Progress::done() {
  if (!active_ || stage_.empty()) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  stage_.clear();
}

std::size_t file_size_or_zero(const std::string& path) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  return ec ? 0 : static_cast<std::size_t>(n);
}

}  // namespace cubecal::cli
