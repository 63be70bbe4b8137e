// Per-channel (or per-item) work spread over threads, with the exception
// of any item carried back to the caller's thread: the pipelines' OpenMP
// loops (analyze, analyze_stream, dev, davar, psd, model, twin_check, ...)
// and io's reader threads. Not an installed header.
#pragma once
#include <cstddef>
#include <exception>
#include <vector>

namespace cubecal::detail {

// The exceptions of n items of work, kept by item: run(k, body) calls
// body(k) and keeps what it throws; rethrow_first() rethrows the first in
// item order once all have run.
class ItemErrors {
 public:
  explicit ItemErrors(std::size_t n) : errors_(n) {}

  template <class Body>
  void run(std::size_t k, const Body& body) noexcept {
    try {
      body(k);
    } catch (...) {
      errors_[k] = std::current_exception();
    }
  }

  void rethrow_first() const {
    for (const auto& e : errors_)
      if (e) std::rethrow_exception(e);
  }

 private:
  std::vector<std::exception_ptr> errors_;
};

// The OpenMP team of a loop: its num_threads (0: OpenMP's default) and its
// if clause (false: the loop runs on the caller's thread alone).
struct Team {
  int threads = 0;
  bool parallel = true;
};

// Runs body(k) for k = first .. n - 1, schedule(dynamic, 1), on the team;
// the first exception in item order is rethrown on the caller's thread
// once all have run.
template <class Body>
void for_channels(std::size_t first, std::size_t n, Team team, const Body& body) {
  ItemErrors errors(n);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(team.threads) if (team.parallel)
#else
  (void)team;  // a layer built without OpenMP (io) runs the items in order
#endif
  for (std::size_t k = first; k < n; ++k) errors.run(k, body);
  errors.rethrow_first();
}

template <class Body>
void for_channels(std::size_t n, Team team, const Body& body) {
  for_channels(0, n, team, body);
}

// Runs body(c) for c = 0 .. channels - 1 on `threads` threads (0: OpenMP's
// default), in parallel when there is more than one channel.
template <class Body>
void for_channels(std::size_t channels, unsigned threads, const Body& body) {
  for_channels(channels, Team{threads > 0 ? static_cast<int>(threads) : 0, channels > 1}, body);
}

}  // namespace cubecal::detail
