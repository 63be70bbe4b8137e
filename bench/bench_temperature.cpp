// The least-squares passes of `analyze --temp-col` on one channel of the
// paper's record length (72 h x 10 Hz = 2.592 M samples): the OLS fit, one
// GLS fit with the random-walk noise model (the joint estimate runs two) and
// one compensation into a buffer that already exists (the stage forms
// three). Beside the stage's three compensated Allan curves, these are what
// a channel's temperature stage costs (docs/performance.md, the budget of
// the analyze target).
//
//   bench_temperature --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "cubecal/noise/temperature.hpp"
#include "cubecal/noise/temperature_random_walk.hpp"
#include "min_max.hpp"

namespace {

constexpr std::size_t kSamples = 2'592'000;
constexpr double kDt = 0.1;

// A gyro channel: white noise, a random-walk bias and 0.01 deg/s per degC of
// a daily temperature cycle of +-10 degC (read to 0.01 degC).
struct Record {
  std::vector<double> y, temp;
};

const Record& record() {
  static const Record r = [] {
    Record out;
    out.y.resize(kSamples);
    out.temp.resize(kSamples);
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g(0.0, 1.0);
    double walk = 0.0;
    for (std::size_t i = 0; i < kSamples; ++i) {
      const double t = static_cast<double>(i) * kDt;
      out.temp[i] = std::round(100.0 * (25.0 + 10.0 * std::sin(2.0 * std::numbers::pi * t / 86400.0))) / 100.0;
      walk += 1e-4 * g(rng);
      out.y[i] = 0.01 * out.temp[i] + walk + 0.05 * g(rng);
    }
    return out;
  }();
  return r;
}

cubecal::RandomWalkModel noise_model() {
  cubecal::RandomWalkModel m;
  m.dt = kDt;
  m.sigma_n = 0.05;
  m.sigma_mu = 1e-3;
  return m;
}

void set_rate(benchmark::State& state) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(kSamples));
}

void BM_FitTemperatureOls(benchmark::State& state) {
  const Record& r = record();
  for (auto _ : state) {
    const cubecal::TemperatureFit f = cubecal::fit_temperature(r.y, r.temp, 1);
    benchmark::DoNotOptimize(f.coeff.data());
  }
  set_rate(state);
}

void BM_FitTemperatureGls(benchmark::State& state) {
  const Record& r = record();
  const cubecal::RandomWalkModel m = noise_model();
  for (auto _ : state) {
    const cubecal::TemperatureFit f = cubecal::fit_temperature_gls(r.y, r.temp, 1, m);
    benchmark::DoNotOptimize(f.coeff.data());
  }
  set_rate(state);
}

void BM_CompensateTemperature(benchmark::State& state) {
  const Record& r = record();
  const cubecal::TemperatureFit f = cubecal::fit_temperature(r.y, r.temp, 1);
  std::vector<double> out(kSamples);
  for (auto _ : state) {
    cubecal::compensate_temperature(r.y, r.temp, f, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  set_rate(state);
}

#define TEMPERATURE_BENCH(fn) \
  BENCHMARK(fn)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime()->Apply(cubecal::bench::with_min_max)

TEMPERATURE_BENCH(BM_FitTemperatureOls);
TEMPERATURE_BENCH(BM_FitTemperatureGls);
TEMPERATURE_BENCH(BM_CompensateTemperature);

}  // namespace

BENCHMARK_MAIN();
