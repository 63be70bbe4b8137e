// OADEV kernel throughput against the memory bandwidth of this machine.
// The kernel streams x[i], x[i+m], x[i+2m] (three reads per term); the
// reference is a plain sum over the same array, the fastest any pass over
// it can be. Bytes "touched" counts every operand read (3 x 8 bytes/term)
// and also the distinct bytes (8 bytes/term), since for m << N the three
// streams mostly hit the same cache lines.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/phase.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "../src/stats/detail/difference_energy.hpp"

namespace {

constexpr std::size_t kSamples = 2'592'000;  // 72 h at 10 Hz

const std::vector<double>& phase() {
  static const std::vector<double> x = [] {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 0.014);
    std::vector<double> y(kSamples);
    for (double& v : y) v = g(rng);
    return cubecal::freq_to_phase(y, 0.1);
  }();
  return x;
}

// The fastest pass over the array: eight partial sums (two AVX2 registers),
// built the same way as the kernel so the comparison is fair.
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target_clones("avx2", "default")))
#endif
double
streaming_sum(const double* p, std::size_t n) {
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (std::size_t j = 0; j < 8; ++j) s[j] += p[i + j];
  double t = 0.0;
  for (; i < n; ++i) t += p[i];
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + t;
}

void BM_StreamingSum(benchmark::State& state) {
  const auto& x = phase();
  for (auto _ : state) benchmark::DoNotOptimize(streaming_sum(x.data(), x.size()));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * x.size() * sizeof(double)));
}
BENCHMARK(BM_StreamingSum)->Unit(benchmark::kMicrosecond);

// One averaging factor: m from 1 to 100000 (the three streams drift apart).
void BM_OadevKernel(benchmark::State& state) {
  const auto& x = phase();
  const auto m = static_cast<std::size_t>(state.range(0));
  const std::size_t count = x.size() - 2 * m;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cubecal::second_difference_energy(x.data(), count, m));
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * count * sizeof(double)));
  state.counters["operand_bytes_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * count * 3 * sizeof(double)), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_OadevKernel)->Arg(1)->Arg(100)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

// A whole channel: the log:20 grid as `cubecal dev --taus log:20`, deviations only.
void BM_OadevLog20Channel(benchmark::State& state) {
  const auto& x = phase();
  const auto ms = cubecal::averaging_factors(cubecal::parse_tau_grid("log:20"),
                                             cubecal::max_averaging_factor(cubecal::Stat::oadev, x.size()), 0.1);
  std::size_t terms = 0;
  for (auto m : ms) terms += x.size() - 2 * m;
  for (auto _ : state) {
    double acc = 0.0;
    for (auto m : ms) acc += cubecal::oavar(x, m, 0.1).var;
    benchmark::DoNotOptimize(acc);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * terms * sizeof(double)));
  state.counters["taus"] = static_cast<double>(ms.size());
}
BENCHMARK(BM_OadevLog20Channel)->Unit(benchmark::kMillisecond);

// The same grid in one call, as StabilityRecord::evaluate makes it (the
// factors walked together in tiles).
void BM_OadevLog20ChannelTiled(benchmark::State& state) {
  const auto& x = phase();
  const auto ms = cubecal::averaging_factors(cubecal::parse_tau_grid("log:20"),
                                             cubecal::max_averaging_factor(cubecal::Stat::oadev, x.size()), 0.1);
  std::size_t terms = 0;
  for (auto m : ms) terms += x.size() - 2 * m;
  std::vector<cubecal::VarianceTerm> out(ms.size());
  for (auto _ : state) {
    cubecal::oavar(x, ms, 0.1, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * terms * sizeof(double)));
  state.counters["taus"] = static_cast<double>(ms.size());
}
BENCHMARK(BM_OadevLog20ChannelTiled)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
