// Kasdin & Walter's generator a block at a time (sim/power_law_generator.hpp):
// the direct convolution's samples, the closed-form Allan variance of each
// power law, and its place in the sensor simulator.
#include <gtest/gtest.h>

#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "cubecal/sim/power_law_generator.hpp"
#include "cubecal/sim/power_law_noise.hpp"
#include "cubecal/sim/simulator.hpp"
#include "cubecal/stats/deviation.hpp"

namespace cubecal {
namespace {

double sigma_w(const PowerLawNoise& t, double dt) {
  return std::sqrt(t.h / (2.0 * dt * std::pow(2.0 * std::numbers::pi * dt, t.alpha)));
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST(PowerLawGenerator, FilterAsLongAsTheRecordIsKasdinWalterExactly) {
  const double dt = 0.1;
  for (const double alpha : {2.0, 1.0, 0.0, -1.0, -2.0, -0.5}) {
    const PowerLawNoise t{alpha, 3e-4};
    const std::size_t n = 3000;
    PowerLawGenerator g(t, dt, PowerLawGenerator::filter_length_for(n), 11);
    std::vector<double> got(n);
    // In uneven pieces: the blocks' seams must not show.
    g.next(std::span<double>(got).subspan(0, 7));
    g.next(std::span<double>(got).subspan(7, 1000));
    g.next(std::span<double>(got).subspan(1007));
    std::vector<double> want = power_law_noise(alpha, n, 11, DataType::freq);
    for (double& v : want) v *= sigma_w(t, dt);
    const double scale = max_abs(want);
    for (std::size_t i = 0; i < n; ++i) ASSERT_NEAR(got[i], want[i], 1e-12 * scale) << "alpha " << alpha << " i " << i;
  }
}

TEST(PowerLawGenerator, ShortFilterIsTheTruncatedConvolutionAcrossBlocks) {
  const PowerLawNoise t = flicker_term(0.02);
  const double dt = 0.01;
  const std::size_t len = 256, n = 2000;
  PowerLawGenerator g(t, dt, len, 5);
  std::vector<double> got(n);
  g.next(got);
  // The same innovations, convolved with the first `len` taps.
  std::mt19937_64 engine(5);
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> w(n), taps(len);
  for (double& v : w) v = normal(engine);
  taps[0] = 1.0;
  for (std::size_t k = 1; k < len; ++k)
    taps[k] = taps[k - 1] * (static_cast<double>(k) - 1.0 + 0.5) / static_cast<double>(k);
  std::vector<double> want(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < len && k <= i; ++k) want[i] += taps[k] * w[i - k];
  for (double& v : want) v *= sigma_w(t, dt);
  const double scale = max_abs(want);
  for (std::size_t i = 0; i < n; ++i) ASSERT_NEAR(got[i], want[i], 1e-12 * scale) << "i " << i;
}

// The Allan variance of S_y(f) = h f^alpha (NIST SP 1065 Table 3):
// white FM h0 / (2 tau), flicker FM 2 ln 2 h_-1, random-walk FM
// (2 pi^2 / 3) h_-2 tau. Each 95 % interval of 24 seeded records holds it
// at each tau about 95 % of the time.
TEST(PowerLawGenerator, AllanVarianceOfEachPowerLaw) {
  const double dt = 0.1;
  const std::size_t n = std::size_t{1} << 16;
  struct Case {
    PowerLawNoise term;
    double (*avar)(double h, double tau);
  };
  const Case cases[] = {
      {{0.0, 2e-4}, [](double h, double tau) { return h / (2.0 * tau); }},
      {flicker_term(0.01), [](double h, double) { return 2.0 * std::numbers::ln2 * h; }},
      {{-2.0, 1e-7}, [](double h, double tau) { return 2.0 * std::numbers::pi * std::numbers::pi / 3.0 * h * tau; }},
  };
  for (const Case& c : cases) {
    int inside = 0, total = 0;
    for (std::uint64_t seed = 1; seed <= 24; ++seed) {
      PowerLawGenerator g(c.term, dt, PowerLawGenerator::filter_length_for(n), seed);
      std::vector<double> y(n);
      g.next(y);
      TauGrid grid;
      grid.kind = TauGrid::Kind::list;
      grid.taus = {1.6, 6.4, 25.6, 102.4};
      StabilityOptions opt;
      opt.ci = 0.95;
      opt.alpha = static_cast<int>(c.term.alpha);  // the known noise type: its EDF
      for (const StabilityPoint& p : oadev(y, 1.0 / dt, DataType::freq, grid, opt)) {
        const double truth = std::sqrt(c.avar(c.term.h, p.tau));
        inside += p.interval.lo <= truth && truth <= p.interval.hi;
        ++total;
      }
    }
    EXPECT_GE(inside, total * 85 / 100) << "alpha " << c.term.alpha << ": " << inside << " of " << total;
  }
}

TEST(PowerLawGenerator, SimulatorAddsTheTermsOnStreamsOfTheirOwn) {
  TriadModel plain;
  plain.unit = "deg/s";
  for (auto& a : plain.axes) {
    a.white_sigma = 0.05;
    a.bias = BiasProcess::random_walk;
    a.bias_sigma = 1e-4;
  }
  TriadModel with = plain;
  for (auto& a : with.axes) a.power_law.push_back(flicker_term(0.003));
  const std::size_t n = 5000;
  const double dt = 0.1;
  TriadSimulator s0(plain, dt, 9, n), s1(with, dt, 9, n);
  std::vector<double> out0(3 * n), out1(3 * n);
  s0.run(n, {}, {}, out0);
  s1.run(n - 1, {}, {}, std::span<double>(out1).subspan(0, 3 * (n - 1)));
  const auto last = s1.step({0.0, 0.0, 0.0}, with.temp_ref);  // step() continues the same streams
  for (int i = 0; i < 3; ++i) out1[3 * (n - 1) + static_cast<std::size_t>(i)] = last[static_cast<std::size_t>(i)];
  // What the flicker added: each axis's own generator, as seeded by the simulator.
  std::vector<double> diff(n);
  double spread = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    diff[k] = out1[3 * k] - out0[3 * k];
    spread = std::max(spread, std::abs(diff[k]));
  }
  EXPECT_GT(spread, 1e-4);  // the term is there
  // The rest of the model sees the same normals: the difference is a
  // flicker process of the term's level, not a different realisation of the
  // white noise (whose sample-to-sample differences would be ~0.07).
  double step = 0.0;
  for (std::size_t k = 1; k < n; ++k) step = std::max(step, std::abs(diff[k] - diff[k - 1]));
  EXPECT_LT(step, 0.02);
}

}  // namespace
}  // namespace cubecal
