// Throughput of the delimited reader on an IMU-like CSV: a time column and
// seven values such as -0.0123457, 2.59 M rows (~210 MB; one day at 30 Hz).
// The file is generated once in the temp directory and removed at exit.
// CUBECAL_BENCH_ROWS overrides the row count for quick runs.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "cubecal/io/delimited_reader.hpp"

namespace {

namespace fs = std::filesystem;

class BenchFile {
 public:
  BenchFile() : path_(fs::temp_directory_path() / ("cubecal_bench_reader_" + std::to_string(::getpid()) + ".csv")) {
    const char* env = std::getenv("CUBECAL_BENCH_ROWS");
    const std::size_t rows = env != nullptr ? std::strtoull(env, nullptr, 10) : 2'590'000;
    std::FILE* f = std::fopen(path_.c_str(), "w");
    if (f == nullptr) std::abort();
    std::fputs("t,gx,gy,gz,ax,ay,az,temp\n", f);
    std::mt19937_64 rng(42);
    std::normal_distribution<double> noise(0.0, 0.02);
    for (std::size_t i = 0; i < rows; ++i) {
      std::fprintf(f, "%.2f", static_cast<double>(i) / 100.0);
      for (int c = 0; c < 7; ++c) std::fprintf(f, ",%.7f", noise(rng));
      std::fputc('\n', f);
    }
    std::fclose(f);
  }
  BenchFile(const BenchFile&) = delete;
  BenchFile& operator=(const BenchFile&) = delete;
  ~BenchFile() { fs::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

const BenchFile& bench_file() {
  static const BenchFile file;
  return file;
}

void run(benchmark::State& state, cubecal::io::TableOptions opt) {
  opt.threads = static_cast<unsigned>(state.range(0));
  const std::string path = bench_file().path();  // generated before timing starts
  std::size_t bytes = 0;
  std::size_t rows = 0;
  for (auto _ : state) {
    const cubecal::io::Table t = cubecal::io::read_table(path, opt);
    bytes += t.bytes;
    rows = t.rows();
    benchmark::DoNotOptimize(t.data.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
  state.counters["rows"] = static_cast<double>(rows);
}

// Threads: 0 = hardware concurrency.
void BM_ReadAllColumns(benchmark::State& state) { run(state, {}); }

// Unselected fields are only skipped: the cost of a selection.
void BM_ReadTwoColumns(benchmark::State& state) {
  cubecal::io::TableOptions opt;
  opt.columns = {"gx", "gy"};
  run(state, opt);
}

BENCHMARK(BM_ReadAllColumns)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ReadTwoColumns)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
