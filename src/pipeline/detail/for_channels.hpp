// Per-channel work of a streamed run spread over the request's threads
// (analyze_stream.cpp, dev_stream.cpp), or any per-item work with an
// exception to carry (twin_check.cpp). Not an installed header.
#pragma once
#include <cstddef>
#include <exception>
#include <vector>

namespace cubecal::pipeline::detail {

// Runs body(c) for c = 0 .. channels - 1 on `threads` threads (0: OpenMP's
// default); the first exception in channel order is rethrown on the
// caller's thread once all have run.
template <class Body>
void for_channels(std::size_t channels, unsigned threads, const Body& body) {
  std::vector<std::exception_ptr> errors(channels);
#pragma omp parallel for schedule(dynamic, 1) \
    num_threads(threads > 0 ? static_cast <int>(threads) : 0) if (channels > 1)
  for (std::size_t c = 0; c < channels; ++c) {
    try {
      body(c);
    } catch (...) {
      errors[c] = std::current_exception();
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace cubecal::pipeline::detail
