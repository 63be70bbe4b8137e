// The min and max of a benchmark's repetitions beside Google Benchmark's
// mean, median and stddev: the project reports min/median/max of several
// runs (docs/performance.md), since a noisy machine shows in the spread.
#pragma once
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

namespace cubecal::bench {

inline double min_of(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
inline double max_of(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

// "min" and "max" among b's aggregates: BENCHMARK(fn)->...->Apply(with_min_max).
inline void with_min_max(benchmark::internal::Benchmark* b) {
  b->ComputeStatistics("min", min_of)->ComputeStatistics("max", max_of);
}

}  // namespace cubecal::bench
