// Progress of long work (large files, long simulations, dense tau grids) on
// stderr. On a terminal: one line rewritten in place, with the percentage
// and the time left. In a log (stderr not a terminal): nothing, unless the
// work is long enough that silence would look like a hang; then one line per
// tenth of the work. Never on stdout.
#pragma once
#include <chrono>
#include <string>

namespace cubecal::cli {

class Progress {
 public:
  // Active when stderr is a terminal and `worth_it` (e.g. a file > 50 MB),
  // or when `long_work`, terminal or not.
  explicit Progress(bool worth_it = true, bool long_work = false);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void stage(const std::string& what);  // "reading log.csv (200 MB)"
  void fraction(double f);              // 0..1 of the current stage: percent and ETA
  // Work of unknown total (a pipe): on a terminal, the count so far and its
  // rate, "12.3 M samples, 45.6 M samples/s", at most four times a second.
  void count(double done, const char* unit);
  void done();

 private:
  bool active_;
  bool terminal_;
  std::string stage_;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point stage_start_;
  std::chrono::steady_clock::time_point last_count_{};
};

// Work estimated to take longer than this many seconds is announced before
// it starts and reports its progress even into a log: 30 s, or the value of
// the environment variable CUBECAL_LONG_WORK_SECONDS.
double long_work_seconds();

// "45 s", "12 min 5 s", "3 h 20 min".
std::string format_duration(double seconds);

// Bytes of a file (of a recording directory: its chunks), 0 if unknown.
std::size_t file_size_or_zero(const std::string& path);

}  // namespace cubecal::cli
