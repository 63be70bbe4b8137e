#include "timings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <thread>

namespace cubecal::cli {

void add_timings_option(CLI::App& cmd, Timings& t) {
  cmd.add_flag("--timings", t.enabled,
               "After the result, print on stderr the time of each stage (read, phase, kernels, noise id, "
               "intervals, fits, drift, covariance, temperature, output) and the wall clock");
}

void print_timings(const Timings& t, unsigned threads) {
  if (!t.enabled) return;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t.start).count();
  for (std::size_t k = 0; k < kStageCount; ++k) {
    const auto stage = static_cast<Stage>(k);
    const double s = t.times.seconds(stage);
    if (s <= 0.0) continue;
    const bool walled = stage == Stage::read || stage == Stage::output || stage == Stage::temperature;
    std::cerr << fmt::format("cubecal: timing: {:<12} {:8.4f} s ({})\n", to_string(stage), s,
                             walled ? "wall" : "thread-seconds");
  }
  const unsigned used = threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  std::cerr << fmt::format("cubecal: timing: {:<12} {:8.4f} s (wall, {} threads)\n", "total", wall, used);
}

}  // namespace cubecal::cli
