// Samples written to a file descriptor at their real rate (`simulate
// --realtime`): sample k leaves at t0 + k / rate on CLOCK_MONOTONIC, each
// deadline computed from t0 (no drift over hours), everything due written in
// one write(2) before the next sleep, so that a pipe's reader sees a sample
// within a millisecond or so of its time. A reader that goes away (EPIPE)
// ends the output; SIGPIPE is ignored for that.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace cubecal::cli {

class PacedOutput {
 public:
  // The clock starts at the first sample(): that sample is due then.
  PacedOutput(int fd, double rate_hz);

  // Writes `bytes` at once (e.g. a header), before any sample.
  bool write_now(std::string_view bytes);
  // Queues sample k (k = 0, 1, ... in order), first writing what is queued
  // and sleeping when k is not yet due. False once the reader is gone (then
  // nothing more is written).
  bool sample(std::size_t k, std::string_view bytes);
  // Writes what is queued. False when the reader is gone.
  bool finish();

  bool reader_gone() const noexcept { return gone_; }
  // Samples written so far (queued ones not counted).
  std::size_t written() const noexcept { return written_; }
  // The largest delay of a write after its first sample's due time, in seconds.
  double worst_lateness_s() const noexcept { return static_cast<double>(worst_late_ns_) * 1e-9; }

 private:
  bool flush();
  std::int64_t due_ns(std::size_t k) const;
  int fd_;
  double rate_hz_;
  std::int64_t t0_ns_ = 0;
  std::int64_t last_write_ns_ = 0;
  bool started_ = false;
  std::string queue_;
  std::size_t queued_ = 0;        // samples in queue_
  std::size_t first_queued_ = 0;  // index of the first of them
  std::size_t written_ = 0;
  std::int64_t worst_late_ns_ = 0;
  bool gone_ = false;
};

}  // namespace cubecal::cli
