// Emits N float64le samples of one channel to standard output: a block of
// 2^22 samples of white noise plus a bias random walk, generated once and
// written again and again (the walk carried over, so the record has no
// jumps at the seams). For measuring `cubecal dev - --stream` without the
// simulator's cost: emit_raw N | cubecal dev - --binary float64le --rate R --stream.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: emit_raw SAMPLES [SEED]\n");
    return 2;
  }
  const std::uint64_t n = std::strtoull(argv[1], nullptr, 10);
  std::mt19937_64 rng(argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1);
  std::normal_distribution<double> g(0.0, 1.0);
  constexpr std::size_t kBlock = std::size_t{1} << 22;
  std::vector<double> white(kBlock), steps(kBlock), out(kBlock);
  double step_sum = 0.0;
  for (std::size_t i = 0; i < kBlock; ++i) {
    white[i] = 0.01 * g(rng);
    steps[i] = 1e-6 * g(rng);
    step_sum += steps[i];
  }
  double bias = 0.0;
  for (std::uint64_t done = 0; done < n;) {
    const std::size_t len = static_cast<std::size_t>(std::min<std::uint64_t>(kBlock, n - done));
    for (std::size_t i = 0; i < len; ++i) {
      out[i] = white[i] + bias;
      bias += steps[i];
    }
    bias -= step_sum;  // each block walks from the same start (a small jump at the seam)
    if (std::fwrite(out.data(), sizeof(double), len, stdout) != len) return 1;
    done += len;
  }
  return 0;
}
