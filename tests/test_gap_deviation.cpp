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
  while (in >> token)
    v.push_back(token == "nan" || token == "NaN" ? std::numeric_limits<double>::quiet_NaN() : std::stod(token));
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
    EXPECT_TRUE(b[j].interval.lo <= a[j].interval.hi && a[j].interval.lo <= b[j].interval.hi) << "m " << ms[j];
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

// A tau at which a channel has no whole term has no point (no n = 0 row
// with a zero deviation), as the gap-free path leaves out a tau that no
// segment holds: gx misses one sample in every 100, so no 2m samples in a
// row are whole from m = 50 on, while gy, whole, keeps the grid's taus. A
// channel without a whole term at any tau is refused in one line.
TEST_F(GapsSkipCli, ATauWithoutAWholeTermIsLeftOut) {
  const std::size_t n = 1000;
  std::mt19937_64 engine(15);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> gx(n), gy(n);
  std::ostringstream text;
  text.precision(17);
  text << "gx,gy\n";
  for (std::size_t k = 0; k < n; ++k) {
    gx[k] = k % 100 == 50 ? std::nan("") : normal(engine);
    gy[k] = normal(engine);
    if (std::isnan(gx[k]))
      text << ',' << gy[k] << '\n';  // an empty field
    else
      text << gx[k] << ',' << gy[k] << '\n';
  }
  const std::string f = write("holes.csv", text.str());
  const auto r = test::run_cubecal("dev " + f + " --rate 10 --taus octave --gaps skip --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& jx = j["columns"][0];
  const auto& jy = j["columns"][1];
  ASSERT_EQ(jx["name"], "gx");
  ASSERT_EQ(jy["name"], "gy");
  // gy has no missing sample: every factor of the grid, each with N + 1 - 2m terms.
  ASSERT_GE(jy["af"].size(), 3u);
  for (std::size_t p = 0; p < jy["af"].size(); ++p)
    EXPECT_EQ(jy["n"][p].get<std::size_t>(), n + 1 - 2 * jy["af"][p].get<std::size_t>());
  // gx: the factors of gy's grid at which a term (2m whole samples) exists, counted here.
  std::vector<std::size_t> want_af, want_n;
  for (const auto& a : jy["af"]) {
    const std::size_t m = a.get<std::size_t>();
    std::size_t terms = 0;
    for (std::size_t i = 0; i + 2 * m <= n; ++i) {
      bool whole = true;
      for (std::size_t s = i; s < i + 2 * m && whole; ++s) whole = !std::isnan(gx[s]);
      terms += whole ? 1 : 0;
    }
    if (terms > 0) {
      want_af.push_back(m);
      want_n.push_back(terms);
    }
  }
  ASSERT_LT(want_af.size(), jy["af"].size()) << "the record must have a tau without a whole term";
  EXPECT_EQ(jx["af"].get<std::vector<std::size_t>>(), want_af);
  EXPECT_EQ(jx["n"].get<std::vector<std::size_t>>(), want_n);
  for (const auto& col : {jx, jy})
    for (const char* key : {"dev", "edf", "lo", "hi"})
      for (const auto& v : col[key]) EXPECT_GT(v.get<double>(), 0.0) << col["name"] << " " << key;
  // The CSV and the table have the same rows: none for gx's taus without a term.
  const auto csv = test::run_cubecal("dev " + f + " --rate 10 --taus octave --gaps skip --format csv");
  ASSERT_EQ(csv.code, 0) << csv.err;
  std::istringstream lines(csv.out);
  std::string line;
  std::size_t gx_rows = 0, gy_rows = 0;
  while (std::getline(lines, line)) {
    gx_rows += line.rfind("gx,", 0) == 0 ? 1 : 0;
    gy_rows += line.rfind("gy,", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(gx_rows, want_af.size());
  EXPECT_EQ(gy_rows, jy["af"].size());
  const auto table = test::run_cubecal("dev " + f + " --rate 10 --taus octave --gaps skip");
  ASSERT_EQ(table.code, 0) << table.err;
  const std::size_t gx_at = table.out.find("gx "), gy_at = table.out.find("gy ");
  ASSERT_TRUE(gx_at != std::string::npos && gy_at != std::string::npos && gx_at < gy_at) << table.out;
  std::istringstream gx_table(table.out.substr(gx_at, gy_at - gx_at));
  std::size_t table_rows = 0;
  while (std::getline(gx_table, line)) {
    std::istringstream fields(line);
    std::size_t af = 0, terms = 0;
    double tau = 0.0;
    if (!(fields >> af >> tau >> terms)) continue;  // the title and the header
    EXPECT_GT(terms, 0u) << line;
    ++table_rows;
  }
  EXPECT_EQ(table_rows, want_af.size());

  // Every other sample missing: no two whole samples in a row, no term at any tau.
  std::string sparse = "gx,gy\n";
  for (std::size_t k = 0; k < 40; ++k) sparse += k % 2 == 0 ? "1.5,1\n" : ",2\n";
  const auto none = test::run_cubecal("dev " + write("sparse.csv", sparse) + " --rate 10 --gaps skip");
  EXPECT_EQ(none.code, 2);
  // After the note on the missing samples, one error line.
  const std::size_t error_at = none.err.find("cubecal: error: ");
  ASSERT_NE(error_at, std::string::npos) << none.err;
  EXPECT_EQ(none.err.find('\n', error_at), none.err.size() - 1) << none.err;
  EXPECT_NE(none.err.find("column gx: no OADEV term without a missing sample", error_at), std::string::npos)
      << none.err;
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
  EXPECT_NE(r.err.find("(a missing sample: --gaps skip leaves it out of the OADEV terms (dev, davar)"),
            std::string::npos)
      << r.err;
  const std::string nan = write("nan.csv", "t,gx\n0,1\n0.1,2\n0.2,NaN\n0.3,4\n0.4,5\n0.5,1\n0.6,2\n");
  r = test::run_cubecal("dev " + nan);  // NaN too, with the way to keep it
  EXPECT_TRUE(test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find(nan + ":4:5: NaN is not accepted in column 2 'gx' (a missing sample: --gaps skip"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(test::run_cubecal("dev " + nan + " --gaps skip").code, 0);
}

// The commands and statistics that need every sample refuse --gaps skip in
// one line that names what to do instead; davar takes it, and a record cut
// at a gap by --gaps split points davar to it.
TEST_F(GapsSkipCli, OtherCommandsAndStatisticsRefuseItInOneLine) {
  const std::string ok = write("ok.csv", "t,gx_dps\n0,1\n0.1,2\n0.2,\n0.3,4\n0.4,5\n0.5,1\n0.6,2\n0.7,1\n");
  for (const std::string command : {"psd", "analyze", "turnon"}) {
    const auto r = test::run_cubecal(command + " " + ok + " --gaps skip --unit deg/s");
    EXPECT_TRUE(test::one_error_line(r)) << command << ": " << r.err;
    EXPECT_NE(r.err.find("--gaps skip: this command needs every sample (missing samples are skipped by dev and "
                         "davar, for OADEV)"),
              std::string::npos)
        << command << ": " << r.err;
    // The shared help of --gaps names the commands that take skip.
    const auto help = test::run_cubecal(command + " --help");
    EXPECT_EQ(help.code, 0) << command;
    EXPECT_NE(help.out.find("dev and davar also take skip (empty fields, NaN and gaps of whole periods are missing "
                            "samples"),
              std::string::npos)
        << command << ": " << help.out;
    EXPECT_NE(r.err.find("--gaps split"), std::string::npos) << command << ": " << r.err;
  }
  const auto dev_help = test::run_cubecal("dev --help");
  EXPECT_NE(dev_help.out.find("dev and davar also take skip"), std::string::npos) << dev_help.out;
  for (const std::string stat : {"mdev", "hdev", "totdev", "theo1", "mtie"}) {
    const auto r = test::run_cubecal("dev " + ok + " --gaps skip --stat " + stat);
    EXPECT_TRUE(test::one_error_line(r)) << stat << ": " << r.err;
    EXPECT_NE(r.err.find("OADEV only"), std::string::npos) << stat << ": " << r.err;
    EXPECT_NE(r.err.find("--gaps split to analyze the contiguous pieces with " + stat), std::string::npos) << r.err;
  }
  const auto davar = test::run_cubecal("davar " + ok + " --gaps skip --window 4 --format csv");
  EXPECT_EQ(davar.code, 0) << davar.err;
  EXPECT_NE(davar.err.find("1 missing sample(s)"), std::string::npos) << davar.err;
  const std::string gap = write("gap.csv", "t,gx\n0,1\n0.1,2\n0.4,3\n0.5,4\n0.6,5\n0.7,1\n0.8,2\n0.9,1\n1.0,1\n");
  const auto split = test::run_cubecal("davar " + gap + " --gaps split --window 4");
  EXPECT_TRUE(test::one_error_line(split)) << split.err;
  EXPECT_NE(split.err.find("read it with --gaps skip"), std::string::npos) << split.err;
  EXPECT_EQ(test::run_cubecal("davar " + gap + " --gaps skip --window 4").code, 0);
}

}  // namespace
}  // namespace cubecal
