// Acceptance check of noise identification by its consequence, the interval
// (issue 11, item 2): "no interval anywhere narrower than the one the true
// noise type would give by more than 2x, checked with seeded power-law noise
// of each alpha at short record lengths".
//
// For every statistic, every noise type it supports (alpha +2..-2, and -3,
// -4 for the Hadamard statistics), record lengths of 64 to 1000 samples of
// frequency and of phase data, several seeds, and every averaging factor of
// the octave grid, the interval with the identified noise type (the default
// options) is compared with the interval with the true type forced
// (StabilityOptions::alpha).
//
// "Narrower by more than 2x" is measured on the interval's width in log
// space, W = ln(hi / lo):  a row fails when W_identified < W_true / 2.
// Why this width: with the chi-squared interval, hi / lo =
// sqrt(chi2_hi / chi2_lo) depends on the EDF (and the confidence) only, not
// on the deviation, which does not depend on alpha, so W compares exactly
// what noise identification changes. W is the length of the error bar on
// the log-log plot on which the curve is read, it is unit-free, and it
// stays meaningful for the wide, lopsided intervals of small EDF where
// (hi - lo) / dev is dominated by hi alone. For large EDF, W ~ z sqrt(2 /
// EDF) (z the normal quantile of the confidence), so a 2x narrower W means
// an EDF overstated about 4x; white PM called on an unmodified
// statistic (EDF ~ the record length instead of a few) gives W 10-100x
// narrower, which is what this test is there to catch.
//
// Noise identification is being reworked: this test states the target. It
// carries the ctest label noise_id_acceptance (`ctest -L noise_id_acceptance`
// runs it alone, `ctest -LE noise_id_acceptance` leaves it out).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "cubecal/sim/power_law_noise.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {
namespace {

constexpr std::size_t kLengths[] = {64, 128, 256, 512, 1000};
constexpr int kSeeds = 24;
constexpr double kNarrowest = 0.5;  // W_identified / W_true below this fails

const Stat kStats[] = {Stat::adev, Stat::oadev, Stat::mdev, Stat::tdev, Stat::hdev, Stat::ohdev, Stat::totdev};

std::vector<int> alphas_of(Stat s) {
  if (s == Stat::hdev || s == Stat::ohdev) return {2, 1, 0, -1, -2, -3, -4};
  return {2, 1, 0, -1, -2};
}

const char* method_name(NoiseId::Method m) {
  switch (m) {
    case NoiseId::Method::acf: return "acf";
    case NoiseId::Method::b1: return "b1";
    case NoiseId::Method::b1_rn: return "b1_rn";
  }
  return "?";
}

// ---------------------------------------------------------------------------
// The generator first: its noise must have the slope of its alpha, or the
// acceptance check below would test nothing.

// Least-squares slope of ln dev against ln tau over the points with
// lo_m <= m <= hi_m.
double log_slope(const std::vector<StabilityPoint>& pts, std::size_t lo_m, std::size_t hi_m) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, k = 0;
  for (const auto& p : pts) {
    if (p.m < lo_m || p.m > hi_m) continue;
    const double x = std::log(p.tau), y = std::log(p.dev);
    sx += x, sy += y, sxx += x * x, sxy += x * y, k += 1;
  }
  return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

// Slopes of the deviations (half the variance's): OADEV tau^((-alpha-1)/2)
// for -2 <= alpha <= 0, MDEV tau^(-3/2) for white PM and tau^-1 for flicker
// PM, HDEV tau^((-alpha-1)/2) down to alpha = -4 (NIST SP 1065 Table 7).
// Averaged over seeds in log space; 4096 samples, m from 2 to 256.
TEST(PowerLawNoise, DeviationSlopesMatchTheirAlpha) {
  const struct {
    double alpha;
    Stat stat;
    double slope;
  } cases[] = {{2, Stat::mdev, -1.5},  {1, Stat::mdev, -1.0}, {0, Stat::oadev, -0.5}, {-1, Stat::oadev, 0.0},
               {-2, Stat::oadev, 0.5}, {-3, Stat::hdev, 1.0}, {-4, Stat::hdev, 1.5}};
  const std::vector<std::size_t> ms{2, 4, 8, 16, 32, 64, 128, 256};
  StabilityOptions no_ci;
  no_ci.intervals = false;
  for (const auto& c : cases) {
    for (DataType type : {DataType::phase, DataType::freq}) {
      double mean = 0.0;
      const int seeds = 12;
      for (int s = 0; s < seeds; ++s) {
        const auto data = power_law_noise(c.alpha, 4096, 500 + static_cast<std::uint64_t>(s), type);
        mean += log_slope(stability(data, type, 1.0, c.stat, ms, no_ci), 2, 256) / seeds;
      }
      EXPECT_NEAR(mean, c.slope, 0.1) << "alpha " << c.alpha << " " << to_string(type) << " " << to_string(c.stat);
    }
  }
}

TEST(PowerLawNoise, WhiteAndItsDifferenceAreExact) {
  // a = 0: the innovations themselves; a = -2: their first difference.
  const auto w = power_law_noise(2.0, 50, 9, DataType::phase);
  EXPECT_EQ(power_law_noise(0.0, 50, 9, DataType::freq), w);
  const auto d = power_law_noise(2.0, 50, 9, DataType::freq);
  EXPECT_EQ(d[0], w[0]);
  for (std::size_t i = 1; i < w.size(); ++i) EXPECT_EQ(d[i], w[i] - w[i - 1]) << i;
  // a = 2 (white FM as phase data): the running sum of the innovations.
  const auto x = power_law_noise(0.0, 50, 9, DataType::phase);
  double sum = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    sum += w[i];
    EXPECT_NEAR(x[i], sum, 1e-12) << i;
  }
  EXPECT_NE(power_law_noise(-1.0, 50, 9), power_law_noise(-1.0, 50, 10)) << "the seed matters";
}

// ---------------------------------------------------------------------------
// The acceptance check.

struct Row {
  Stat stat;
  int alpha;
  DataType type;
  std::size_t n;
  std::uint64_t seed;
  std::size_t m;
  std::size_t from_end;  // 0: the last AF of the grid, 1: the one before, ...
  int id_alpha;
  NoiseId::Method method;
  double alpha_est;
  double edf_id, edf_true;
  double w_id, w_true;
  double ratio() const { return w_id / w_true; }
};

struct Tally {
  std::size_t rows = 0, failing = 0, no_interval = 0;
  double worst = INFINITY;
};

using Tallies = std::map<std::tuple<Stat, int, DataType>, Tally>;

// Every (type, alpha, length, seed, statistic, AF) row with the identified
// type's interval and the true type's; prints the summary and returns the
// tallies. `widest`: StabilityOptions::conservative_short.
Tallies run_power_law_check(bool widest) {
  std::printf("\n== intervals where fewer than 30 averages remain: %s\n",
              widest ? "widest of the neighbouring types (conservative_short, analyze's default)"
                     : "the identified type's, as Stable32 (dev's default)");
  Tallies tally;
  std::vector<Row> failing;
  StabilityOptions identified;  // alpha identified per tau
  identified.conservative_short = widest;
  for (DataType type : {DataType::freq, DataType::phase}) {
    for (int alpha : {2, 1, 0, -1, -2, -3, -4}) {
      for (std::size_t n : kLengths) {
        for (int s = 0; s < kSeeds; ++s) {
          const std::uint64_t seed =  // distinct for every (alpha, n, s)
              1'000'000 * static_cast<std::uint64_t>(alpha + 10) + 100 * n + static_cast<std::uint64_t>(s);
          const std::vector<double> data = power_law_noise(alpha, n, seed, type);
          for (Stat stat : kStats) {
            const auto alphas = alphas_of(stat);
            if (std::find(alphas.begin(), alphas.end(), alpha) == alphas.end()) continue;
            const StabilityRecord rec(data, type, 1.0, stat);
            const auto ms = averaging_factors(parse_tau_grid("octave"), rec.max_m(), 1.0);
            StabilityOptions truth;
            truth.alpha = alpha;
            const auto id = rec.evaluate(ms, identified);
            const auto tr = rec.evaluate(ms, truth);
            Tally& t = tally[{stat, alpha, type}];
            for (std::size_t j = 0; j < ms.size(); ++j) {
              const StabilityPoint &p = id[j], &q = tr[j];
              EXPECT_GT(q.edf, 0.0) << to_string(stat) << " has an interval for alpha " << alpha;
              ++t.rows;
              if (!(p.edf > 0.0)) {  // no interval at all: said, not counted as narrow
                ++t.no_interval;
                continue;
              }
              const NoiseId nid = identify_noise(rec.phase(), ms[j], stat);
              const Row r{stat,
                          alpha,
                          type,
                          n,
                          seed,
                          ms[j],
                          ms.size() - 1 - j,
                          p.alpha,
                          nid.method,
                          nid.alpha_est,
                          p.edf,
                          q.edf,
                          std::log(p.interval.hi / p.interval.lo),
                          std::log(q.interval.hi / q.interval.lo)};
              t.worst = std::min(t.worst, r.ratio());
              if (r.ratio() < kNarrowest) {
                ++t.failing;
                failing.push_back(r);
              }
            }
          }
        }
      }
    }
  }

  // The summary: one line per statistic and noise type, frequency and
  // phase data side by side.
  std::printf("\nW = ln(hi/lo); a row fails when W_identified < %.2f W_true\n", kNarrowest);
  std::printf("%-7s %5s | %28s | %28s\n", "stat", "alpha", "freq: rows  fail  no-CI  worst",
              "phase: rows  fail  no-CI worst");
  for (Stat stat : kStats)
    for (int alpha : alphas_of(stat)) {
      const Tally &f = tally[{stat, alpha, DataType::freq}], &p = tally[{stat, alpha, DataType::phase}];
      std::printf("%-7s %5d | %11zu %5zu %6zu %5.3f | %11zu %5zu %6zu %5.3f\n", std::string(to_string(stat)).c_str(),
                  alpha, f.rows, f.failing, f.no_interval, f.worst, p.rows, p.failing, p.no_interval, p.worst);
    }

  // The failing rows: the three narrowest of each statistic, noise type and
  // data type, and the failures per record length.
  std::sort(failing.begin(), failing.end(), [](const Row& a, const Row& b) {
    return std::tie(a.stat, a.alpha, a.type) < std::tie(b.stat, b.alpha, b.type) ||
           (std::tie(a.stat, a.alpha, a.type) == std::tie(b.stat, b.alpha, b.type) && a.ratio() < b.ratio());
  });
  std::size_t rows = 0;
  for (const auto& [key, t] : tally) rows += t.rows;
  std::printf("%zu of %zu rows fail\n", failing.size(), rows);
  if (!failing.empty()) {
    std::printf("\n%zu failing rows; the narrowest three per (stat, alpha, type):\n", failing.size());
    std::printf("%-7s %5s %5s %5s %6s %4s %6s %-10s %7s %9s %9s %7s %7s %6s\n", "stat", "alpha", "type", "N", "seed",
                "AF", "id", "method", "a_est", "edf_id", "edf_true", "W_id", "W_true", "ratio");
    std::size_t shown = 0;
    for (std::size_t i = 0; i < failing.size(); ++i) {
      const Row& r = failing[i];
      if (i > 0 &&
          std::tie(r.stat, r.alpha, r.type) == std::tie(failing[i - 1].stat, failing[i - 1].alpha, failing[i - 1].type))
        ++shown;
      else
        shown = 0;
      if (shown >= 3) continue;
      std::printf("%-7s %5d %5s %5zu %6llu %4zu %6d %-10s %7.2f %9.1f %9.1f %7.4f %7.4f %6.3f\n",
                  std::string(to_string(r.stat)).c_str(), r.alpha, std::string(to_string(r.type)).c_str(), r.n,
                  static_cast<unsigned long long>(r.seed), r.m, r.id_alpha, method_name(r.method), r.alpha_est,
                  r.edf_id, r.edf_true, r.w_id, r.w_true, r.ratio());
    }
    std::map<std::size_t, std::size_t> per_n, per_end;
    std::map<std::pair<int, int>, std::size_t> per_call;  // (true alpha, identified alpha)
    std::map<std::string, std::size_t> per_method;
    for (const Row& r : failing) {
      ++per_n[r.n];
      ++per_end[r.from_end];
      ++per_method[method_name(r.method)];
      ++per_call[{r.alpha, r.id_alpha}];
    }
    std::printf("failing rows per record length:");
    for (const auto& [n, k] : per_n) std::printf("  N=%zu: %zu", n, k);
    std::printf("\nfailing rows per AF counted from the grid's last (0: the last):");
    for (const auto& [e, k] : per_end) std::printf("  %zu: %zu", e, k);
    std::printf("\nfailing rows per (true alpha -> identified alpha):");
    for (const auto& [a, k] : per_call) std::printf("  %d->%d: %zu", a.first, a.second, k);
    std::printf("\nfailing rows per identification method:");
    for (const auto& [name, k] : per_method) std::printf("  %s: %zu", name.c_str(), k);
    std::printf("\n");
  }

  return tally;
}

// The target of the noise-identification work: with the conservative
// intervals no row fails. The Stable32-faithful intervals are printed for
// the record (they fail at the last AFs, where B1 calls PM for FM).
TEST(NoiseIdPowerLaw, NoIntervalNarrowerThanTheTrueTypesByMoreThan2x) {
  run_power_law_check(false);
  Tallies tally = run_power_law_check(true);
  for (Stat stat : kStats)
    for (int alpha : alphas_of(stat))
      for (DataType type : {DataType::freq, DataType::phase}) {
        const Tally& t = tally[{stat, alpha, type}];
        EXPECT_EQ(t.failing, 0u) << to_string(stat) << " alpha " << alpha << " " << to_string(type)
                                 << " data: " << t.failing << " of " << t.rows
                                 << " intervals narrower than the true type's "
                                 << "by more than 2x (worst W ratio " << t.worst << ")";
      }
}

}  // namespace
}  // namespace cubecal
