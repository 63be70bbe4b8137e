// TIE rms, MTIE, MTOT, TTOT, HTOT, Theo1 and TheoBR against the Stable32
// tables in ../shared/data/stable32 (tau and n exact, the value within 1e-4
// relative, the noise type where Stable32 identified it, the interval within
// 1e-3 where Stable32's EDF is ours), and each against its definition or a
// closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/deviation.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/stats/theo.hpp"
#include "../src/stats/detail/time_error.hpp"
#include "../src/stats/detail/total_kernels.hpp"
#include "direct_total.hpp"
#include "stable32_table.hpp"

namespace cubecal {
namespace {

using test::read_column;
using test::shared_data;

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// A row of any Stable32 table: AF, tau, n, then the value (4-column TIE and
// MTIE tables) or alpha, min, value, max (7 columns; Theo1 prints n as a
// floating-point number).
struct Row {
  std::size_t af = 0;
  double tau = 0;
  double n = 0;
  std::optional<int> alpha;
  double lo = 0, dev = 0, hi = 0;
};

// Rows commented out with '#' (AllanTools' test suite left out the rows it
// did not reproduce) are rows of the table too: every one is compared.
std::vector<Row> read_rows(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t first = line.find_first_not_of(" \t");
    const bool commented = first != std::string::npos && line[first] == '#';
    const std::string body = commented ? line.substr(first + 1) : line;
    if (body.find_first_of("#:") != std::string::npos) continue;  // a header line
    std::istringstream ss(body);
    std::vector<double> v;
    double d = 0;
    while (ss >> d) v.push_back(d);
    Row r;
    if (v.size() == 4) {
      r = {static_cast<std::size_t>(v[0]), v[1], v[2], std::nullopt, 0, v[3], 0};
    } else if (v.size() == 7) {
      r = {static_cast<std::size_t>(v[0]), v[1], v[2], static_cast<int>(v[3]), v[4], v[5], v[6]};
    } else {
      continue;
    }
    rows.push_back(r);
  }
  return rows;
}

const std::vector<double>& phase_dat() {
  static const std::vector<double> x = read_column(shared_data("stable32/phasedat/PHASE.DAT"));
  return x;
}
const std::vector<double>& cs5071a() {
  static const std::vector<double> x = read_column(shared_data("stable32/cs5071a/5071A_phase.txt.gz"));
  return x;
}

enum class NTerms {
  exact,   // the table's # is the number of terms
  record,  // the table's # is the record length (Stable32's MTIE outside its fast mode)
};

struct Case {
  const char* table;
  bool cs5071a;  // else PHASE.DAT
  Stat stat;
  std::optional<int> fixed_alpha = std::nullopt;  // the table was made with this type
  // As Stable32 made the table: corrected (on), plain (off), or its default
  // (stable32: TOTDEV and HTOT corrected, MTOT and TTOT not).
  BiasCorrection bias_correction = BiasCorrection::stable32;
  NTerms n_terms = NTerms::exact;
  // From this factor on Stable32's intervals follow coefficients of its own
  // (MTOT and TTOT from m = 10: docs/formulas/stability.md 5.6): ours, from
  // SP 1065 Table 8, must hold them (wider); below it they must match.
  std::size_t ci_own_from = std::numeric_limits<std::size_t>::max();
};

struct Outcome {
  std::size_t rows = 0, alpha_rows = 0, alpha_match = 0, ci_rows = 0, ci_own_rows = 0;
  double worst_dev = 0, worst_ci = 0, worst_ci_own = 0;
};

Outcome compare(const Case& c) {
  Outcome o;
  const auto rows = read_rows(shared_data(c.table));
  EXPECT_FALSE(rows.empty()) << c.table;
  const std::vector<double>& x = c.cs5071a ? cs5071a() : phase_dat();
  const StabilityRecord rec(x, DataType::phase, 1.0, c.stat);
  std::vector<std::size_t> afs;
  for (const auto& r : rows) afs.push_back(r.af);
  StabilityOptions opt;
  opt.alpha = c.fixed_alpha;
  opt.bias_correction = c.bias_correction;
  const auto run = rec.evaluate(afs, opt);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    const StabilityPoint& p = run[k];
    SCOPED_TRACE(std::string(c.table) + " AF " + std::to_string(row.af));
    EXPECT_LE(row.af, rec.max_m());
    EXPECT_GT(p.n, 0u);
    if (p.n == 0) continue;
    EXPECT_LE(rel(p.tau, row.tau), 5e-5);  // tau printed with 5 digits
    const double n_want = c.n_terms == NTerms::record ? static_cast<double>(x.size()) : row.n;
    if (c.n_terms == NTerms::record) {
      EXPECT_EQ(row.n, n_want);                                                   // the record length
      EXPECT_EQ(static_cast<double>(p.n), n_want - static_cast<double>(row.af));  // N - m windows
    } else if (c.stat == Stat::theo1 || c.stat == Stat::theobr) {
      // Stable32 prints Theo1's # with five significant digits (1.0050e+05).
      const double unit = std::pow(10.0, std::floor(std::log10(row.n)) - 4.0);
      EXPECT_LE(std::abs(static_cast<double>(p.n) - n_want), 0.5 * unit) << p.n << " vs " << row.n;
    } else {
      EXPECT_EQ(static_cast<double>(p.n), n_want);
    }
    const double e = rel(p.dev, row.dev);
    EXPECT_LE(e, 1e-4) << "value " << p.dev << " vs " << row.dev;
    o.worst_dev = std::max(o.worst_dev, e);
    ++o.rows;
    if (row.alpha && !c.fixed_alpha && has_intervals(c.stat)) {
      ++o.alpha_rows;
      if (p.alpha == *row.alpha) ++o.alpha_match;
      // Where 30 or more averages remain the lag-1 ACF decides, as in Stable32.
      if ((x.size() - 1) / row.af >= 30) {
        EXPECT_EQ(p.alpha, *row.alpha) << "noise type";
      }
    }
    if (row.lo > 0 && row.hi > 0) {
      ++o.ci_rows;
      StabilityOptions forced = opt;
      forced.alpha = *row.alpha;
      const StabilityPoint q = rec.evaluate(row.af, forced);
      const double ci_err = std::max(rel(q.interval.lo, row.lo), rel(q.interval.hi, row.hi));
      if (row.af < c.ci_own_from) {
        EXPECT_LE(ci_err, 1e-3) << "interval [" << q.interval.lo << ", " << q.interval.hi << "] vs [" << row.lo << ", "
                                << row.hi << "]";
        o.worst_ci = std::max(o.worst_ci, ci_err);
      } else {
        --o.ci_rows;
        ++o.ci_own_rows;
        EXPECT_LE(q.interval.lo, row.lo) << "Stable32's interval within ours";
        EXPECT_GE(q.interval.hi, row.hi) << "Stable32's interval within ours";
        o.worst_ci_own = std::max(o.worst_ci_own, ci_err);
      }
    }
  }
  return o;
}

class Stable32More : public ::testing::TestWithParam<Case> {};

TEST_P(Stable32More, MatchesTable) {
  const Outcome o = compare(GetParam());
  std::printf("  %-52s rows %3zu  worst value %.2e  alpha %zu/%zu  CI rows %zu (worst %.2e, Stable32's type)",
              GetParam().table, o.rows, o.worst_dev, o.alpha_match, o.alpha_rows, o.ci_rows, o.worst_ci);
  if (o.ci_own_rows > 0)
    std::printf("; %zu rows of Stable32's own EDF (apart by up to %.2e, inside ours)", o.ci_own_rows, o.worst_ci_own);
  std::printf("\n");
}

const Case kCases[] = {
    {"stable32/phasedat/phase_dat_tierms.txt", false, Stat::tierms},
    {"stable32/cs5071a/tierms_all.txt", true, Stat::tierms},
    {"stable32/cs5071a/tierms_decade.txt", true, Stat::tierms},
    {"stable32/phasedat/phase_dat_mtie.txt", false, Stat::mtie},
    {"stable32/cs5071a/mtie_all.txt", true, Stat::mtie},
    {"stable32/cs5071a/mtie_fast.txt", true, Stat::mtie},
    // Stable32's MTIE outside its fast mode prints the record length as "#".
    {"stable32/cs5071a/mtie_decade.txt", true, Stat::mtie, std::nullopt, BiasCorrection::off, NTerms::record},
    {"stable32/phasedat/phase_dat_mtotdev_octave.txt", false, Stat::mtotdev, std::nullopt, BiasCorrection::stable32,
     NTerms::exact, 10},
    {"stable32/phasedat/phase_dat_mtotdev_decade.txt", false, Stat::mtotdev, std::nullopt, BiasCorrection::stable32,
     NTerms::exact, 10},
    {"stable32/phasedat/phase_dat_mtotdev_octave_alpha0.txt", false, Stat::mtotdev, 0, BiasCorrection::stable32,
     NTerms::exact, 10},
    // Stable32 1.53's all-tau run: bias-corrected by the noise type it gives.
    {"stable32/phasedat/phase_dat_mtotdev.txt", false, Stat::mtotdev, std::nullopt, BiasCorrection::on},
    {"stable32/phasedat/phase_dat_ttotdev_octave.txt", false, Stat::ttotdev, std::nullopt, BiasCorrection::stable32,
     NTerms::exact, 10},
    {"stable32/phasedat/phase_dat_ttotdev_decade.txt", false, Stat::ttotdev, std::nullopt, BiasCorrection::stable32,
     NTerms::exact, 10},
    {"stable32/phasedat/phase_dat_ttotdev_all.txt", false, Stat::ttotdev, std::nullopt, BiasCorrection::on},
    {"stable32/phasedat/phase_dat_htotdev_octave.txt", false, Stat::htotdev},
    // Made without bias correction; Stable32 says alpha 2 on every row.
    {"stable32/phasedat/phase_dat_htotdev_octave_nobias.txt", false, Stat::htotdev, 2, BiasCorrection::off},
    // Theo1 with the type fixed at white FM (Theo1's bias is 1 there).
    {"stable32/phasedat/phase_dat_theo1_alpha0.txt", false, Stat::theo1, 0},
    {"stable32/phasedat/phase_dat_theo1_alpha0_decade.txt", false, Stat::theo1, 0},
    // Stable32's bias-removed Theo1 ("Alpha = 1" in its header): TheoBR.
    {"stable32/phasedat/phase_dat_theo1.txt", false, Stat::theobr, 1},
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.table;
  s = s.substr(s.find('/') + 1);
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Tables, Stable32More, ::testing::ValuesIn(kCases), case_name);

// ---------------------------------------------------------------------------
// Definitions, written out term by term (O(N m) and slower), on seeded data.

std::vector<double> random_walk(std::size_t n, unsigned seed, double drift = 0.0) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> w(0.0, 1.0);
  std::vector<double> x(n);
  double acc = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = acc + drift * static_cast<double>(i);
    acc += w(g);
  }
  return x;
}

double direct_mtie(const std::vector<double>& x, std::size_t m) {
  double best = 0;
  for (std::size_t i = 0; i + m < x.size(); ++i) {
    const auto [lo, hi] = std::minmax_element(x.begin() + static_cast<std::ptrdiff_t>(i),
                                              x.begin() + static_cast<std::ptrdiff_t>(i + m + 1));
    best = std::max(best, *hi - *lo);
  }
  return best;
}

double direct_theo1(const std::vector<double>& x, std::size_t m) {
  const std::size_t N = x.size(), h = m / 2;
  double sum = 0;
  for (std::size_t i = 0; i < N - m; ++i)
    for (std::size_t d = 0; d < h; ++d) {
      const double t = (x[i] - x[i - d + h]) + (x[i + m] - x[i + d + h]);
      sum += t * t / static_cast<double>(h - d);
    }
  return sum / (0.75 * static_cast<double>(N - m) * static_cast<double>(m * m));
}

TEST(TimeError, TieRmsAndMtieOfALineAreItsSlope) {
  // Phase growing 3 ns per s: every window's TIE is 3 m ns.
  std::vector<double> x(500);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = 3e-9 * static_cast<double>(i);
  for (std::size_t m : {1u, 7u, 100u, 499u}) {
    const double want = 3e-9 * static_cast<double>(m);
    EXPECT_NEAR(std::sqrt(tie_mean_square(x, m).var), want, want * 1e-12) << m;
    EXPECT_NEAR(std::sqrt(mtie_square(x, m).var), want, want * 1e-12) << m;
  }
  // The same line given as frequency: TIE keeps the offset.
  const std::vector<double> y(499, 3e-9);
  const auto t = cubecal::mtie(y, 1.0, DataType::freq, parse_tau_grid("1,10"));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[1].dev, 30e-9, 30e-9 * 1e-12);
}

TEST(TimeError, MtieEqualsTheDirectScan) {
  const auto x = random_walk(3000, 7, 0.01);
  for (std::size_t m : {1u, 2u, 5u, 63u, 64u, 65u, 1000u, 2999u})
    EXPECT_DOUBLE_EQ(std::sqrt(mtie_square(x, m).var), direct_mtie(x, m)) << m;
}

TEST(TimeError, TieRmsOfWhitePhaseIsSqrt2Sigma) {
  // Independent phase points of variance s^2: E[(x[i+m] - x[i])^2] = 2 s^2,
  // and the mean of n terms (N - m of them, within m of each other
  // correlated at most pairwise) has a relative sd below sqrt(4/n).
  std::mt19937_64 g(11);
  std::normal_distribution<double> w(0.0, 2.0);
  std::vector<double> x(200000);
  for (double& v : x) v = w(g);
  for (std::size_t m : {1u, 10u, 1000u}) {
    const VarianceTerm t = tie_mean_square(x, m);
    EXPECT_NEAR(t.var / 8.0, 1.0, 4.0 * std::sqrt(4.0 / static_cast<double>(t.n))) << m;
  }
}

TEST(TotalVariances, MatchTheDefinition) {
  const auto x = random_walk(400, 3, 0.5);
  std::vector<double> d(x.size() - 1);
  for (std::size_t k = 0; k + 1 < x.size(); ++k) d[k] = x[k + 1] - x[k];
  for (std::size_t m : {1u, 2u, 3u, 8u, 33u, 133u}) {
    const double tau0 = 0.5, tau = static_cast<double>(m) * tau0;
    const VarianceTerm mt = mtotvar(x, m, tau0);
    EXPECT_EQ(mt.n, x.size() - 3 * m + 1);
    EXPECT_NEAR(mt.var, test::direct_total(x, m) / (2.0 * tau * tau), 1e-10 * mt.var) << m;
    if (m < 2) continue;
    const VarianceTerm ht = htotvar(d, m, tau0);
    EXPECT_EQ(ht.n, x.size() - 3 * m);
    EXPECT_NEAR(ht.var, test::direct_total(d, m) / (6.0 * tau0 * tau0), 1e-10 * ht.var) << m;
  }
  // TTOT is tau MTOT / sqrt 3; HTOT at m = 1 is the overlapping HDEV.
  const StabilityRecord mt(x, DataType::phase, 0.5, Stat::mtotdev);
  const StabilityRecord tt(x, DataType::phase, 0.5, Stat::ttotdev);
  const StabilityRecord ht(x, DataType::phase, 0.5, Stat::htotdev);
  const StabilityRecord oh(x, DataType::phase, 0.5, Stat::ohdev);
  StabilityOptions none;
  none.intervals = false;
  for (std::size_t m : {1u, 4u, 50u}) {
    const double tau = 0.5 * static_cast<double>(m);
    EXPECT_NEAR(tt.evaluate(m, none).dev, mt.evaluate(m, none).dev * tau / std::sqrt(3.0),
                1e-12 * tt.evaluate(m, none).dev);
  }
  EXPECT_DOUBLE_EQ(ht.evaluate(1, none).dev, oh.evaluate(1, none).dev);
}

TEST(TotalVariances, InvariantToPhaseOffsetAndFrequencyOffset) {
  const auto x = random_walk(300, 5);
  auto y = x;
  for (std::size_t i = 0; i < y.size(); ++i) y[i] += 1e3 + 40.0 * static_cast<double>(i);
  for (Stat s : {Stat::mtotdev, Stat::theo1}) {
    const StabilityRecord a(x, DataType::phase, 1.0, s), b(y, DataType::phase, 1.0, s);
    StabilityOptions none;
    none.intervals = false;
    for (std::size_t m : {2u, 10u, 50u})
      EXPECT_NEAR(b.evaluate(m, none).dev, a.evaluate(m, none).dev, 1e-8 * a.evaluate(m, none).dev)
          << to_string(s) << " m " << m;
  }
}

// MTOT's bias for white FM (0.73 of MVAR) and HTOT's for random-walk FM
// (0.771 of HVAR), the factors of the bias correction, by seeded simulation:
// the mean over runs of the total variance over the mean of MVAR (OHVAR) of
// the same runs.
TEST(TotalVariances, BiasFactorsBySimulation) {
  constexpr int kRuns = 200;
  constexpr std::size_t kN = 1025, kM = 32;
  double mt = 0, mv = 0, ht = 0, hv = 0;
  std::mt19937_64 g(2024);
  std::normal_distribution<double> w(0.0, 1.0);
  std::vector<double> wfm(kN), rwfm(kN);
  for (int r = 0; r < kRuns; ++r) {
    double acc = 0, f = 0, acc2 = 0;
    for (std::size_t i = 0; i < kN; ++i) {
      wfm[i] = acc;
      acc += w(g);
      rwfm[i] = acc2;
      f += w(g);
      acc2 += f;
    }
    mt += mtotvar(wfm, kM, 1.0).var;
    mv += mvar(wfm, kM, 1.0).var;
    std::vector<double> d(kN - 1);
    for (std::size_t k = 0; k + 1 < kN; ++k) d[k] = rwfm[k + 1] - rwfm[k];
    ht += htotvar(d, kM, 1.0).var;
    hv += ohvar(rwfm, kM, 1.0).var;
  }
  std::printf("  MTOT/MVAR white FM %.3f (0.73), HTOT/HVAR random-walk FM %.3f (0.771)\n", mt / mv, ht / hv);
  // Relative sd of a ratio of means over 200 runs of EDF ~ 30..100: ~2 %.
  EXPECT_NEAR(mt / mv, 0.73, 0.06);
  EXPECT_NEAR(ht / hv, 0.771, 0.08);
}

// The EDFs of the total variances against the sample EDF (2 mean^2 / var)
// of seeded simulations (N = 1001, 400 runs: ~10 % sd). From m = 16 on the
// formulas of the totals, MTOT's SP 1065 Table 8 and HTOT's table of Howe
// et al., within 30 %; at m = 4 the EDFs taken there (MDEV's Greenhall-Riley
// for MTOT, SP 1065 Table 5 for HTOT, as Stable32) at most the simulated one
// (lower bounds: the interval is never too narrow).
TEST(TotalVariances, EdfBySimulation) {
  constexpr int kRuns = 400;
  constexpr std::size_t kN = 1001;
  std::mt19937_64 g(99);
  std::normal_distribution<double> w(0.0, 1.0);
  for (int alpha : {0, -2}) {
    for (std::size_t m : {4u, 16u, 64u}) {
      double s1 = 0, s2 = 0, h1 = 0, h2 = 0;
      std::vector<double> x(kN), d(kN - 1);
      for (int r = 0; r < kRuns; ++r) {
        double a = 0, f = 0;
        for (double& v : x) {
          v = a;
          if (alpha == 0) {
            a += w(g);
          } else {
            f += w(g);
            a += f;
          }
        }
        const double v = mtotvar(x, m, 1.0).var;
        s1 += v;
        s2 += v * v;
        for (std::size_t k = 0; k + 1 < kN; ++k) d[k] = x[k + 1] - x[k];
        const double hv = htotvar(d, m, 1.0).var;
        h1 += hv;
        h2 += hv * hv;
      }
      const double mm = s1 / kRuns, mv = s2 / kRuns - mm * mm;
      const double hm = h1 / kRuns, hvar = h2 / kRuns - hm * hm;
      const double mtot_sim = 2 * mm * mm / mv, htot_sim = 2 * hm * hm / hvar;
      const double mtot_edf = edf_for(Stat::mtotdev, alpha, m, kN), htot_edf = edf_for(Stat::htotdev, alpha, m, kN);
      std::printf("  alpha %2d m %2zu: MTOT EDF simulated %.1f, ours %.1f; HTOT simulated %.1f, ours %.1f\n", alpha, m,
                  mtot_sim, mtot_edf, htot_sim, htot_edf);
      if (m >= 16) {
        EXPECT_NEAR(mtot_edf / mtot_sim, 1.0, 0.3) << alpha << " " << m;
        EXPECT_NEAR(htot_edf / htot_sim, 1.0, 0.3) << alpha << " " << m;
      } else {
        EXPECT_LE(mtot_edf, 1.1 * mtot_sim) << alpha << " " << m;
        EXPECT_LE(htot_edf, 1.1 * htot_sim) << alpha << " " << m;
      }
    }
  }
}

TEST(Theo1, MatchesTheDefinition) {
  const auto x = random_walk(300, 9, 0.2);
  for (std::size_t m : {2u, 10u, 64u, 298u}) {
    const VarianceTerm t = theo1var(x, m, 2.0);
    EXPECT_EQ(t.n, (x.size() - m) * (m / 2));
    EXPECT_NEAR(t.var, direct_theo1(x, m) / 4.0, 1e-10 * t.var) << m;
  }
  EXPECT_EQ(theo1var(x, 11, 1.0).n, 0u);  // odd factors are not defined
  const auto p = cubecal::theo1(x, 2.0, DataType::phase, parse_tau_grid("octave"));
  ASSERT_FALSE(p.empty());
  EXPECT_EQ(p.front().m, 2u);
  EXPECT_DOUBLE_EQ(p.front().tau, 0.75 * 2 / 2.0);
}

// Theo1 is an unbiased estimator of AVAR at tau = 0.75 m tau0 for white FM,
// and its EDF (SP 1065) is checked here for white PM and white FM: the
// sample EDF 2 mean^2 / var of Theo1 over seeded runs against the formula.
TEST(Theo1, WhiteFmUnbiasedAndEdfBySimulation) {
  constexpr int kRuns = 600;
  constexpr std::size_t kN = 501;
  std::mt19937_64 g(77);
  std::normal_distribution<double> w(0.0, 1.0);
  for (int alpha : {2, 0}) {
    for (std::size_t m : {10u, 40u, 160u}) {
      std::vector<double> v;
      std::vector<double> x(kN);
      double avar_sum = 0;
      for (int r = 0; r < kRuns; ++r) {
        double acc = 0;
        for (std::size_t i = 0; i < kN; ++i) {
          const double e = w(g);
          x[i] = alpha == 2 ? e : acc;
          acc += e;
        }
        v.push_back(theo1var(x, m, 1.0).var);
        avar_sum += alpha == 0 ? oavar(x, 3 * m / 4, 1.0).var : 0.0;
      }
      const double mean = std::accumulate(v.begin(), v.end(), 0.0) / kRuns;
      double var = 0;
      for (double t : v) var += (t - mean) * (t - mean);
      var /= kRuns - 1;
      const double edf_sim = 2 * mean * mean / var, edf = edf_theo1(alpha, m, kN);
      std::printf("  Theo1 alpha %d m %3zu: EDF simulated %.1f, SP 1065 %.1f\n", alpha, m, edf_sim, edf);
      // The sample variance of 600 near-chi-squared values: relative sd
      // ~6 %; the formula is a fit within a few per cent.
      EXPECT_NEAR(edf_sim / edf, 1.0, 0.2) << "alpha " << alpha << " m " << m;
      if (alpha == 0) {
        // White FM of unit frequency variance: AVAR = 1 / tau at tau = 0.75 m
        // (an integer here): Theo1's mean within 4 sd of its mean over the runs.
        const double tau = 0.75 * static_cast<double>(m);
        EXPECT_NEAR(mean * tau, 1.0, 4.0 * std::sqrt(2.0 / (edf * kRuns))) << m;
        EXPECT_NEAR(avar_sum / kRuns * tau, 1.0, 0.1) << m;
      }
    }
  }
}

TEST(TheoBr, RatioIsTheMeanAvarOverTheo1) {
  const auto& x = phase_dat();
  const double r = theobr_ratio(x);
  double sum = 0;
  const std::size_t last = x.size() / 6 - 3;  // floor(N/6 - 3), N = 1001
  for (std::size_t i = 0; i <= last; ++i) sum += oavar(x, 9 + 3 * i, 1.0).var / direct_theo1(x, 12 + 4 * i);
  EXPECT_NEAR(r, sum / static_cast<double>(last + 1), 1e-12);
  std::vector<double> big(StabilityRecord::kTheobrMaxPoints + 1, 0.0);
  big[5] = 1.0;
  EXPECT_THROW(StabilityRecord(big, DataType::phase, 1.0, Stat::theobr), std::invalid_argument);
}

// Stable32's MTOT and HTOT intervals of a second record: the "Sr87" record
// (1253 phase points, tau0 = 2.5 s) of AllanToolkit's test assets
// (tests/assets/Sr87/phase/{octave,decade}/{mtotdev,htotdev}.txt, made with
// Stable32), whose types reach flicker and random-walk FM. The interval of
// the printed deviation with our EDF at N = 1253, the type Stable32 printed,
// within 1e-3 of its Min/Max: MTOT below m = 10 (MDEV's EDF), HTOT below
// m = 16 (SP 1065 Table 5) and from m = 16 on (the rows alpha 0 and -1 of
// Howe et al.'s table, and flicker PM: Table 5 + 2, as TOTDEV's); TOTDEV
// (phase/{octave,decade}/totdev.txt: SP 1065 Table 11 for white, flicker and
// random-walk FM, Table 5 + 2 for flicker PM at m = 100). Left out: MTOT from
// m = 10 on (Stable32's own coefficients).
TEST(Stable32Intervals, SecondRecordMtotAndHtot) {
  struct RefRow {
    Stat stat;
    std::size_t m;
    int alpha;
    double lo, dev, hi;
  };
  constexpr std::size_t kN = 1253;
  const RefRow rows[] = {
      {Stat::mtotdev, 1, -1, 6.2540e-17, 6.3842e-17, 6.5230e-17},
      {Stat::mtotdev, 2, -2, 6.4501e-17, 6.6538e-17, 6.8782e-17},
      {Stat::mtotdev, 4, -1, 7.1559e-17, 7.4419e-17, 7.7655e-17},
      {Stat::mtotdev, 8, 0, 6.6183e-17, 6.9877e-17, 7.4272e-17},
      {Stat::htotdev, 1, -1, 8.0946e-17, 8.2651e-17, 8.4469e-17},
      {Stat::htotdev, 2, -2, 7.5923e-17, 7.8025e-17, 8.0313e-17},
      {Stat::htotdev, 4, -1, 8.8264e-17, 9.1349e-17, 9.4785e-17},
      {Stat::htotdev, 8, 0, 8.5090e-17, 8.8938e-17, 9.3364e-17},
      {Stat::htotdev, 10, 0, 8.1805e-17, 8.5915e-17, 9.0718e-17},
      {Stat::htotdev, 16, 0, 7.8591e-17, 8.3165e-17, 8.8649e-17},
      {Stat::htotdev, 20, 0, 7.5569e-17, 8.0481e-17, 8.6500e-17},
      {Stat::htotdev, 32, 0, 6.4085e-17, 6.9376e-17, 7.6241e-17},
      {Stat::htotdev, 40, 0, 5.8634e-17, 6.4044e-17, 7.1295e-17},
      {Stat::htotdev, 64, 0, 4.8613e-17, 5.4288e-17, 6.2567e-17},
      {Stat::htotdev, 128, 0, 3.4607e-17, 4.0350e-17, 5.0403e-17},
      {Stat::htotdev, 200, -1, 2.2752e-17, 2.8300e-17, 4.1983e-17},
      {Stat::htotdev, 256, 0, 1.8034e-17, 2.2308e-17, 3.2500e-17},
      {Stat::htotdev, 400, -1, 1.1419e-17, 1.5213e-17, 3.1436e-17},
      {Stat::htotdev, 100, 1, 4.4525e-17, 4.7680e-17, 5.1617e-17},
      {Stat::totdev, 1, -1, 8.8689e-17, 9.0304e-17, 9.2011e-17},
      {Stat::totdev, 2, -2, 8.6445e-17, 8.8930e-17, 9.1644e-17},
      {Stat::totdev, 4, -1, 1.0156e-16, 1.0523e-16, 1.0932e-16},
      {Stat::totdev, 8, 0, 9.7585e-17, 1.0195e-16, 1.0697e-16},
      {Stat::totdev, 100, 1, 4.2698e-17, 4.5724e-17, 4.9499e-17},
      {Stat::totdev, 200, -1, 2.0582e-17, 2.5261e-17, 3.5911e-17},
      {Stat::totdev, 256, 0, 1.7362e-17, 2.1255e-17, 2.9986e-17},
      {Stat::totdev, 400, -1, 1.5759e-17, 2.0492e-17, 3.6551e-17},
      {Stat::totdev, 512, 0, 1.4893e-17, 1.9264e-17, 3.3449e-17},
  };
  double worst = 0;
  for (const RefRow& r : rows) {
    const Interval ci = chi2_interval(r.dev, edf_for(r.stat, r.alpha, r.m, kN), 0.683);
    const double e = std::max(rel(ci.lo, r.lo), rel(ci.hi, r.hi));
    EXPECT_LE(e, 1e-3) << to_string(r.stat) << " m " << r.m << ": [" << ci.lo << ", " << ci.hi << "]";
    worst = std::max(worst, e);
  }
  std::printf("  Stable32's MTOT, HTOT and TOTDEV intervals of the Sr87 record (%zu rows): worst %.2e\n",
              std::size(rows), worst);
}

// ---------------------------------------------------------------------------
// The command line: every statistic by name, JSON without intervals for the
// time-interval errors, the names in --help.

const std::string kPhaseDat = shared_data("stable32/phasedat/PHASE.DAT");

TEST(Cli, EveryNewStatisticThroughDevJson) {
  struct Want {
    const char* stat;
    double af, tau, dev;  // a row of a Stable32 table
    bool intervals;
  };
  // HTOT: bias-corrected by default, as Stable32 (phase_dat_htotdev_octave.txt).
  const Want wants[] = {
      {"tierms", 4, 4, 5.7044e-01, false},  {"mtie", 1, 1, 5.0597e-01, false},   {"mtotdev", 4, 4, 9.4613e-02, true},
      {"ttotdev", 4, 4, 2.1850e-01, true},  {"htotdev", 4, 4, 1.4252e-01, true}, {"theo1", 16, 12, 8.5040e-02, true},
      {"theobr", 16, 12, 6.6025e-02, true},
  };
  for (const Want& w : wants) {
    const auto r = test::run_cubecal("dev " + kPhaseDat + " --type phase --rate 1 --stat " + w.stat + " --taus " +
                                     std::to_string(w.tau) + " --format json");
    ASSERT_EQ(r.code, 0) << w.stat << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["stat"], w.stat);
    const auto& c = j["columns"][0];
    ASSERT_EQ(c["dev"].size(), 1u) << w.stat;
    EXPECT_EQ(c["af"][0].get<double>(), w.af) << w.stat;
    EXPECT_NEAR(c["tau"][0].get<double>(), w.tau, 1e-12) << w.stat;
    EXPECT_LE(rel(c["dev"][0].get<double>(), w.dev), 1e-4) << w.stat;
    EXPECT_EQ(c.contains("lo"), w.intervals) << w.stat;
    EXPECT_EQ(j["ci"].is_null(), !w.intervals) << w.stat;
  }
  const auto help = test::run_cubecal("dev --help");
  for (const char* name : {"tierms", "mtie", "mtotdev", "ttotdev", "htotdev", "theo1", "theobr"})
    EXPECT_NE(help.out.find(name), std::string::npos) << name;
}

// TOTDEV's bias correction (SP 1065: TOTVAR / AVAR = 1 - a tau/T, a = 0.750
// for random-walk FM, T = 1000 s): on by default with intervals, as Stable32;
// --no-bias-correction and a run without noise type (--no-ci) give the plain
// estimator, Stable32's all-tau value of PHASE.DAT at AF 256 (8.2053e-03 is
// its AF 499; the AF 256 row of the octave table: 1.3369e-02).
TEST(Cli, TotdevBiasCorrection) {
  auto dev_at_256 = [](const std::string& flags) {
    const auto r = test::run_cubecal("dev " + kPhaseDat + " --type phase --rate 1 --stat totdev --taus 256 " + flags +
                                     " --format json");
    EXPECT_EQ(r.code, 0) << flags << ": " << r.err;
    return r.code == 0 ? nlohmann::json::parse(r.out)["columns"][0]["dev"][0].get<double>() : 0.0;
  };
  const double plain = dev_at_256("--alpha -2 --no-bias-correction");
  EXPECT_LE(rel(plain, 1.3369e-02), 1e-4);
  const double factor = 1.0 / std::sqrt(1.0 - 0.75 * 256.0 / 1000.0);
  EXPECT_NEAR(dev_at_256("--alpha -2"), plain * factor, plain * 1e-12);
  EXPECT_NEAR(dev_at_256("--alpha -2 --bias-correction"), plain * factor, plain * 1e-12);
  EXPECT_NEAR(dev_at_256("--alpha -1"), plain / std::sqrt(1.0 - 256.0 / (3.0 * std::log(2.0)) / 1000.0), plain * 1e-12);
  EXPECT_EQ(dev_at_256("--alpha -2 --no-ci"), plain);
  EXPECT_EQ(dev_at_256("--alpha 0"), plain);  // white FM: no bias
  const auto both = test::run_cubecal("dev " + kPhaseDat +
                                      " --type phase --rate 1 --stat totdev --bias-correction --no-bias-correction");
  EXPECT_TRUE(test::one_error_line(both)) << both.err;
}

TEST(Cli, BiasCorrectionOption) {
  // Stable32 1.53's bias-corrected MTOT of PHASE.DAT at AF 4 (white FM).
  const auto r = test::run_cubecal("dev " + kPhaseDat +
                                   " --type phase --rate 1 --stat mtotdev --taus 4 --bias-correction --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_LE(rel(j["columns"][0]["dev"][0].get<double>(), 1.1074e-01), 1e-4);
}

// ---------------------------------------------------------------------------
// Stable32's own data files: the header says the type, tau and scaling.

std::string stable32_header(const std::string& type, const std::string& tau, std::size_t points,
                            const std::string& addend = "0.000000e+00",
                            const std::string& multiplier = "1.000000e+00") {
  return "File: C:\\Data\\RECORD.DAT\nDate: 12/17/20 10:48:15\nType: " + type + "\nPoints: " + std::to_string(points) +
         "\nTau: " + tau + "\nAddend: " + addend + "\nMultiplier: " + multiplier +
         "\nTag Scale: 8.640000e+04\nTag Offset: 0.000000e+00\n# Header End\n";
}

std::string values_text(const std::vector<double>& v) {
  std::string out;
  char buf[40];
  for (const double x : v) {
    std::snprintf(buf, sizeof buf, "%.17g\n", x);
    out += buf;
  }
  return out;
}

// Every row of a Stable32 table against `dev FILE --stat STAT --taus TAUS`.
void expect_table(const std::string& file, const std::string& stat, const std::string& table, double tau0) {
  const auto rows = read_rows(shared_data(table));
  ASSERT_FALSE(rows.empty());
  std::string taus;
  for (const Row& r : rows) {
    if (!taus.empty()) taus += ',';
    taus += std::to_string(static_cast<double>(r.af) * tau0);
  }
  const auto r = test::run_cubecal("dev " + file + " --stat " + stat + " --taus " + taus + " --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = nlohmann::json::parse(r.out)["columns"][0];
  ASSERT_EQ(c["af"].size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    SCOPED_TRACE(table + " AF " + std::to_string(rows[k].af));
    EXPECT_EQ(c["af"][k].get<double>(), static_cast<double>(rows[k].af));
    EXPECT_LE(rel(c["tau"][k].get<double>(), rows[k].tau), 5e-5);
    EXPECT_EQ(c["n"][k].get<double>(), rows[k].n);
    EXPECT_LE(rel(c["dev"][k].get<double>(), rows[k].dev), 1e-4);
    if (rows[k].lo > 0) {
      EXPECT_LE(rel(c["lo"][k].get<double>(), rows[k].lo), 1e-3);
      EXPECT_LE(rel(c["hi"][k].get<double>(), rows[k].hi), 1e-3);
    }
  }
}

class Stable32Dat : public test::TempDirTest {};

// PHASE.DAT as Stable32 writes it: read without --type or --rate, the
// octave OADEV table of Stable32 (values, intervals) reproduced.
TEST_F(Stable32Dat, PhaseFromTheHeader) {
  const std::vector<double>& x = phase_dat();
  const std::string file = write("PHASE.DAT", stable32_header("Phase", "1.000000e+00", x.size()) + values_text(x));
  expect_table(file, "oadev", "stable32/phasedat/phase_dat_oadev_octave.txt", 1.0);
  expect_table(file, "totdev", "stable32/phasedat/phase_dat_totdev.txt", 1.0);
}

// Frequency with tau 42 s, stored as (y - Addend) / Multiplier: the header's
// scaling restores y (value * Multiplier + Addend), its Tau gives the taus.
TEST_F(Stable32Dat, FrequencyScaledByTheHeader) {
  const std::vector<double> y = read_column(shared_data("stable32/pink_frequency/pink_frequency.txt"));
  std::vector<double> stored(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) stored[i] = (y[i] - 3.0e-6) / 1.0e-9;
  const std::string file =
      write("PINK.DAT", stable32_header("Frequency", "4.200000e+01", y.size(), "3.000000e-06", "1.000000e-09") +
                            values_text(stored));
  expect_table(file, "oadev", "stable32/pink_frequency/oadev.txt", 42.0);
  expect_table(file, "mdev", "stable32/pink_frequency/mdev.txt", 42.0);
}

// What the header says is not overridden silently, and a header that cannot
// be read is an error at its line.
TEST_F(Stable32Dat, ContradictionsAndBadHeadersAreRefused) {
  const std::vector<double>& x = phase_dat();
  const std::string file = write("PHASE.DAT", stable32_header("Phase", "1.000000e+00", x.size()) + values_text(x));
  for (const char* flags : {"--rate 2", "--type freq"}) {
    const auto r = test::run_cubecal("dev " + file + " " + flags);
    EXPECT_TRUE(test::one_error_line(r)) << flags << ": " << r.err;
    EXPECT_NE(r.err.find("header"), std::string::npos) << r.err;
  }
  // Its header is read whole: --stream says so (not "no sampling rate").
  const auto streamed = test::run_cubecal("dev " + file + " --stream");
  EXPECT_TRUE(test::one_error_line(streamed)) << streamed.err;
  EXPECT_NE(streamed.err.find("Stable32"), std::string::npos) << streamed.err;
  // The same rate and type as the header's are accepted.
  EXPECT_EQ(test::run_cubecal("dev " + file + " --rate 1 --type phase").code, 0);
  const std::string bad_type = write("TYPE.DAT", stable32_header("Voltage", "1.000000e+00", x.size()) + values_text(x));
  const auto t = test::run_cubecal("dev " + bad_type);
  EXPECT_TRUE(test::one_error_line(t)) << t.err;
  EXPECT_NE(t.err.find("TYPE.DAT:3:"), std::string::npos) << t.err;
  const std::string short_file =
      write("SHORT.DAT", stable32_header("Phase", "1.000000e+00", x.size() + 5) + values_text(x));
  const auto p = test::run_cubecal("dev " + short_file);
  EXPECT_TRUE(test::one_error_line(p)) << p.err;
  EXPECT_NE(p.err.find("Points"), std::string::npos) << p.err;
  const std::string no_end = write("NOEND.DAT", "File: x\nType: Phase\n1.0\n2.0\n3.0\n");
  const auto e = test::run_cubecal("dev " + no_end);
  EXPECT_TRUE(test::one_error_line(e)) << e.err;
  EXPECT_NE(e.err.find("Header End"), std::string::npos) << e.err;
}

}  // namespace
}  // namespace cubecal
