// Writes synthetic static records for the end-to-end benchmarks.
//   make_record OUT.csv HOURS RATE_HZ CHANNELS [SEED]
//     t plus CHANNELS columns of white noise + bias random walk
//   make_record OUT.csv HOURS RATE_HZ imu [SEED]
//     t,gx,gy,gz,mx,my,mz,temp: the paper's gyro (deg/s) and magnetometer
//     (mGauss, 0.7 mGauss/degC) models under a daily temperature swing
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: make_record OUT.csv HOURS RATE_HZ CHANNELS|imu [SEED]\n");
    return 2;
  }
  const double hours = std::atof(argv[2]);
  const double rate = std::atof(argv[3]);
  const bool imu = std::strcmp(argv[4], "imu") == 0;
  const int channels = imu ? 6 : std::atoi(argv[4]);
  const std::uint64_t seed = argc > 5 ? std::strtoull(argv[5], nullptr, 10) : 1;
  const auto n = static_cast<std::size_t>(std::llround(hours * 3600.0 * rate));
  std::FILE* f = std::fopen(argv[1], "wb");
  if (!f) {
    std::perror(argv[1]);
    return 2;
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const double dt = 1.0 / rate;
  // Per channel: fixed bias, white sigma, random-walk rate, temperature coefficient.
  struct Ch {
    double bias, white, walk, tc;
  };
  std::vector<Ch> ch;
  if (imu) {
    ch = {{0.1823, 13.9e-3, 3.5e-3, 0.0}, {1.5093, 14.5e-3, 0.87e-3, 0.0}, {-1.5015, 13.0e-3, 0.66e-3, 0.0},
          {210.0, 3.0, 0.0034, 0.7},      {-95.0, 4.9, 0.0042, 0.7},       {430.0, 2.96, 0.0036, 0.7}};
    std::fprintf(f, "t,gx,gy,gz,mx,my,mz,temp\n");
  } else {
    ch.assign(static_cast<std::size_t>(channels), {0.0, 0.014, 0.001, 0.0});
    std::fprintf(f, "t");
    for (int c = 0; c < channels; ++c) std::fprintf(f, ",c%d", c + 1);
    std::fprintf(f, "\n");
  }
  std::vector<double> b(ch.size(), 0.0);
  // Enough decimals for the time stamps to resolve one sample period.
  const int time_decimals = std::max(2, static_cast<int>(std::ceil(std::log10(rate))) + 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * dt;
    const double temp = 25.0 + 5.0 * std::sin(2.0 * std::numbers::pi * t / 86400.0);
    std::fprintf(f, "%.*f", time_decimals, t);
    for (std::size_t c = 0; c < ch.size(); ++c) {
      std::fprintf(f, ",%.7g", ch[c].bias + b[c] + ch[c].white * g(rng) + ch[c].tc * (temp - 25.0));
      b[c] += ch[c].walk * dt * g(rng);
    }
    if (imu) std::fprintf(f, ",%.3f", temp);
    std::fputc('\n', f);
  }
  return std::fclose(f) == 0 ? 0 : 1;
}
