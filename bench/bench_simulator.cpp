// Sensor simulator throughput: the batch API run() and the per-sample step()
// on the "sport-gyro" preset (white noise, random-walk bias, truncating
// quantization at 145.6 LSB/(deg/s), saturation, static sensor).
//
// items_per_second counts axis-samples (one value of one axis); the
// "triads_per_second" counter counts triads (3 axis-samples). Target: >= 30 M
// axis-samples/s on one core for run().
//
//   bench_simulator --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "cubecal/sim/presets.hpp"

namespace {

constexpr std::size_t kTriads = 1'000'000;
constexpr double kDt = 0.1;

void set_rates(benchmark::State& state, std::size_t triads_per_iteration) {
  const auto triads = static_cast<double>(state.iterations()) * static_cast<double>(triads_per_iteration);
  state.SetItemsProcessed(static_cast<std::int64_t>(3.0 * triads));
  state.counters["triads_per_second"] = benchmark::Counter(triads, benchmark::Counter::kIsRate);
}

// Batch API: 1 M triads per call, no true input, no temperature series.
void BM_RunTriad(benchmark::State& state) {
  cubecal::TriadSimulator sim(cubecal::preset("sport-gyro"), kDt, 42);
  std::vector<double> out(3 * kTriads);
  for (auto _ : state) {
    sim.run(kTriads, {}, {}, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_rates(state, kTriads);
}
BENCHMARK(BM_RunTriad)->Unit(benchmark::kMillisecond);

// Batch API with a true-input series (u = M * true) and a temperature series.
void BM_RunTriadInputTemperature(benchmark::State& state) {
  cubecal::TriadSimulator sim(cubecal::preset("sport-gyro"), kDt, 42);
  std::vector<double> in(3 * kTriads), temp(kTriads), out(3 * kTriads);
  for (std::size_t k = 0; k < kTriads; ++k) {
    in[3 * k] = 0.1;
    in[3 * k + 1] = -0.2;
    in[3 * k + 2] = 0.05;
    temp[k] = 25.0 + 1e-6 * static_cast<double>(k);
  }
  for (auto _ : state) {
    sim.run(kTriads, in, temp, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_rates(state, kTriads);
}
BENCHMARK(BM_RunTriadInputTemperature)->Unit(benchmark::kMillisecond);

// Per-sample API: one triad per call, 1 M calls per iteration.
void BM_Step(benchmark::State& state) {
  cubecal::TriadSimulator sim(cubecal::preset("sport-gyro"), kDt, 42);
  const std::array<double, 3> in{0.0, 0.0, 0.0};
  for (auto _ : state) {
    for (std::size_t k = 0; k < kTriads; ++k) {
      auto y = sim.step(in, 25.0);
      benchmark::DoNotOptimize(y);
    }
  }
  set_rates(state, kTriads);
}
BENCHMARK(BM_Step)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
