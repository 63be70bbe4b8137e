// OADEV with missing samples left out (stats/gap_deviation.hpp, `dev --gaps
// skip`): the definition term by term, the gap-free statistic when nothing
// is missing, AllanTools' gradev data with and without its gaps, and the
// reader turning empty fields, NaN and whole-period gaps into missing samples.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/stats/gap_deviation.hpp"
#include "cubecal/stats/stability.hpp"

namespace cubecal {
namespace {

const std::string kGradev = std::string(CUBECAL_SHARED_DATA) + "/allantools/gradev/";

std::vector<double> load(const std::string& path) {
  std::ifstream in(path);
  std::vector<double> v;
  std::string token;
  while (in >> token) v.push_back(token == "nan" || token == "NaN" ? std::numeric_limits<double>::quiet_NaN()
                                                                   : std::stod(token));
  return v;
}

std::vector<std::size_t> octave(std::size_t top) {
  std::vector<std::size_t> ms;
  for (std::size_t m = 1; m <= top; m *= 2) ms.push_back(m);
  return ms;
}

// Phase: the terms whose three points are there, as AllanTools' gradev sums them.
TEST(GapDeviation, PhaseTermsWithAllThreePoints) {
  const std::vector<double> x = load(kGradev + "y_gap.dat");
  ASSERT_EQ(x.size(), 1000u);
  ASSERT_EQ(missing_samples(x), 200u);
  StabilityOptions opt;
  opt.intervals = false;
  const auto ms = octave(256);
  const auto pts = oadev_skipping_missing(x, DataType::phase, 1.0, ms, opt);
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const std::size_t m = ms[j];
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i + 2 * m < x.size(); ++i) {
      const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
      if (std::isnan(d)) continue;
      sum += d * d;
      ++n;
    }
    ASSERT_EQ(pts[j].n, n) << "m " << m;
    EXPECT_NEAR(pts[j].dev, std::sqrt(sum / (2.0 * static_cast<double>(n))) / static_cast<double>(m),
                1e-13 * pts[j].dev)
        << "m " << m;
  }
}

// Frequency: a term counts when both of its m-averages are whole; then it is
// half the squared difference of the averages.
TEST(GapDeviation, FrequencyTermsWithWholeAverages) {
  std::mt19937_64 engine(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> y(5000);
  for (double& v : y) v = 1e-3 + normal(engine);
  for (const std::size_t k : {17u, 18u, 400u, 2500u, 2501u, 2502u, 4999u}) y[k] = std::nan("");
  StabilityOptions opt;
  opt.intervals = false;
  const std::vector<std::size_t> ms = {1, 3, 10, 64, 500};
  const auto pts = oadev_skipping_missing(y, DataType::freq, 0.5, ms, opt);
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const std::size_t m = ms[j];
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i + 2 * m <= y.size(); ++i) {
      double a = 0.0, b = 0.0;
      for (std::size_t k = 0; k < m; ++k) {
        a += y[i + k];
        b += y[i + m + k];
      }
      if (std::isnan(a) || std::isnan(b)) continue;
      const double d = (b - a) / static_cast<double>(m);
      sum += d * d / 2.0;
      ++n;
    }
    ASSERT_EQ(pts[j].n, n) << "m " << m;
    EXPECT_NEAR(pts[j].dev, std::sqrt(sum / static_cast<double>(n)), 1e-11 * pts[j].dev) << "m " << m;
  }
}

TEST(GapDeviation, NothingMissingIsOadev) {
  const std::vector<double> x = load(kGradev + "y.dat");
  const auto ms = octave(249);
  const auto got = oadev_skipping_missing(x, DataType::phase, 1.0, ms);
  const auto want = StabilityRecord(x, DataType::phase, 1.0, Stat::oadev).evaluate(ms, StabilityOptions{});
  for (std::size_t j = 0; j < ms.size(); ++j) {
    EXPECT_EQ(got[j].n, want[j].n);
    EXPECT_NEAR(got[j].dev, want[j].dev, 1e-12 * want[j].dev);
    EXPECT_EQ(got[j].alpha, want[j].alpha);  // identified on the whole record, which has no gap
    EXPECT_NEAR(got[j].edf, want[j].edf, 1e-9 * want[j].edf) << "m " << ms[j];
  }
}

// AllanTools' gradev test: its data with 200 of 1000 phase points missing
// give deviations close to those of the whole series (AllanTools asserts a
// log ratio below 1; here within 5 %, and each inside the whole series' 95 %
// interval widened by the gapped one's).
TEST(GapDeviation, AllanToolsGapDataStaysNearTheWholeSeries) {
  const std::vector<double> whole = load(kGradev + "y.dat");
  const std::vector<double> gapped = load(kGradev + "y_gap.dat");
  const auto ms = octave(128);
  StabilityOptions opt;
  opt.ci = 0.95;
  const auto a = oadev_skipping_missing(whole, DataType::phase, 1.0, ms, opt);
  const auto b = oadev_skipping_missing(gapped, DataType::phase, 1.0, ms, opt);
  for (std::size_t j = 0; j < ms.size(); ++j) {
    EXPECT_LT(std::abs(std::log(b[j].dev / a[j].dev)), 0.05) << "m " << ms[j];
    EXPECT_LT(b[j].n, a[j].n);
    EXPECT_TRUE(b[j].lo <= a[j].hi && a[j].lo <= b[j].hi) << "m " << ms[j];
  }
}

class GapsSkipCli : public test::TempDirTest {};

// Empty fields, NaN and a gap of whole periods in the time stamps are
// missing samples; the same record with the missing rows written out as NaN
// gives the same deviations.
TEST_F(GapsSkipCli, EmptyNanAndWholePeriodGapsAreMissingSamples) {
  std::mt19937_64 engine(8);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::ostringstream holes, filled;
  holes << "t,gx\n";
  filled << "t,gx\n";
  holes.precision(17);
  filled.precision(17);
  for (int k = 0; k < 3000; ++k) {
    const double t = 0.1 * k, v = normal(engine);
    if (k >= 1000 && k < 1005) {  // five rows not logged at all
      filled << t << ",nan\n";
      continue;
    }
    if (k == 200) {
      holes << t << ",\n";
      filled << t << ",NaN\n";
      continue;
    }
    if (k == 2999) {
      holes << t << ",nan\n";
      filled << t << ",nan\n";
      continue;
    }
    holes << t << ',' << v << '\n';
    filled << t << ',' << v << '\n';
  }
  const auto a = test::run_cubecal("dev " + write("holes.csv", holes.str()) + " --gaps skip --format json");
  const auto b = test::run_cubecal("dev " + write("filled.csv", filled.str()) + " --gaps skip --rate 10 --format json");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_NE(a.err.find("7 missing sample(s)"), std::string::npos) << a.err;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja["samples"], 3000);
  EXPECT_EQ(ja["columns"][0]["dev"], jb["columns"][0]["dev"]);
  EXPECT_EQ(ja["columns"][0]["n"], jb["columns"][0]["n"]);
  // AF 1: a missing sample k voids the terms starting at k-1 and k: two for
  // sample 200, six for the run 1000-1004, one for the last sample.
  EXPECT_EQ(ja["columns"][0]["n"][0], 2999 - (2 + 6 + 1));
}

TEST_F(GapsSkipCli, WhatCannotBeSkippedIsRefused) {
  const std::string jitter = write("jitter.csv", "t,gx\n0,1\n0.1,2\n0.25,3\n0.3,4\n0.4,5\n0.5,1\n");
  auto r = test::run_cubecal("dev " + jitter + " --gaps skip");
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find(jitter + ":4:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a whole number of periods"), std::string::npos) << r.err;

  const std::string no_time = write("no_time.csv", "t,gx\n0,1\n0.1,2\n,3\n0.3,4\n0.4,5\n0.5,1\n");
  r = test::run_cubecal("dev " + no_time + " --gaps skip");
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find(no_time + ":4:1: missing time stamp"), std::string::npos) << r.err;

  const std::string ok = write("ok.csv", "t,gx\n0,1\n0.1,2\n0.2,\n0.3,4\n0.4,5\n0.5,1\n0.6,2\n");
  r = test::run_cubecal("dev " + ok + " --gaps skip --stat mdev");
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("OADEV only"), std::string::npos) << r.err;
  r = test::run_cubecal("analyze " + ok + " --gaps skip --unit deg/s");
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  r = test::run_cubecal("dev " + ok + " --gaps skip --stream");
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  r = test::run_cubecal("dev " + ok);  // without skip an empty field is still an error at its place
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find(ok + ":4:5: empty field"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace cubecal
