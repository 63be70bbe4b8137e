// Test records: white noise plus a bias random walk, seeded.
#pragma once
#include <cstdint>
#include <random>
#include <vector>

namespace cubecal::test {

// n samples of `sigma` white noise per sample plus a bias random walk
// (increment walk * dt per step) around `bias`.
inline std::vector<double> white_plus_walk(std::size_t n, double dt, double sigma, double walk, std::uint64_t seed,
                                           double bias = 0.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double b = 0.0;
  for (auto& v : y) {
    v = bias + b + sigma * g(rng);
    b += walk * dt * g(rng);
  }
  return y;
}

}  // namespace cubecal::test
