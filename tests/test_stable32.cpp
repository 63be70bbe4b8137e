// Every statistic against the Stable32 result tables in ../shared/data/stable32:
// tau and n exact, deviation within 1e-4 relative, confidence bounds within
// 1e-3 relative where cubecal identifies the same noise type as Stable32.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "stable32_table.hpp"

namespace cubecal {
namespace {

using test::read_column;
using test::read_stable32;
using test::shared_data;

struct Input {
  const char* file;
  DataType type;
  double tau0;
  double offset;  // subtracted before scaling (ocxo: 1e7 Hz)
  double scale;   // divided after (ocxo: 1e7 Hz)
};

const Input kPhaseDat{"stable32/phasedat/PHASE.DAT", DataType::phase, 1.0, 0.0, 1.0};
const Input kPink42{"stable32/pink_frequency/pink_frequency.txt", DataType::freq, 42.0, 0.0, 1.0};
const Input kPink1{"stable32/pink_frequency/pink_frequency.txt", DataType::freq, 1.0, 0.0, 1.0};
const Input kOcxo{"stable32/ocxo/ocxo_frequency.txt", DataType::freq, 1.0, 1e7, 1e7};

struct Case {
  const char* table;
  const Input* input;
  Stat stat;
  bool octave;  // table is a complete octave run (check the grid itself)
  // The ocxo octave tables were computed by Stable32 from a copy of the data
  // normalized to f/f0 ~ 1.0 ("ocxo_frequency.001", Average = 1.000000e+00),
  // and Stable32 lost digits on it: its own ADEV and OADEV at AF 1, which are
  // the same quantity, differ there by 4.9e-4 (7.6106e-11 vs 7.6143e-11).
  // For those tables the deviation is checked against the table Stable32
  // computed from the exact offsets ("ocxo_frequency.003", the all-tau run)
  // at every AF the two share, and the confidence bounds are checked as
  // ratios to the deviation (what the EDF determines).
  const char* exact_table = nullptr;
};

std::vector<double> load(const Input& in) {
  auto v = read_column(shared_data(in.file));
  for (double& x : v) x = (x - in.offset) / in.scale;
  return v;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// Worst errors per table, printed for the validation notes.
struct Summary {
  std::string table;
  double worst_dev = 0, worst_ci = 0, worst_ci_forced = 0;
  std::size_t rows = 0, ci_rows = 0, alpha_match = 0;
};
class Stable32 : public ::testing::TestWithParam<Case> {};

TEST_P(Stable32, MatchesTable) {
  const Case& c = GetParam();
  const auto rows = read_stable32(shared_data(c.table));
  ASSERT_FALSE(rows.empty()) << c.table;
  const auto data = load(*c.input);
  const StabilityRecord rec(data, c.input->type, c.input->tau0, c.stat);

  std::vector<test::Stable32Row> exact;
  if (c.exact_table) exact = read_stable32(shared_data(c.exact_table));
  auto exact_dev = [&](std::size_t af) -> double {
    for (const auto& r : exact)
      if (r.af == af) return r.dev;
    return 0.0;
  };

  Summary s{c.table};
  std::size_t exact_checked = 0;
  double worst_vs_rounded = 0.0;
  for (const auto& row : rows) {
    ASSERT_LE(row.af, rec.max_m()) << c.table << " AF " << row.af << " beyond cubecal's limit";
    const StabilityPoint p = rec.evaluate(row.af, {});
    SCOPED_TRACE(std::string(c.table) + " AF " + std::to_string(row.af));
    EXPECT_EQ(p.n, row.n);
    EXPECT_LE(rel(p.tau, row.tau), 5e-5);  // tau printed with 5 digits
    // Stable32's printed bounds scaled to cubecal's deviation: identical when
    // the deviations agree, EDF-only comparison when the reference is rounded.
    double ref_lo = row.lo, ref_hi = row.hi;
    if (c.exact_table) {
      worst_vs_rounded = std::max(worst_vs_rounded, rel(p.dev, row.dev));
      ref_lo *= p.dev / row.dev;
      ref_hi *= p.dev / row.dev;
      const double ex = exact_dev(row.af);
      if (ex > 0) {
        const double e = rel(p.dev, ex);
        EXPECT_LE(e, 1e-4) << "dev " << p.dev << " vs exact-data table " << ex;
        s.worst_dev = std::max(s.worst_dev, e);
        ++exact_checked;
      }
    } else {
      const double e = rel(p.dev, row.dev);
      EXPECT_LE(e, 1e-4) << "dev " << p.dev << " vs " << row.dev;
      s.worst_dev = std::max(s.worst_dev, e);
    }
    ++s.rows;
    if (row.lo > 0 && row.hi > 0) {
      ++s.ci_rows;
      // With Stable32's own noise type the EDF and chi-squared bounds must match.
      StabilityOptions forced;
      forced.alpha = row.alpha;
      const StabilityPoint q = rec.evaluate(row.af, forced);
      const double ef = std::max(rel(q.lo, ref_lo), rel(q.hi, ref_hi));
      EXPECT_LE(ef, 1e-3) << "forced alpha " << row.alpha << ": [" << q.lo << ", " << q.hi
                          << "] vs [" << ref_lo << ", " << ref_hi << "] edf " << q.edf;
      s.worst_ci_forced = std::max(s.worst_ci_forced, ef);
      // Where 30 or more averaged points remain, Stable32 identifies the
      // noise by the lag-1 autocorrelation, and so must cubecal, exactly.
      // Below that (the last one to three AFs of a run) Stable32 falls back
      // on rules cubecal reproduces only in part; those rows are reported.
      const std::size_t points = (rec.phase_points() - 1) / row.af;
      if (points >= 30) {
        EXPECT_EQ(p.alpha, row.alpha) << "lag-1 ACF noise identification differs";
      }
      if (p.alpha == row.alpha) {
        ++s.alpha_match;
        const double ec = std::max(rel(p.lo, ref_lo), rel(p.hi, ref_hi));
        EXPECT_LE(ec, 1e-3) << "[" << p.lo << ", " << p.hi << "] vs [" << ref_lo << ", " << ref_hi
                            << "]";
        s.worst_ci = std::max(s.worst_ci, ec);
      } else {
        std::printf("  noise id differs: %s AF %zu alpha %d (Stable32 %d)\n", c.table, row.af,
                    p.alpha, row.alpha);
      }
    }
  }
  if (c.octave) {
    const auto ms = averaging_factors(parse_tau_grid("octave"), rec.max_m(), c.input->tau0);
    std::vector<std::size_t> want;
    for (const auto& r : rows) want.push_back(r.af);
    EXPECT_EQ(ms, want) << "octave grid differs from Stable32's";
  }
  std::printf("  %-45s rows %3zu  worst dev %.2e  CI rows %2zu  alpha match %2zu  worst CI %.2e"
              "  worst CI (Stable32 alpha) %.2e\n",
              c.table, s.rows, s.worst_dev, s.ci_rows, s.alpha_match, s.worst_ci,
              s.worst_ci_forced);
  if (c.exact_table) {
    EXPECT_GE(exact_checked, 4u) << "too few AFs shared with the exact-data table";
    std::printf("  %-45s deviation vs this (rounded-input) table: worst %.2e; %zu AFs checked"
                " against %s\n", c.table, worst_vs_rounded, exact_checked, c.exact_table);
  }
}

const Case kCases[] = {
    {"stable32/phasedat/phase_dat_adev.txt", &kPhaseDat, Stat::adev, false},
    {"stable32/phasedat/phase_dat_adev_octave.txt", &kPhaseDat, Stat::adev, true},
    {"stable32/phasedat/phase_dat_oadev.txt", &kPhaseDat, Stat::oadev, false},
    {"stable32/phasedat/phase_dat_oadev_octave.txt", &kPhaseDat, Stat::oadev, true},
    {"stable32/phasedat/phase_dat_mdev.txt", &kPhaseDat, Stat::mdev, false},
    {"stable32/phasedat/phase_dat_mdev_octave.txt", &kPhaseDat, Stat::mdev, true},
    {"stable32/phasedat/phase_dat_tdev.txt", &kPhaseDat, Stat::tdev, false},
    {"stable32/phasedat/phase_dat_tdev_octave.txt", &kPhaseDat, Stat::tdev, true},
    {"stable32/phasedat/phase_dat_hdev.txt", &kPhaseDat, Stat::hdev, false},
    {"stable32/phasedat/phase_dat_hdev_octave.txt", &kPhaseDat, Stat::hdev, true},
    {"stable32/phasedat/phase_dat_ohdev.txt", &kPhaseDat, Stat::ohdev, false},
    {"stable32/phasedat/phase_dat_ohdev_octave.txt", &kPhaseDat, Stat::ohdev, true},
    {"stable32/phasedat/phase_dat_totdev.txt", &kPhaseDat, Stat::totdev, false},
    {"stable32/phasedat/phase_dat_totdev_octave.txt", &kPhaseDat, Stat::totdev, true},
    {"stable32/pink_frequency/adev.txt", &kPink42, Stat::adev, false},
    {"stable32/pink_frequency/oadev.txt", &kPink42, Stat::oadev, false},
    {"stable32/pink_frequency/mdev.txt", &kPink42, Stat::mdev, false},
    {"stable32/pink_frequency/tdev.txt", &kPink42, Stat::tdev, false},
    {"stable32/pink_frequency/hdev.txt", &kPink42, Stat::hdev, false},
    {"stable32/pink_frequency/ohdev.txt", &kPink42, Stat::ohdev, false},
    {"stable32/pink_frequency/totdev_alpha0.txt", &kPink42, Stat::totdev, false},
    {"stable32/pink_frequency/s32_oadev_octave.txt", &kPink1, Stat::oadev, true},
    {"stable32/ocxo/adev_octave.txt", &kOcxo, Stat::adev, true,
     "stable32/ocxo/stable32_adev_alltau.txt"},
    {"stable32/ocxo/oadev_octave.txt", &kOcxo, Stat::oadev, true,
     "stable32/ocxo/stable32_oadev_alltau.txt"},
    {"stable32/ocxo/mdev_octave.txt", &kOcxo, Stat::mdev, true,
     "stable32/ocxo/stable32_mdev_alltau.txt"},
    {"stable32/ocxo/tdev_octave.txt", &kOcxo, Stat::tdev, true,
     "stable32/ocxo/stable32_tdev_alltau.txt"},
    {"stable32/ocxo/hdev_octave.txt", &kOcxo, Stat::hdev, true,
     "stable32/ocxo/stable32_hdev_alltau.txt"},
    {"stable32/ocxo/ohdev_octave.txt", &kOcxo, Stat::ohdev, true,
     "stable32/ocxo/stable32_ohdev_alltau.txt"},
    {"stable32/ocxo/totdev_octave.txt", &kOcxo, Stat::totdev, true,
     "stable32/ocxo/stable32_totdev_alltau.txt"},
    {"stable32/ocxo/stable32_adev_alltau.txt", &kOcxo, Stat::adev, false},
    {"stable32/ocxo/stable32_oadev_alltau.txt", &kOcxo, Stat::oadev, false},
    {"stable32/ocxo/stable32_mdev_alltau.txt", &kOcxo, Stat::mdev, false},
    {"stable32/ocxo/stable32_tdev_alltau.txt", &kOcxo, Stat::tdev, false},
    {"stable32/ocxo/stable32_hdev_alltau.txt", &kOcxo, Stat::hdev, false},
    {"stable32/ocxo/stable32_ohdev_alltau.txt", &kOcxo, Stat::ohdev, false},
    {"stable32/ocxo/stable32_totdev_alltau.txt", &kOcxo, Stat::totdev, false},
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.table;
  s = s.substr(s.find('/') + 1);
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Tables, Stable32, ::testing::ValuesIn(kCases), case_name);

// NIST SP 1065 Table 31 (the NBS14 1000-point set), at tau = 1, 10, 100 s.
struct Nbs14 {
  Stat stat;
  double dev[3];
  std::size_t n[3];
};

TEST(Nbs14, ThousandPointTable) {
  const auto y = read_column(shared_data("stable32/nbs14/generated_nbs14_1000point_frequency.txt"));
  ASSERT_EQ(y.size(), 1000u);
  // SP 1065 values; n as Stable32 counts them.
  const Nbs14 ref[] = {
      {Stat::adev, {2.922319e-01, 9.965736e-02, 3.897804e-02}, {999, 99, 9}},
      {Stat::oadev, {2.922319e-01, 9.159953e-02, 3.241343e-02}, {999, 981, 801}},
      {Stat::mdev, {2.922319e-01, 6.172376e-02, 2.170921e-02}, {999, 972, 702}},
      {Stat::tdev, {1.687202e-01, 3.563623e-01, 1.253382e+00}, {999, 972, 702}},
      {Stat::hdev, {2.943883e-01, 1.052754e-01, 3.910860e-02}, {998, 98, 8}},
      {Stat::ohdev, {2.943883e-01, 9.581083e-02, 3.237638e-02}, {998, 971, 701}},
      {Stat::totdev, {2.922319e-01, 9.134743e-02, 3.406530e-02}, {999, 999, 999}},
  };
  const std::size_t ms[] = {1, 10, 100};
  double worst = 0;
  for (const auto& r : ref) {
    const StabilityRecord rec(y, DataType::freq, 1.0, r.stat);
    for (int k = 0; k < 3; ++k) {
      const auto p = rec.evaluate(ms[k], {});
      SCOPED_TRACE(std::string(to_string(r.stat)) + " m=" + std::to_string(ms[k]));
      EXPECT_EQ(p.n, r.n[k]);
      const double e = rel(p.dev, r.dev[k]);
      EXPECT_LE(e, 1e-6);  // reference printed to 7 digits
      worst = std::max(worst, e);
    }
  }
  std::printf("  nbs14 1000-point: worst dev error %.2e\n", worst);
}

}  // namespace
}  // namespace cubecal
