// `cubecal record --target`: the live status of a recording (the terms of
// each channel, their precision against the targets, the time still
// needed), written to DIR/status.json every --status-every of recorded time
// and at the end, summarised on the status line; with --stop-when-met, the
// run's stop flag is raised when every target holds.
#pragma once
#include <csignal>
#include <functional>
#include <memory>
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
  // before each status is written, so that a status never counts a sample a
  // kill -9 would lose.
  TargetWatch(RecordTargets t, std::string out_dir, volatile std::sig_atomic_t* stop, std::function<void()> flush);

  // One sample of the recording whose manifest is `m` (its layout known).
  void on_sample(std::span<const double> values, const io::RecordingManifest& m);
  // The last status, evaluated again on every sample, written as final.
  void finish(const io::RecordingManifest& m);

  // The status line's part: "targets 3/6 met, 1:20:00 still needed".
  const std::string& line() const noexcept { return line_; }
  // True once the targets were met and the stop flag raised.
  bool stopped_met() const noexcept { return stopped_met_; }
  // The samples of the status at which every target held (0: never).
  std::size_t met_at_samples() const noexcept { return met_at_; }
  double met_at_record_s() const noexcept { return met_at_s_; }
  // Notices for stderr (a status that could not be written), taken once.
  std::vector<std::string> take_notices();

 private:
  void update(const io::RecordingManifest& m, bool final);

  RecordTargets t_;
  std::string dir_;
  volatile std::sig_atomic_t* stop_;
  std::function<void()> flush_;
  std::unique_ptr<pipeline::LiveNoiseStatus> live_;
  double next_s_ = 0.0;
  bool wrote_without_period_ = false;
  std::string line_;
  bool stopped_met_ = false;
  std::size_t met_at_ = 0;
  double met_at_s_ = 0.0;
  bool write_failed_ = false;
  std::vector<std::string> notices_;
};

}  // namespace cubecal::cli
