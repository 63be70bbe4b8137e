// The front door (stats/deviation.hpp): one call per statistic gives
// Stable32's numbers on its own grid, and the same points as the engine the
// CLI runs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/stats/deviation.hpp"
#include "stable32_table.hpp"

namespace cubecal {
namespace {

using test::read_column;
using test::read_stable32;
using test::shared_data;

struct Table {
  Stat stat;
  const char* file;
};

// PHASE.DAT (phase data, tau0 = 1 s) against Stable32's octave tables: the
// grid, n and the deviation to the table's 5 digits, and the confidence
// bounds to 1e-3 where the noise type agrees (all rows of these tables).
TEST(FrontDoor, EveryStatisticMatchesStable32OnItsOctaveGrid) {
  const std::vector<double> x = read_column(shared_data("stable32/phasedat/PHASE.DAT"));
  ASSERT_FALSE(x.empty());
  const Table tables[] = {
      {Stat::adev, "phase_dat_adev_octave.txt"},     {Stat::oadev, "phase_dat_oadev_octave.txt"},
      {Stat::mdev, "phase_dat_mdev_octave.txt"},     {Stat::tdev, "phase_dat_tdev_octave.txt"},
      {Stat::hdev, "phase_dat_hdev_octave.txt"},     {Stat::ohdev, "phase_dat_ohdev_octave.txt"},
      {Stat::totdev, "phase_dat_totdev_octave.txt"},
  };
  for (const auto& t : tables) {
    SCOPED_TRACE(t.file);
    const auto rows = read_stable32(shared_data(std::string("stable32/phasedat/") + t.file));
    ASSERT_FALSE(rows.empty());
    const auto pts = deviation(t.stat, x, 1.0, DataType::phase);
    ASSERT_EQ(pts.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      EXPECT_EQ(pts[i].m, rows[i].af);
      EXPECT_EQ(pts[i].n, rows[i].n);
      EXPECT_NEAR(pts[i].dev / rows[i].dev, 1.0, 1e-4) << "af " << rows[i].af;
      if (rows[i].lo > 0 && pts[i].alpha == rows[i].alpha) {
        EXPECT_NEAR(pts[i].interval.lo / rows[i].lo, 1.0, 1e-3) << "af " << rows[i].af;
        EXPECT_NEAR(pts[i].interval.hi / rows[i].hi, 1.0, 1e-3) << "af " << rows[i].af;
      }
    }
  }
}

// The named calls are the statistic they name, and agree with the parallel
// pipeline point for point (same grid, n, deviation, alpha, EDF, bounds).
TEST(FrontDoor, NamedCallsEqualThePipeline) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  std::vector<double> y(20000);
  double walk = 0.0;
  for (double& v : y) {
    walk += 0.01 * n01(rng);
    v = n01(rng) + walk;
  }
  using Fn = std::vector<StabilityPoint> (*)(std::span<const double>, double, DataType, const TauGrid&,
                                             const StabilityOptions&);
  const std::pair<Stat, Fn> calls[] = {{Stat::adev, adev},    {Stat::oadev, oadev}, {Stat::mdev, mdev},
                                       {Stat::tdev, tdev},    {Stat::hdev, hdev},   {Stat::ohdev, ohdev},
                                       {Stat::totdev, totdev}};
  TauGrid grid;
  grid.kind = TauGrid::Kind::log;
  grid.per_decade = 5;
  for (const auto& [stat, fn] : calls) {
    SCOPED_TRACE(std::string(to_string(stat)));
    const auto pts = fn(y, 50.0, DataType::freq, grid, {});
    pipeline::DevRequest req;
    req.stat = stat;
    req.grid = grid;
    req.threads = 2;
    const auto ref = pipeline::run_dev({"y"}, {y}, 50.0, req).channels.at(0).points;
    ASSERT_EQ(pts.size(), ref.size());
    ASSERT_GT(pts.size(), 10u);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      EXPECT_EQ(pts[i].m, ref[i].m);
      EXPECT_EQ(pts[i].n, ref[i].n);
      EXPECT_DOUBLE_EQ(pts[i].tau, ref[i].tau);
      EXPECT_DOUBLE_EQ(pts[i].dev, ref[i].dev);
      EXPECT_EQ(pts[i].alpha, ref[i].alpha);
      EXPECT_DOUBLE_EQ(pts[i].edf, ref[i].edf);
      EXPECT_DOUBLE_EQ(pts[i].interval.lo, ref[i].interval.lo);
      EXPECT_DOUBLE_EQ(pts[i].interval.hi, ref[i].interval.hi);
    }
  }
}

// A linear frequency ramp R t has sigma_y(tau) = R tau / sqrt(2) exactly.
TEST(FrontDoor, RampHasTheClosedFormAllanDeviation) {
  const double R = 1e-3, rate = 4.0;
  std::vector<double> y(4000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = R * static_cast<double>(i) / rate;
  StabilityOptions no_intervals;
  no_intervals.intervals = false;
  const auto pts = oadev(y, rate, DataType::freq, parse_tau_grid("decade"), no_intervals);
  ASSERT_GE(pts.size(), 6u);
  for (const auto& p : pts) {
    EXPECT_NEAR(p.dev / (R * p.tau / std::sqrt(2.0)), 1.0, 1e-9) << "tau " << p.tau;
    EXPECT_EQ(p.interval.lo, 0.0);  // no intervals asked for
  }
}

TEST(FrontDoor, RefusesWhatCannotBeComputed) {
  const std::vector<double> y(100, 1.0);
  EXPECT_THROW(oadev(y, 0.0), UsageError);
  EXPECT_THROW(oadev(y, -1.0), UsageError);
  EXPECT_THROW(oadev(y, std::nan("")), UsageError);
  EXPECT_THROW(oadev(std::vector<double>(3, 1.0), 1.0), UsageError);  // no tau fits
  EXPECT_THROW(oadev(y, 1.0, DataType::freq, parse_tau_grid("1000")), UsageError);
  std::vector<double> bad(y);
  bad[17] = std::nan("");
  EXPECT_THROW(oadev(bad, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace cubecal
