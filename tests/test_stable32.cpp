// Every statistic against the Stable32 result tables in ../shared/data/stable32:
// tau and n exact, deviation within 1e-4 relative, confidence bounds within
// 1e-3 relative where cubecal identifies the same noise type as Stable32.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <utility>
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
const Input kCs5071a{"stable32/cs5071a/5071A_phase.txt.gz", DataType::phase, 1.0, 0.0, 1.0};

struct Case {
  const char* table;
  const Input* input;
  Stat stat;
  bool octave;  // table is a complete octave run (check the grid itself)
  // The ocxo octave tables were computed by Stable32 from a copy of the data
  // normalized to f/f0 ~ 1.0 ("ocxo_frequency.001", Average = 1.000000e+00):
  // its overlapping statistics take the running sum of those values as the
  // phase, which rounds at ~1e-12 a step (OADEV at AF 1: 7.6143e-11, against
  // 7.6106e-11 from the offsets). Here the deviation is checked against the
  // table Stable32 computed from the exact offsets ("ocxo_frequency.003", the
  // all-tau run, alpha 0: no bias correction) at every AF the two share, and
  // the confidence bounds as ratios to the deviation (what the EDF
  // determines); Stable32Ocxo.OctaveTablesFromTheNormalizedCopy rebuilds that
  // phase and checks every row's value.
  const char* exact_table = nullptr;
  // A table Stable32 made with the noise type fixed (its header and every row
  // say so): compared with that alpha forced, never with cubecal's own.
  std::optional<int> fixed_alpha = std::nullopt;
};

std::vector<double> load(const Input& in) {
  auto v = read_column(shared_data(in.file));
  for (double& x : v) x = (x - in.offset) / in.scale;
  return v;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// Rows whose noise type is not a reference for cubecal's, each with the
// check (in reference_fault_shown) that shows why.
//
// Stable32's TOTDEV octave run of PHASE.DAT says white FM (0) at AF 128,
// where its all-tau run of the same data says flicker PM (1) at AF 127 and
// 129; all three are identified anew (below half the largest AF, 499), and
// the B1 ratio and R(n) at 127, 128 and 129 fall in the same classes. AF 256
// carries AF 128's type in both programs. Every other statistic's octave
// run agrees with its all-tau run there.
struct ReferenceFault {
  const char* table;
  std::size_t af;
  const char* all_tau;  // Stable32's all-tau table of the same statistic and data
};
const ReferenceFault kReferenceFaults[] = {
    {"stable32/phasedat/phase_dat_totdev_octave.txt", 128, "stable32/phasedat/phase_dat_totdev.txt"},
    {"stable32/phasedat/phase_dat_totdev_octave.txt", 256, "stable32/phasedat/phase_dat_totdev.txt"},
};

const ReferenceFault* reference_fault(const std::string& table, std::size_t af) {
  for (const auto& f : kReferenceFaults)
    if (table == f.table && af == f.af) return &f;
  return nullptr;
}

// Whether the listed fault is borne out: the row differs from cubecal, and
// cubecal's type equals the one Stable32's all-tau run gives at the
// neighbouring AFs below and above.
bool reference_fault_shown(const ReferenceFault& f, const test::Stable32Row& row, const StabilityPoint& p) {
  const auto all = read_stable32(shared_data(f.all_tau));
  const test::Stable32Row* below = nullptr;
  const test::Stable32Row* above = nullptr;
  for (const auto& r : all) {
    if (r.af < f.af) below = &r;
    if (r.af > f.af && !above) above = &r;
  }
  return below && above && below->alpha == p.alpha && above->alpha == p.alpha && row.alpha != p.alpha;
}

// What one table gives: worst errors, and the counts of the agreement table.
struct Summary {
  std::string table;
  double worst_dev = 0, worst_ci = 0, worst_ci_forced = 0;
  std::size_t rows = 0;
  std::size_t alpha_rows = 0, alpha_match = 0;  // rows where cubecal identifies the noise
  std::size_t ci_rows = 0, ci_1e3 = 0, ci_1e2 = 0;
  std::size_t faults = 0, ci_faults = 0;  // rows of kReferenceFaults (shown)
  std::vector<std::string> differences;   // one line per alpha disagreement
};

// Compares one table row by row; with `check`, every per-row target is
// asserted (the agreement table only counts).
Summary compare(const Case& c, bool check) {
  Summary s;
  s.table = c.table;
  const auto rows = read_stable32(shared_data(c.table));
  if (check) {
    EXPECT_FALSE(rows.empty()) << c.table;
  }
  const auto data = load(*c.input);
  const StabilityRecord rec(data, c.input->type, c.input->tau0, c.stat);

  std::vector<test::Stable32Row> exact;
  if (c.exact_table) exact = read_stable32(shared_data(c.exact_table));
  auto exact_dev = [&](std::size_t af) -> double {
    for (const auto& r : exact)
      if (r.af == af) return r.dev;
    return 0.0;
  };

  std::size_t exact_checked = 0;
  double worst_vs_rounded = 0.0;
  // The table's AFs are one run, as Stable32 made it (the noise type beyond
  // half the largest AF follows the run: StabilityRecord::carry_types).
  std::vector<std::size_t> afs;
  for (const auto& row : rows)
    if (row.af <= rec.max_m()) afs.push_back(row.af);
  StabilityOptions opt;
  opt.alpha = c.fixed_alpha;
  const std::vector<StabilityPoint> run = rec.evaluate(afs, opt);
  // The exact-data table was made with alpha 0: the plain estimator.
  StabilityOptions plain = opt;
  plain.bias_correction = BiasCorrection::off;
  const std::vector<StabilityPoint> plain_run = c.exact_table ? rec.evaluate(afs, plain) : run;
  std::size_t next = 0;
  for (const auto& row : rows) {
    if (check) {
      EXPECT_LE(row.af, rec.max_m()) << c.table << " AF " << row.af << " beyond cubecal's limit";
    }
    if (row.af > rec.max_m()) continue;
    const StabilityPoint& plain_p = plain_run[next];
    const StabilityPoint p = run[next++];
    SCOPED_TRACE(std::string(c.table) + " AF " + std::to_string(row.af));
    if (check) {
      EXPECT_EQ(p.n, row.n);
      EXPECT_LE(rel(p.tau, row.tau), 5e-5);  // tau printed with 5 digits
    }
    // Stable32's printed bounds scaled to cubecal's deviation: identical when
    // the deviations agree, EDF-only comparison when the reference is rounded.
    double ref_lo = row.lo, ref_hi = row.hi;
    if (c.exact_table) {
      worst_vs_rounded = std::max(worst_vs_rounded, rel(p.dev, row.dev));
      ref_lo *= p.dev / row.dev;
      ref_hi *= p.dev / row.dev;
      const double ex = exact_dev(row.af);
      if (ex > 0) {
        const double e = rel(plain_p.dev, ex);
        if (check) {
          EXPECT_LE(e, 1e-4) << "dev " << plain_p.dev << " vs exact-data table " << ex;
        }
        s.worst_dev = std::max(s.worst_dev, e);
        ++exact_checked;
      }
    } else {
      const double e = rel(p.dev, row.dev);
      if (check) {
        EXPECT_LE(e, 1e-4) << "dev " << p.dev << " vs " << row.dev;
      }
      s.worst_dev = std::max(s.worst_dev, e);
    }
    ++s.rows;
    // A listed fault of the reference is left out of the counts once its
    // check holds; a listed row whose check fails is a test failure.
    bool fault_row = false;
    if (const ReferenceFault* fault = reference_fault(c.table, row.af)) {
      fault_row = reference_fault_shown(*fault, row, p);
      if (check) {
        EXPECT_TRUE(fault_row) << "listed as a fault of the reference, but not shown to be one "
                                  "(cubecal alpha "
                               << p.alpha << ", Stable32 " << row.alpha << ")";
      }
      if (fault_row) {
        ++s.faults;
        if (row.lo > 0 && row.hi > 0) ++s.ci_faults;
      }
    }
    if (!c.fixed_alpha && !fault_row) {
      ++s.alpha_rows;
      const std::size_t points = (rec.phase_points() - 1) / row.af;
      if (p.alpha == row.alpha) {
        ++s.alpha_match;
      } else {
        s.differences.push_back(std::string(c.table) + " AF " + std::to_string(row.af) + " (" + std::to_string(points) +
                                " points): alpha " + std::to_string(p.alpha) + ", Stable32 " +
                                std::to_string(row.alpha));
      }
      // Where 30 or more averaged points remain, Stable32 identifies the
      // noise by the lag-1 autocorrelation, and so must cubecal, exactly.
      if (check && points >= 30) {
        EXPECT_EQ(p.alpha, row.alpha) << "lag-1 ACF noise identification differs";
      }
    }
    if (row.lo > 0 && row.hi > 0) {
      ++s.ci_rows;
      // With Stable32's own noise type the EDF and chi-squared bounds must match.
      StabilityOptions forced;
      forced.alpha = row.alpha;
      const StabilityPoint q = rec.evaluate(row.af, forced);
      const double ef = std::max(rel(q.interval.lo, ref_lo), rel(q.interval.hi, ref_hi));
      if (check) {
        EXPECT_LE(ef, 1e-3) << "forced alpha " << row.alpha << ": [" << q.interval.lo << ", " << q.interval.hi
                            << "] vs [" << ref_lo << ", " << ref_hi << "] edf " << q.edf;
      }
      s.worst_ci_forced = std::max(s.worst_ci_forced, ef);
      const double ec = std::max(rel(p.interval.lo, ref_lo), rel(p.interval.hi, ref_hi));
      if (!fault_row) {
        if (ec <= 1e-3) ++s.ci_1e3;
        if (ec <= 1e-2) ++s.ci_1e2;
        s.worst_ci = std::max(s.worst_ci, ec);
      }
      if (check && p.alpha == row.alpha) {
        EXPECT_LE(ec, 1e-3) << "[" << p.interval.lo << ", " << p.interval.hi << "] vs [" << ref_lo << ", " << ref_hi
                            << "]";
      }
    }
  }
  if (check && c.octave) {
    const auto ms = averaging_factors(parse_tau_grid("octave"), rec.max_m(), c.input->tau0);
    std::vector<std::size_t> want;
    for (const auto& r : rows) want.push_back(r.af);
    EXPECT_EQ(ms, want) << "octave grid differs from Stable32's";
  }
  if (check && c.exact_table) {
    EXPECT_GE(exact_checked, 4u) << "too few AFs shared with the exact-data table";
    std::printf(
        "  %-45s deviation vs this (rounded-input) table: worst %.2e; %zu AFs checked"
        " against %s\n",
        c.table, worst_vs_rounded, exact_checked, c.exact_table);
  }
  return s;
}

class Stable32 : public ::testing::TestWithParam<Case> {};

TEST_P(Stable32, MatchesTable) {
  const Summary s = compare(GetParam(), true);
  for (const auto& d : s.differences) std::printf("  noise id differs: %s\n", d.c_str());
  std::printf(
      "  %-45s rows %3zu  worst dev %.2e  alpha %zu/%zu  CI rows %2zu  worst CI %.2e"
      "  worst CI (Stable32 alpha) %.2e\n",
      s.table.c_str(), s.rows, s.worst_dev, s.alpha_match, s.alpha_rows, s.ci_rows, s.worst_ci, s.worst_ci_forced);
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
    // Made with the noise type fixed at alpha 0 (its name and every row say so).
    {"stable32/pink_frequency/totdev_alpha0.txt", &kPink42, Stat::totdev, false, nullptr, 0},
    {"stable32/pink_frequency/s32_oadev_octave.txt", &kPink1, Stat::oadev, true},
    {"stable32/ocxo/adev_octave.txt", &kOcxo, Stat::adev, true, "stable32/ocxo/stable32_adev_alltau.txt"},
    {"stable32/ocxo/oadev_octave.txt", &kOcxo, Stat::oadev, true, "stable32/ocxo/stable32_oadev_alltau.txt"},
    {"stable32/ocxo/mdev_octave.txt", &kOcxo, Stat::mdev, true, "stable32/ocxo/stable32_mdev_alltau.txt"},
    {"stable32/ocxo/tdev_octave.txt", &kOcxo, Stat::tdev, true, "stable32/ocxo/stable32_tdev_alltau.txt"},
    {"stable32/ocxo/hdev_octave.txt", &kOcxo, Stat::hdev, true, "stable32/ocxo/stable32_hdev_alltau.txt"},
    {"stable32/ocxo/ohdev_octave.txt", &kOcxo, Stat::ohdev, true, "stable32/ocxo/stable32_ohdev_alltau.txt"},
    {"stable32/ocxo/totdev_octave.txt", &kOcxo, Stat::totdev, true, "stable32/ocxo/stable32_totdev_alltau.txt"},
    {"stable32/ocxo/stable32_adev_alltau.txt", &kOcxo, Stat::adev, false},
    {"stable32/ocxo/stable32_oadev_alltau.txt", &kOcxo, Stat::oadev, false},
    {"stable32/ocxo/stable32_mdev_alltau.txt", &kOcxo, Stat::mdev, false},
    {"stable32/ocxo/stable32_tdev_alltau.txt", &kOcxo, Stat::tdev, false},
    {"stable32/ocxo/stable32_hdev_alltau.txt", &kOcxo, Stat::hdev, false},
    {"stable32/ocxo/stable32_ohdev_alltau.txt", &kOcxo, Stat::ohdev, false},
    // Made by Stable32 with the noise type fixed at alpha 0 (all 310 rows say 0,
    // where its OADEV run on the same data identifies -2 to 1).
    {"stable32/ocxo/stable32_totdev_alltau.txt", &kOcxo, Stat::totdev, false, nullptr, 0},
    {"stable32/cs5071a/adev_all.txt", &kCs5071a, Stat::adev, false},
    {"stable32/cs5071a/oadev_all.txt", &kCs5071a, Stat::oadev, false},
    {"stable32/cs5071a/mdev_all.txt", &kCs5071a, Stat::mdev, false},
    {"stable32/cs5071a/tdev_all.txt", &kCs5071a, Stat::tdev, false},
    {"stable32/cs5071a/hdev_all.txt", &kCs5071a, Stat::hdev, false},
    {"stable32/cs5071a/ohdev_all.txt", &kCs5071a, Stat::ohdev, false},
    {"stable32/cs5071a/totdev_all.txt", &kCs5071a, Stat::totdev, false},
    {"stable32/cs5071a/adev_decade.txt", &kCs5071a, Stat::adev, false},
    {"stable32/cs5071a/oadev_decade.txt", &kCs5071a, Stat::oadev, false},
    {"stable32/cs5071a/mdev_decade.txt", &kCs5071a, Stat::mdev, false},
    {"stable32/cs5071a/tdev_decade.txt", &kCs5071a, Stat::tdev, false},
    {"stable32/cs5071a/hdev_decade.txt", &kCs5071a, Stat::hdev, false},
    {"stable32/cs5071a/ohdev_decade.txt", &kCs5071a, Stat::ohdev, false},
    // Made by Stable32 with the noise type fixed at alpha 0 (every row says 0).
    {"stable32/cs5071a/totdev_decade.txt", &kCs5071a, Stat::totdev, false, nullptr, 0},
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.table;
  s = s.substr(s.find('/') + 1);
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Tables, Stable32, ::testing::ValuesIn(kCases), case_name);

// The agreement table of docs/validation.md, per dataset, and the targets
// over all of them: alpha agrees in at least 97 % of the rows where cubecal
// identifies the noise, and every interval is within 1e-2 of Stable32's.
TEST(Stable32Agreement, Table) {
  struct Total {
    std::size_t rows = 0, alpha_rows = 0, alpha_match = 0, ci_rows = 0, ci_1e3 = 0, ci_1e2 = 0;
    std::size_t faults = 0, ci_faults = 0;
  };
  std::map<std::string, Total> by_set;
  Total all;
  std::vector<std::string> differences;
  for (const Case& c : kCases) {
    const Summary s = compare(c, false);
    std::string set = s.table.substr(s.table.find('/') + 1);
    set = set.substr(0, set.find('/'));
    for (Total* t : {&by_set[set], &all}) {
      t->rows += s.rows;
      t->alpha_rows += s.alpha_rows;
      t->alpha_match += s.alpha_match;
      t->ci_rows += s.ci_rows;
      t->ci_1e3 += s.ci_1e3;
      t->ci_1e2 += s.ci_1e2;
      t->faults += s.faults;
      t->ci_faults += s.ci_faults;
    }
    differences.insert(differences.end(), s.differences.begin(), s.differences.end());
  }
  std::printf(
      "  | dataset | rows | faults of the reference | alpha agrees | rows with CI "
      "(faults) | CI within 1e-3 | CI within 1e-2 |\n"
      "  |---|---|---|---|---|---|---|\n");
  auto line = [](const std::string& name, const Total& t) {
    std::printf(
        "  | %s | %zu | %zu | %zu/%zu (%.2f %%) | %zu (%zu) | %zu | %zu |\n", name.c_str(), t.rows, t.faults,
        t.alpha_match, t.alpha_rows,
        100.0 * static_cast<double>(t.alpha_match) / static_cast<double>(std::max<std::size_t>(t.alpha_rows, 1)),
        t.ci_rows, t.ci_faults, t.ci_1e3, t.ci_1e2);
  };
  for (const auto& [name, t] : by_set) line(name, t);
  line("all", all);
  for (const auto& d : differences) std::printf("  noise id differs: %s\n", d.c_str());
  EXPECT_EQ(all.faults, std::size(kReferenceFaults)) << "a listed fault of the reference is not shown";
  // Every interval within 1e-2 of Stable32's, but the faults of the reference.
  // Every interval within 1e-3 of Stable32's, but the faults of the reference.
  EXPECT_EQ(all.ci_1e3, all.ci_rows - all.ci_faults) << "intervals further than 1e-3 from Stable32's";
  // Alpha: the target is 97 % of the rows. One row is off and not
  // explained: 5071A HDEV AF 53297 (10 averages), random-run FM (-4) in
  // Stable32, random-walk FM (-2) by the B1 ratio (printed above).
  const std::vector<std::string> known = {"stable32/cs5071a/hdev_all.txt AF 53297 (10 points): alpha -2, Stable32 -4"};
  EXPECT_EQ(differences, known);
  EXPECT_GE(static_cast<double>(all.alpha_match), 0.97 * static_cast<double>(all.alpha_rows));
}

// The ocxo octave tables of OADEV, OHDEV and TOTDEV, every row: the phase
// Stable32 takes from the normalized copy (the running double sum of f/1e7,
// values near 1; its MDEV and TDEV are not reproduced by it, and stay
// checked against the exact-data tables above), Stable32's noise type (it identified the type on
// the frequency values, where the rounding does not reach). TOTDEV's rows of
// flicker and random-walk FM (AF 16 to 1024) hold only with the TOTVAR bias
// correction, as Stable32 applies it (up to 1.2e-2 without).
TEST(Stable32Ocxo, OctaveTablesFromTheNormalizedCopy) {
  const std::vector<double> f = read_column(shared_data("stable32/ocxo/ocxo_frequency.txt"));
  std::vector<double> x(f.size() + 1, 0.0);
  double sum = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) x[i + 1] = sum += f[i] / 1e7;
  const std::pair<const char*, Stat> tables[] = {{"stable32/ocxo/oadev_octave.txt", Stat::oadev},
                                                 {"stable32/ocxo/ohdev_octave.txt", Stat::ohdev},
                                                 {"stable32/ocxo/totdev_octave.txt", Stat::totdev}};
  for (const auto& [table, stat] : tables) {
    const StabilityRecord rec(x, DataType::phase, 1.0, stat);
    const auto rows = read_stable32(shared_data(table));
    ASSERT_FALSE(rows.empty()) << table;
    double worst_dev = 0.0, worst_ci = 0.0;
    for (const auto& row : rows) {
      SCOPED_TRACE(std::string(table) + " AF " + std::to_string(row.af));
      StabilityOptions opt;
      opt.alpha = row.alpha;
      const StabilityPoint p = rec.evaluate(row.af, opt);
      EXPECT_EQ(p.n, row.n);
      const double e = rel(p.dev, row.dev);
      EXPECT_LE(e, 1e-4) << "dev " << p.dev << " vs " << row.dev;
      const double ec = std::max(rel(p.interval.lo, row.lo), rel(p.interval.hi, row.hi));
      EXPECT_LE(ec, 1e-3) << "[" << p.interval.lo << ", " << p.interval.hi << "] vs [" << row.lo << ", " << row.hi
                          << "]";
      worst_dev = std::max(worst_dev, e);
      worst_ci = std::max(worst_ci, ec);
    }
    std::printf("  %-35s (normalized copy) rows %2zu  worst dev %.2e  worst CI %.2e\n", table, rows.size(), worst_dev,
                worst_ci);
  }
}

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
