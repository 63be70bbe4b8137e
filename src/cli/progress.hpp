// Progress of long work (large files, long simulations) on stderr, only when
// stderr is a terminal: scripts and CI logs get nothing.
#pragma once
#include <chrono>
#include <string>

namespace cubecal::cli {

class Progress {
 public:
  // Active when stderr is a terminal and `worth_it` (e.g. a file > 50 MB).
  explicit Progress(bool worth_it = true);
  ~Progress();
  void stage(const std::string& what);    // "reading log.csv (200 MB)"
  void fraction(double f);                // 0..1 of the current stage
  void done();

 private:
  bool active_;
  std::string stage_;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point start_;
};

// Bytes of a file, 0 if unknown.
std::size_t file_size_or_zero(const std::string& path);

}  // namespace cubecal::cli
