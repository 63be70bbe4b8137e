// The C++ side of bench/python_speed.py: the work cubecal.oadev does for
// Python (a StabilityRecord of the channel, then its deviations at the given
// averaging factors, no intervals, one thread), called from C++ on the same
// samples, so that the Python call's overhead is the difference.
//
//   bench_deviation_call SAMPLES.f64 FACTORS.txt RATE_HZ RUNS
//
// SAMPLES.f64: native float64 frequency samples; FACTORS.txt: one factor per
// line. Prints "min median max" seconds of RUNS calls.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <vector>

#include "cubecal/stats/stability.hpp"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: bench_deviation_call SAMPLES.f64 FACTORS.txt RATE_HZ RUNS\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary | std::ios::ate);
  if (!in) {
    std::fprintf(stderr, "bench_deviation_call: cannot read %s\n", argv[1]);
    return 2;
  }
  std::vector<double> y(static_cast<std::size_t>(in.tellg()) / sizeof(double));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(y.data()), static_cast<std::streamsize>(y.size() * sizeof(double)));
  std::vector<std::size_t> ms;
  std::ifstream f(argv[2]);
  for (std::size_t m = 0; f >> m;) ms.push_back(m);
  const double rate = std::atof(argv[3]);
  const int runs = std::atoi(argv[4]);
  if (y.empty() || ms.empty() || !(rate > 0.0) || runs < 1) {
    std::fprintf(stderr, "bench_deviation_call: empty samples or factors, or a bad rate or run count\n");
    return 2;
  }
  cubecal::StabilityOptions opt;
  opt.intervals = false;
  std::vector<double> seconds;
  double sink = 0.0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const cubecal::StabilityRecord record(y, cubecal::DataType::freq, 1.0 / rate, cubecal::Stat::oadev);
    const auto points = record.evaluate(ms, opt);
    const auto t1 = std::chrono::steady_clock::now();
    sink += points.back().dev;
    seconds.push_back(std::chrono::duration<double>(t1 - t0).count());
  }
  std::sort(seconds.begin(), seconds.end());
  std::printf("%.6f %.6f %.6f\n", seconds.front(), seconds[seconds.size() / 2], seconds.back());
  return sink > 0.0 ? 0 : 1;
}
