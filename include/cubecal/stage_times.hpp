/// @file
/// Where a run's time goes, stage by stage, for `--timings` and `make bench`
/// (bench/limits.md relates each stage to what this machine can do at best).
/// A stage's time is summed over the threads that worked on it
/// (thread-seconds); the callers that time a stage around a parallel region
/// or outside any (the reading of a file, the temperature analysis, the
/// output) time its wall clock. Adding is
/// thread-safe; a null StageTimes* makes every StageTimer a no-op, which is
/// what every request holds unless asked.
#pragma once
#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <string_view>

namespace cubecal {

/// The stages of an analysis whose time is measured.
enum class Stage : std::size_t {
  read,         ///< the file to columns of doubles (wall)
  phase,        ///< the phase records the kernels run on
  kernels,      ///< the variance sums at every averaging factor
  noise_id,     ///< the power-law noise type per factor
  intervals,    ///< EDF and confidence interval per factor
  fits,         ///< slope read-offs, noise terms and the sensor models
  drift,        ///< bias drift (moving average), mean and standard deviation
  covariance,   ///< the covariance matrix of the channels
  temperature,  ///< temperature fit and the compensated series' analysis, its deviations included (wall)
  output,       ///< formatting and writing the result (wall)
};
/// The number of stages.
inline constexpr std::size_t kStageCount = 10;

/// The stage's name as --timings prints it ("noise id"). Throws nothing.
constexpr std::string_view to_string(Stage s) noexcept {
  constexpr std::array<std::string_view, kStageCount> names = {
      "read", "phase", "kernels", "noise id", "intervals", "fits", "drift", "covariance", "temperature", "output"};
  return names[static_cast<std::size_t>(s)];
}

/// Seconds per stage, added from any thread.
class StageTimes {
 public:
  /// Adds `seconds` (s) to stage `s`; thread-safe. Throws nothing.
  void add(Stage s, double seconds) noexcept { t_[static_cast<std::size_t>(s)].fetch_add(seconds); }
  /// The seconds (s) added to stage `s` so far. Throws nothing.
  double seconds(Stage s) const noexcept { return t_[static_cast<std::size_t>(s)].load(); }

 private:
  std::array<std::atomic<double>, kStageCount> t_{};
};

/// Adds the time from its construction to stop() (or its end) to a stage.
class StageTimer {
 public:
  /// Starts timing `stage` into `times` (null: a no-op timer). Throws nothing.
  StageTimer(StageTimes* times, Stage stage) noexcept : times_(times), stage_(stage) {
    if (times_ != nullptr) start_ = std::chrono::steady_clock::now();
  }
  ~StageTimer() { stop(); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  /// Adds the time since construction to the stage, once; later calls do nothing. Throws nothing.
  void stop() noexcept {
    if (times_ == nullptr) return;
    times_->add(stage_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
    times_ = nullptr;
  }

 private:
  StageTimes* times_;
  Stage stage_;
  std::chrono::steady_clock::time_point start_{};
};

}  // namespace cubecal
