// --timings (dev, analyze): where the run's time went, stage by stage, on
// stderr after the result. bench/run.sh reads it to set each stage beside
// what this machine can do at best (bench/limits.cpp).
#pragma once
#include <chrono>

#include <CLI/CLI.hpp>

#include "cubecal/stage_times.hpp"

namespace cubecal::cli {

struct Timings {
  bool enabled = false;
  StageTimes times;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  // What the requests point at: null unless --timings.
  StageTimes* sink() { return enabled ? &times : nullptr; }
};

void add_timings_option(CLI::App& cmd, Timings& t);

// One line per stage that took time ("cubecal: timing: kernels 0.412 s
// (thread-seconds)"), then the wall clock since the command started and the
// threads. Nothing unless --timings.
void print_timings(const Timings& t, unsigned threads);

}  // namespace cubecal::cli
