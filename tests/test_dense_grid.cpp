// The dense-grid fast paths (stats/kernels.hpp: eight averaging factors per
// pass, MVAR's four interleaved windows; pipeline::run_dev's blocks of
// factors in parallel) against the definitions written out term by term
// (docs/formulas/stability.md §2), at every averaging factor of the `all`
// grid, for every statistic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/stats/deviation.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/phase.hpp"

namespace cubecal {
namespace {

// A seeded record with all of white, flicker-ish (AR(1)) and random-walk
// frequency noise plus a drift, so no difference order cancels it exactly.
std::vector<double> record(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double walk = 0.0, ar = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    walk += 0.02 * g(rng);
    ar = 0.9 * ar + 0.3 * g(rng);
    y[i] = 3.0 + g(rng) + ar + walk + 1e-4 * static_cast<double>(i);
  }
  return y;
}

double second(const std::vector<double>& x, std::size_t i, std::size_t m) {
  return x[i + 2 * m] - 2.0 * x[i + m] + x[i];
}
double third(const std::vector<double>& x, std::size_t i, std::size_t m) {
  return x[i + 3 * m] - 3.0 * x[i + 2 * m] + 3.0 * x[i + m] - x[i];
}

// The variance at m straight from its definition (SP 1065 eqs. 8, 11, 14,
// 18, 20, 25), on phase x with tau0 = 1; 0 when m does not fit.
double direct_variance(Stat stat, const std::vector<double>& x, std::size_t m) {
  const std::size_t N = x.size();
  const double md = static_cast<double>(m);
  double sum = 0.0;
  std::size_t n = 0;
  switch (stat) {
    case Stat::adev:
      for (std::size_t i = 0; i + 2 * m < N; i += m, ++n) sum += std::pow(second(x, i, m), 2);
      return sum / (2.0 * static_cast<double>(n) * md * md);
    case Stat::oadev:
      for (std::size_t i = 0; i + 2 * m < N; ++i, ++n) sum += std::pow(second(x, i, m), 2);
      return sum / (2.0 * static_cast<double>(n) * md * md);
    case Stat::mdev:
    case Stat::tdev:
      for (std::size_t j = 0; j + 3 * m <= N; ++j, ++n) {
        double s = 0.0;
        for (std::size_t i = j; i < j + m; ++i) s += second(x, i, m);
        sum += s * s;
      }
      return sum / (2.0 * md * md * md * md * static_cast<double>(n));
    case Stat::hdev:
      for (std::size_t i = 0; i + 3 * m < N; i += m, ++n) sum += std::pow(third(x, i, m), 2);
      return sum / (6.0 * static_cast<double>(n) * md * md);
    case Stat::ohdev:
      for (std::size_t i = 0; i + 3 * m < N; ++i, ++n) sum += std::pow(third(x, i, m), 2);
      return sum / (6.0 * static_cast<double>(n) * md * md);
    case Stat::totdev: {
      // Odd reflection at both ends.
      auto xs = [&](std::ptrdiff_t k) {
        const auto last = static_cast<std::ptrdiff_t>(N) - 1;
        if (k < 0) return 2.0 * x[0] - x[static_cast<std::size_t>(-k)];
        if (k > last) return 2.0 * x[N - 1] - x[static_cast<std::size_t>(2 * last - k)];
        return x[static_cast<std::size_t>(k)];
      };
      const auto mm = static_cast<std::ptrdiff_t>(m);
      for (std::ptrdiff_t i = 1; i + 1 < static_cast<std::ptrdiff_t>(N); ++i, ++n)
        sum += std::pow(xs(i - mm) - 2.0 * xs(i) + xs(i + mm), 2);
      return sum / (2.0 * md * md * static_cast<double>(n));
    }
    default:  // the statistics this test does not cover
      break;
  }
  return 0.0;
}

double direct_deviation(Stat stat, const std::vector<double>& x, std::size_t m) {
  const double dev = std::sqrt(direct_variance(stat, x, m));
  return stat == Stat::tdev ? dev * static_cast<double>(m) / std::sqrt(3.0) : dev;
}

constexpr Stat kStats[] = {Stat::adev, Stat::oadev, Stat::mdev, Stat::tdev, Stat::hdev, Stat::ohdev, Stat::totdev};

StabilityOptions no_intervals() {
  StabilityOptions o;
  o.intervals = false;
  return o;
}

// Every m of the `all` grid, through the front door (one thread, the
// grouped kernels) and through run_dev (blocks of factors on two threads).
TEST(DenseGrid, AllTausMatchTheDefinitionForEveryStatistic) {
  const std::vector<double> y = record(1500, 11);
  // The kernels' phase: y integrated, scaled by the same power of two.
  const double scale = power_of_two_scale(y);
  const std::vector<double> x = freq_to_phase(y, 1.0, scale);
  pipeline::DevRequest req;
  req.grid = parse_tau_grid("all");
  req.options = no_intervals();
  req.threads = 2;
  for (Stat stat : kStats) {
    SCOPED_TRACE(std::string(to_string(stat)));
    const auto front = deviation(stat, y, 1.0, DataType::freq, req.grid, req.options);
    req.stat = stat;
    const auto piped = pipeline::run_dev({"y"}, {y}, 1.0, req).channels.at(0).points;
    ASSERT_EQ(front.size(), max_averaging_factor(stat, x.size()));
    ASSERT_EQ(piped.size(), front.size());
    double worst = 0.0;
    for (std::size_t j = 0; j < front.size(); ++j) {
      const std::size_t m = j + 1;
      ASSERT_EQ(front[j].m, m);
      ASSERT_EQ(piped[j].m, m);
      const double want = direct_deviation(stat, x, m) * scale;
      ASSERT_GT(want, 0.0);
      worst = std::max({worst, std::abs(front[j].dev / want - 1.0), std::abs(piped[j].dev / want - 1.0)});
    }
    EXPECT_LT(worst, 1e-12);
  }
}

// A grid in any order with whole groups (9..16, 225..232), a group that
// runs past the end of the record (449..456) and factors around them: each
// point is the single-factor kernel's.
TEST(DenseGrid, GroupsInAnyGridMatchOneFactorAtATime) {
  const std::vector<double> y = record(900, 5);
  const std::vector<std::size_t> ms = {40,  3,   17,  64,  5,   9,   10,  11,  12,  13,  14,  15,
                                       16,  1,   2,   225, 226, 227, 228, 229, 230, 231, 232, 200,
                                       449, 450, 451, 452, 453, 454, 455, 456, 57,  58,  59,  60};
  EXPECT_TRUE(kernel_group_at(ms, 5));
  EXPECT_TRUE(kernel_group_at(ms, 15));
  EXPECT_FALSE(kernel_group_at(ms, 32));  // 57..60 only
  for (Stat stat : {Stat::oadev, Stat::ohdev, Stat::totdev}) {
    SCOPED_TRACE(std::string(to_string(stat)));
    const StabilityRecord rec(y, DataType::freq, 1.0, stat);
    const auto many = rec.evaluate(ms, no_intervals());
    ASSERT_EQ(many.size(), ms.size());
    for (std::size_t j = 0; j < ms.size(); ++j) {
      const StabilityPoint one = rec.evaluate(ms[j], no_intervals());
      EXPECT_EQ(many[j].m, ms[j]);
      EXPECT_EQ(many[j].n, one.n) << ms[j];
      if (one.n > 0) {
        EXPECT_NEAR(many[j].dev / one.dev, 1.0, 1e-12) << ms[j];
      }
    }
  }
}

// A sparse grid (log:20, and factors in no group) is walked in tiles with
// every factor's own accumulators: each OADEV must be the very bits of the
// single-factor kernel, on records whose length is and is not a multiple of
// the tile, with factors at, below and beyond the record's limit.
TEST(DenseGrid, TiledSparseFactorsAreTheBitsOfOneFactorAtATime) {
  for (const std::size_t n : {std::size_t{20'000}, std::size_t{2048 * 5 + 8}, std::size_t{2048 * 3 + 13}}) {
    const std::vector<double> x = freq_to_phase(record(n, 11), 0.1);
    std::vector<std::size_t> ms;
    for (double f = 1.0; f < static_cast<double>(n); f *= 1.122) {
      const auto m = static_cast<std::size_t>(f);
      if (ms.empty() || m != ms.back()) ms.push_back(m);
    }
    ms.push_back((x.size() - 1) / 2);      // the largest that fits
    ms.push_back((x.size() - 1) / 2 + 1);  // does not fit: n == 0
    std::vector<VarianceTerm> tiled(ms.size());
    oavar(x, ms, 0.1, tiled);
    // The first factors 1..8 form a group (its own kernel, equal up to rounding).
    std::vector<bool> grouped(ms.size(), false);
    for (std::size_t j = 0; j < ms.size(); ++j)
      if (kernel_group_at(ms, j)) std::fill_n(grouped.begin() + static_cast<std::ptrdiff_t>(j), kKernelGroup, true);
    std::size_t checked = 0;
    for (std::size_t j = 0; j < ms.size(); ++j) {
      const VarianceTerm one = oavar(x, ms[j], 0.1);
      ASSERT_EQ(tiled[j].n, one.n) << "n=" << n << " m=" << ms[j];
      if (!grouped[j]) {
        EXPECT_EQ(tiled[j].var, one.var) << "n=" << n << " m=" << ms[j];  // bitwise: same terms, same order
      }
      if (one.n > 0) {
        EXPECT_NEAR(tiled[j].var, direct_variance(Stat::oadev, x, ms[j]) / 0.01, 1e-10 * one.var);
        ++checked;
      }
    }
    EXPECT_GT(checked, 50u);
    EXPECT_GT(std::count(grouped.begin(), grouped.end(), false), 50);
    EXPECT_EQ(tiled.back().n, 0u);
  }
}

}  // namespace
}  // namespace cubecal
