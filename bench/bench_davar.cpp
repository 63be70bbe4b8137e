// The dynamic Allan deviation of issue 15, item 2: one 72 h x 10 Hz channel,
// 1 h windows every 60 s (4261 windows), log:10 taus (37 factors up to the
// OADEV limit of a window, m = 9000). The fast method (block sums slid along
// the record) against the direct one (the OADEV kernel on every window), and
// the fast method with intervals, for a fixed noise type and for one
// identified in every cell. Target: the fast matrix in under 2 s.
//
//   bench_davar --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Each repetition is one call (Iterations(1)); min, median and max are over
// the repetitions. The direct run also reports the largest relative
// difference of its matrix from the fast one (max_rel_diff).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "cubecal/stats/davar.hpp"
#include "min_max.hpp"

namespace {

constexpr std::size_t kSamples = 2'592'000;  // 72 h at 10 Hz
constexpr double kTau0 = 0.1;

// A gyro-like channel: white rate noise and a slow rate random walk.
const std::vector<double>& record() {
  static const std::vector<double> y = [] {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> v(kSamples);
    double b = 0.0;
    for (double& s : v) {
      s = 0.014 * g(rng) + b;
      b += 2e-5 * g(rng);
    }
    return v;
  }();
  return y;
}

cubecal::DavarOptions options(cubecal::DavarMethod method) {
  cubecal::DavarOptions o;
  o.window = 36'000;  // 1 h
  o.step = 600;       // 60 s
  o.grid = cubecal::parse_tau_grid("log:10");
  o.method = method;
  return o;
}

void set_counters(benchmark::State& state, const cubecal::DavarMatrix& r) {
  state.counters["windows"] = static_cast<double>(r.windows());
  state.counters["taus"] = static_cast<double>(r.taus());
}

void BM_DavarFast(benchmark::State& state) {
  const auto& y = record();
  const auto o = options(cubecal::DavarMethod::fast);
  cubecal::DavarMatrix r;
  for (auto _ : state) {
    r = cubecal::davar(y, cubecal::DataType::freq, kTau0, o);
    benchmark::DoNotOptimize(r.dev.data());
  }
  set_counters(state, r);
}

void BM_DavarFastIntervalsFixedAlpha(benchmark::State& state) {
  const auto& y = record();
  auto o = options(cubecal::DavarMethod::fast);
  o.intervals.enabled = true;
  o.intervals.alpha = 0;
  cubecal::DavarMatrix r;
  for (auto _ : state) {
    r = cubecal::davar(y, cubecal::DataType::freq, kTau0, o);
    benchmark::DoNotOptimize(r.hi.data());
  }
  set_counters(state, r);
}

void BM_DavarFastIntervalsIdentified(benchmark::State& state) {
  const auto& y = record();
  auto o = options(cubecal::DavarMethod::fast);
  o.intervals.enabled = true;
  cubecal::DavarMatrix r;
  for (auto _ : state) {
    r = cubecal::davar(y, cubecal::DataType::freq, kTau0, o);
    benchmark::DoNotOptimize(r.hi.data());
  }
  set_counters(state, r);
}

void BM_DavarDirect(benchmark::State& state) {
  const auto& y = record();
  const auto o = options(cubecal::DavarMethod::direct);
  cubecal::DavarMatrix r;
  for (auto _ : state) {
    r = cubecal::davar(y, cubecal::DataType::freq, kTau0, o);
    benchmark::DoNotOptimize(r.dev.data());
  }
  set_counters(state, r);
  // Outside the timing: how far the fast matrix is from this one.
  const auto fast = cubecal::davar(y, cubecal::DataType::freq, kTau0, options(cubecal::DavarMethod::fast));
  double worst = 0.0;
  for (std::size_t i = 0; i < r.dev.size(); ++i)
    worst = std::max(worst, std::abs(fast.dev[i] - r.dev[i]) / std::abs(r.dev[i]));
  state.counters["max_rel_diff"] = worst;
}

#define DAVAR_BENCH(fn) \
  BENCHMARK(fn)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime()->Apply(cubecal::bench::with_min_max)

DAVAR_BENCH(BM_DavarFast);
DAVAR_BENCH(BM_DavarFastIntervalsFixedAlpha);
DAVAR_BENCH(BM_DavarFastIntervalsIdentified);
DAVAR_BENCH(BM_DavarDirect);

}  // namespace

BENCHMARK_MAIN();
