// The GMWM's speed (issue 16, item 5): one record of WN + 2 GM + RW of
// 1e6 samples (the process of docs/performance.md: white-noise variance 1,
// Gauss-Markov T_c 40 and 4000 samples with sigma_b 0.3 and 0.15, random-walk
// innovation variance 1e-8; simulate_composite(model, 1000000, 1)).
//   BM_GmwmFit        the Haar wavelet variance and the fit (32 starts): target < 2 s
//   BM_GmwmBootstrap  pipeline::run_model with 200 parametric-bootstrap
//                     replicates on all cores (the fit, then each replicate
//                     simulated, its wavelet variance taken and refitted):
//                     target < 30 s
//
//   bench_gmwm --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Each repetition is one call (Iterations(1)), timed on the wall clock;
// min, median and max are over the repetitions. The bootstrap's CPU column
// is the process's (all threads): on a busy machine, CPU / cores is what the
// wall time would be on idle cores.
#include <benchmark/benchmark.h>

#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/wavelet_variance.hpp"
#include "min_max.hpp"

namespace {

constexpr std::size_t kSamples = 1'000'000;

cubecal::CompositeModel truth() {
  cubecal::CompositeModel m = cubecal::parse_composite_model("WN+2*GM+RW");
  m.processes[0].value = 1.0;
  m.processes[1] = cubecal::gm_process(40.0, 0.3, 1.0);
  m.processes[2] = cubecal::gm_process(4000.0, 0.15, 1.0);
  m.processes[3].value = 1e-8;
  return m;
}

const std::vector<double>& record() {
  static const std::vector<double> y = cubecal::simulate_composite(truth(), kSamples, 1);
  return y;
}

void BM_GmwmFit(benchmark::State& state) {
  const auto& y = record();
  const cubecal::CompositeModel structure = cubecal::parse_composite_model("WN+2*GM+RW");
  double objective = 0.0;
  for (auto _ : state) {
    const cubecal::WaveletVariance wv = cubecal::wavelet_variance(y);
    const cubecal::GmwmFit fit = cubecal::fit_gmwm(wv, structure);
    objective = fit.objective;
    benchmark::DoNotOptimize(fit.model.processes.data());
  }
  state.counters["objective"] = objective;
  state.counters["samples"] = static_cast<double>(kSamples);
}
BENCHMARK(BM_GmwmFit)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Apply(cubecal::bench::with_min_max);

void BM_GmwmBootstrap(benchmark::State& state) {
  cubecal::io::Series s;
  s.file = "simulated";
  s.rate_hz = 1.0;
  s.tau0 = 1.0;
  s.names = {"y"};
  s.channels = {record()};
  s.segments = {cubecal::IndexRange{0, kSamples}};
  cubecal::pipeline::ModelRequest req;
  req.model = "WN+2*GM+RW";
  req.bootstrap = static_cast<std::size_t>(state.range(0));
  std::size_t replicates = 0;
  for (auto _ : state) {
    const cubecal::pipeline::ModelResult r = cubecal::pipeline::run_model(s, req);
    replicates = r.channels.at(0).replicates;
    benchmark::DoNotOptimize(r.channels.data());
  }
  state.counters["replicates"] = static_cast<double>(replicates);
}
BENCHMARK(BM_GmwmBootstrap)
    ->Arg(200)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Apply(cubecal::bench::with_min_max);

}  // namespace

BENCHMARK_MAIN();
