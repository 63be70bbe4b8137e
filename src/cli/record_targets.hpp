// `cubecal record --target`: the live status of a recording (the terms of
// each channel, their precision against the targets, the time still
// needed), written to DIR/status.json every --status-every of recorded time
// and at the end, summarised on the status line; with --stop-when-met, the
// run's stop flag is raised when every target holds.
//
// A status takes a while (the plan reads a model curve at each trial
// length: about 0.1-0.5 s per channel), so it is computed on a thread of
// its own from a snapshot of the curves, while the recorder goes on reading
// the source: the recording loop never waits for it (a serial line's buffer
// would overflow). A status falls due every --status-every of recorded time
// and is started at the first sample after that at which the previous one
// has finished.
#pragma once
#include <atomic>
#include <csignal>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/pipeline/record_status.hpp"

namespace cubecal::cli {

// What record's target options ask.
struct RecordTargets {
  std::vector<PlanTarget> targets;
  double ci = 0.683;
  double every_s = 120.0;  // recorded time between two statuses
  bool stop_when_met = false;
};

// RecordTargets from the flags' text; UsageError naming the flag for a bad one.
RecordTargets parse_record_targets(const std::string& target, double ci, const std::string& every, bool stop_when_met);

class TargetWatch {
 public:
  // `stop`: the recorder's stop flag, raised when every target holds (with
  // stop_when_met); `flush`: hands the recorded samples to the kernel, called
  // before each snapshot, so that a status never counts a sample a kill -9
  // would lose.
  TargetWatch(RecordTargets t, std::string out_dir, volatile std::sig_atomic_t* stop, std::function<void()> flush);
  // Waits for a status being computed.
  ~TargetWatch();
  TargetWatch(const TargetWatch&) = delete;
  TargetWatch& operator=(const TargetWatch&) = delete;

  // One sample of the recording whose manifest is `m` (its layout known).
  void on_sample(std::span<const double> values, const io::RecordingManifest& m);
  // After the run: waits for a status being computed, then writes the last
  // one, of every sample, as final.
  void finish(const io::RecordingManifest& m);

  // The status line's part: "targets 3/6 met, 1:20:00 still needed".
  std::string line() const;
  // True once the targets were met and the stop flag raised.
  bool stopped_met() const noexcept { return stopped_met_; }
  // The samples (and recorded time) of the first status at which every target held (0: never).
  std::size_t met_at_samples() const;
  double met_at_record_s() const;
  // Notices for stderr (a status that could not be written), taken once.
  std::vector<std::string> take_notices();

 private:
  void start_status(const io::RecordingManifest& m);
  void compute(pipeline::LiveNoiseStatus snapshot, int segment, bool final);

  RecordTargets t_;
  std::string dir_;
  volatile std::sig_atomic_t* stop_;
  std::function<void()> flush_;
  std::unique_ptr<pipeline::LiveNoiseStatus> live_;
  double next_s_ = 0.0;  // recorded time the next status falls due at
  bool wrote_without_period_ = false;
  bool stopped_met_ = false;
  std::future<void> running_;     // the status being computed
  std::atomic<bool> met_{false};  // a status found every target met
  mutable std::mutex m_;          // guards what follows, written by the status's thread
  std::string line_;
  std::size_t met_at_ = 0;
  double met_at_s_ = 0.0;
  bool write_failed_ = false;
  std::vector<std::string> notices_;
};

}  // namespace cubecal::cli
