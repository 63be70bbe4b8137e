// Writes a synthetic static IMU record for the end-to-end benchmark:
// t plus N channels of white noise + bias random walk at the given rate.
// Usage: make_record OUT.csv HOURS RATE_HZ CHANNELS [SEED]
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: make_record OUT.csv HOURS RATE_HZ CHANNELS [SEED]\n");
    return 2;
  }
  const double hours = std::atof(argv[2]);
  const double rate = std::atof(argv[3]);
  const int channels = std::atoi(argv[4]);
  const std::uint64_t seed = argc > 5 ? std::strtoull(argv[5], nullptr, 10) : 1;
  const auto n = static_cast<std::size_t>(std::llround(hours * 3600.0 * rate));
  std::FILE* f = std::fopen(argv[1], "wb");
  if (!f) {
    std::perror(argv[1]);
    return 2;
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> bias(static_cast<std::size_t>(channels), 0.0);
  std::fprintf(f, "t");
  for (int c = 0; c < channels; ++c) std::fprintf(f, ",c%d", c + 1);
  std::fprintf(f, "\n");
  const double dt = 1.0 / rate;
  for (std::size_t i = 0; i < n; ++i) {
    std::fprintf(f, "%.2f", static_cast<double>(i) * dt);
    for (auto& b : bias) {
      std::fprintf(f, ",%.7g", 0.014 * g(rng) + b);
      b += 0.001 * dt * g(rng);
    }
    std::fputc('\n', f);
  }
  return std::fclose(f) == 0 ? 0 : 1;
}
