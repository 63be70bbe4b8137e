// Issue 10 item 6, "the first hour": what a new user meets on the real data
// in ../shared/data and on small records: units taken from the column names
// (or a request for --unit), accelerometer terms in navigation units, which B
// to trust, hints for the common mistakes, --gnuplot, and the cosmetic
// defects (doubled slashes, fixed six decimals, nine-digit rates, a garbled
// header).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using cubecal::test::one_error_line;
using Result = cubecal::test::CliRun;
Result run(const std::string& args) { return cubecal::test::run_cubecal(args); }

const std::string kData = CUBECAL_SHARED_DATA;

std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class FirstHour : public cubecal::test::TempDirTest {
 protected:
  // A white-noise record with a time column, columns named as given, at
  // `period` seconds per sample.
  std::string record(const std::string& name, const std::string& header, int columns, double period = 0.1,
                     int rows = 3000) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    std::string s = header + "\n";
    char buf[64];
    for (int k = 0; k < rows; ++k) {
      std::snprintf(buf, sizeof buf, "%.5f", k * period);
      s += buf;
      for (int c = 0; c < columns; ++c) {
        std::snprintf(buf, sizeof buf, ",%.6f", 0.01 * g(rng));
        s += buf;
      }
      s += "\n";
    }
    return write(name, s);
  }
};

// --- 1. units from the column names ------------------------------------------

TEST_F(FirstHour, AnalyzeTakesTheUnitsFromTheColumnSuffixes) {
  const auto r = run("analyze " + kData + "/imu/adis16405/run1.csv.gz --taus log:5");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.err,
                  "units from the column names: gyro_x_dps,gyro_y_dps,gyro_z_dps deg/s; "
                  "acc_x_g,acc_y_g,acc_z_g g (--unit overrides)"))
      << r.err;
  EXPECT_TRUE(has(r.out, "gyro_x_dps [deg/s, rate]")) << r.out;
  EXPECT_TRUE(has(r.out, "deg/sqrt(h)"));
  EXPECT_FALSE(has(r.out, "counts"));
}

TEST_F(FirstHour, AnalyzeAsksForTheUnitInsteadOfCounts) {
  const std::string f = record("plain.csv", "t,gx,gy", 2);
  const auto r = run("analyze " + f);
  EXPECT_TRUE(one_error_line(r)) << r.code << " " << r.err;
  EXPECT_TRUE(has(r.err, "cubecal: error: " + f + ": no unit in the names of columns gx, gy: give --unit (")) << r.err;
  EXPECT_TRUE(has(r.err, "deg/s|rad/s")) << r.err;
  EXPECT_TRUE(has(r.err, "_dps")) << r.err;
  EXPECT_TRUE(r.out.empty());
  // Only the columns without a unit are named.
  const std::string mixed = record("mixed.csv", "t,gx_dps,ax", 2);
  const auto m = run("analyze " + mixed);
  EXPECT_TRUE(one_error_line(m)) << m.err;
  EXPECT_TRUE(has(m.err, "no unit in the name of column ax:")) << m.err;
  // An explicit --unit counts is still honoured.
  const auto c = run("analyze " + f + " --unit counts");
  EXPECT_EQ(c.code, 0) << c.err;
  EXPECT_TRUE(has(c.out, "gx [counts, generic]")) << c.out;
  EXPECT_FALSE(has(c.err, "units from the column names"));
}

TEST_F(FirstHour, TurnonAndCompareInferOrAskToo) {
  const std::string a = record("a.csv", "t,gx_rads", 1), b = record("b.csv", "t,gx_rads", 1);
  const auto t = run("turnon " + a + " " + b);
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_TRUE(has(t.err, "units from the column names: gx_rads rad/s")) << t.err;
  EXPECT_TRUE(has(t.out, "rad/s")) << t.out;
  const std::string p = record("p.csv", "t,gx", 1), q = record("q.csv", "t,gx", 1);
  for (const std::string cmd : {"turnon", "compare"}) {
    const auto r = run(cmd + " " + p + " " + q);
    EXPECT_TRUE(one_error_line(r)) << cmd << ": " << r.err;
    EXPECT_TRUE(has(r.err, "no unit in the name of column gx")) << r.err;
  }
  // Runs whose names announce different units.
  const std::string d = record("d.csv", "t,gx_dps", 1);
  const auto r = run("compare " + a + " " + d);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_TRUE(has(r.err, "do not announce the units")) << r.err;
}

// --- 2 and 3. accelerometer terms, which B to trust -----------------------------

TEST_F(FirstHour, AccelerometerTermsAndTheBiasVerdictOnTheAdis) {
  const std::string out = path("adis");
  const auto r = run("analyze " + kData + "/imu/adis16405/run1.csv.gz --columns acc_x_g --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "m/s/sqrt(h) = ")) << r.out;
  EXPECT_TRUE(has(r.out, " ug/sqrt(Hz)")) << r.out;
  EXPECT_TRUE(has(r.out, " ug = ")) << r.out;
  EXPECT_TRUE(has(r.out, " mg")) << r.out;
  // The read-off's 442 ug against the fit's 926 ug on a curve the fit misses by 62 %.
  EXPECT_TRUE(has(r.out, "  B         read-off ")) << r.out;
  EXPECT_TRUE(has(r.out, "use the read-off: the five power laws miss this curve")) << r.out;
  const auto j = nlohmann::json::parse(slurp(out + "/analysis.json"));
  const auto& n = j.at("channels").at(0).at("noise");
  const auto& vrw = n.at("accelerometer").at("read_off").at("velocity_random_walk");
  ASSERT_EQ(vrw.size(), 2u);
  EXPECT_EQ(vrw.at(0).at("unit"), "m/s/sqrt(h)");
  EXPECT_EQ(vrw.at(1).at("unit"), "ug/sqrt(Hz)");
  // Closed form from the data-unit N (g*sqrt(h)): ug/sqrt(Hz) = N * 60 * 1e6.
  const double N_g_sqrt_h = n.at("arw").at("value").get<double>();
  EXPECT_NEAR(vrw.at(1).at("value").get<double>(), N_g_sqrt_h * 60.0 * 1e6, 1e-9 * N_g_sqrt_h * 60e6);
  EXPECT_NEAR(vrw.at(0).at("value").get<double>(), N_g_sqrt_h * 3600.0 * 9.80665, 1e-12);
  const auto& b = n.at("accelerometer").at("read_off").at("bias_instability");
  EXPECT_NEAR(b.at(0).at("value").get<double>(), n.at("bias_instability").at("value").get<double>() * 1e6, 1e-6);
  EXPECT_EQ(n.at("bias_instability_choice").at("trust"), "read_off");
  EXPECT_TRUE(n.at("bias_instability_choice").at("beyond_combined_sigma").get<bool>());
  // The file still loads (report reads it back).
  EXPECT_EQ(run("report " + out).code, 0);
}

// --- 4. hints for the common mistakes -------------------------------------------

TEST_F(FirstHour, PreambleNotSkippedSuggestsTheRightSkipRows) {
  const std::string f = kData + "/imu/mpu6050/imu_static_test.csv";
  const auto r = run("analyze " + f + " --rate 100 --unit counts");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_TRUE(has(r.err, "the table seems to start on line 5 after a preamble: add --skip-rows 4")) << r.err;
  EXPECT_EQ(run("analyze " + f + " --rate 100 --unit counts --skip-rows 4 --taus log:3").code, 0);
  // A preamble with as many fields as the data: the field count is wrong first.
  const std::string g = write("pre.csv", "logger v2,2024\nsite,lab\nt,gx_dps\n0,1\n0.1,2\n0.2,3\n0.3,2\n");
  const auto p = run("dev " + g + " --rate 10");
  EXPECT_TRUE(one_error_line(p)) << p.err;
  EXPECT_TRUE(has(p.err, "add --skip-rows 2")) << p.err;
}

TEST_F(FirstHour, NoSamplingRateNamesTheFile) {
  const std::string f = write("norate.csv", "gx_dps,gy_dps\n1,2\n3,4\n5,6\n");
  for (const std::string cmd : {"dev", "analyze"}) {
    const auto r = run(cmd + " " + f);
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_TRUE(has(r.err, "cubecal: error: " + f + ": no sampling rate")) << r.err;
    EXPECT_TRUE(has(r.err, "--rate HZ or --time-col NAME")) << r.err;
  }
}

TEST_F(FirstHour, FieldNormFarFromTheDataSaysSo) {
  const std::string f = kData + "/mag/cubesat-adcs/meas_for_mag_calib.csv";
  const auto r = run("calibrate mag " + f + " --field-norm 50 --allow-partial");
  EXPECT_TRUE(has(r.err, "warning: " + f + ": --field-norm 50 is ")) << r.err;
  EXPECT_TRUE(has(r.err, "give the field norm in the unit of the values")) << r.err;
  const auto ok = run("calibrate mag " + f + " --field-norm 1 --method twostep");
  EXPECT_FALSE(has(ok.err, "warning")) << ok.err;
}

// --- 5. --gnuplot PATH -------------------------------------------------------------

TEST_F(FirstHour, GnuplotPathThatDoesNotExistIsAClearError) {
  const std::string rec = record("g.csv", "t,gx_dps,gy_dps,gz_dps", 3);
  const std::string bad = path("no/such/gnuplot");
  const std::string want = "cubecal: error: --gnuplot: no executable gnuplot at " + bad + " (give the path";
  const std::vector<std::string> cmds{
      "analyze " + rec + " --out " + path("o1") + " --report --gnuplot " + bad,
      "turnon " + rec + " " + rec + " --report " + path("o2") + " --gnuplot " + bad,
      "compare " + rec + " " + rec + " --report " + path("o3") + " --gnuplot " + bad,
      "calibrate mag " + kData + "/mag/cubesat-adcs/meas_for_mag_calib.csv --report " + path("o4") + " --gnuplot " +
          bad,
      "demo --hours 0.5 --out " + path("o5") + " --gnuplot " + bad,
  };
  for (const auto& c : cmds) {
    const auto r = run(c);
    EXPECT_TRUE(one_error_line(r)) << c << "\n" << r.err;
    EXPECT_TRUE(has(r.err, want)) << c << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(path("o1") + "/analysis.json")) << "refused before the work";
}

TEST_F(FirstHour, GnuplotPathIsTheOneThatRuns) {
  if (!fs::exists("/usr/bin/gnuplot")) GTEST_SKIP() << "gnuplot not installed";
  const std::string log = path("calls.log");
  const std::string wrapper =
      write("my-gnuplot", "#!/bin/sh\necho called >> '" + log + "'\nexec /usr/bin/gnuplot \"$@\"\n");
  ::chmod(wrapper.c_str(), 0755);
  const std::string rec = record("g.csv", "t,gx_dps", 1);
  const auto a = run("analyze " + rec + " --out " + path("res1") + "/ --report --gnuplot " + wrapper);
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_TRUE(has(slurp(log), "called"));
  // 6: no doubled slash when --out ends with one.
  EXPECT_FALSE(has(a.err, "//")) << a.err;
  EXPECT_TRUE(has(a.err, "plots in " + path("res1") + "/plots/)")) << a.err;
  fs::remove(log);
  const auto t = run("turnon " + rec + " " + rec + " --report " + path("rep") + "/ --gnuplot " + wrapper);
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_TRUE(has(slurp(log), "called"));
  EXPECT_FALSE(has(t.err, "//")) << t.err;
}

// --- 6. cosmetic defects -------------------------------------------------------------

TEST_F(FirstHour, NumbersPrintedAsPeopleReadThem) {
  // Time stamps every 0.09999 s: the rate 10.0010001 Hz is shown as 10.001 Hz.
  const std::string f = record("r10.csv", "t,gx_dps", 1, 0.09999);
  const auto d = run("dev " + f);
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_TRUE(has(d.out, "samples at 10.001 Hz")) << d.out;
  EXPECT_FALSE(has(d.out, "10.0010001"));
  const auto a = run("analyze " + f);
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_TRUE(has(a.out, "samples at 10.001 Hz")) << a.out;
  // White noise has no Gauss-Markov hump: the search range is said in plain numbers.
  EXPECT_TRUE(has(a.out, "no Gauss-Markov correlation time between 0.2 s and ")) << a.out;
  EXPECT_FALSE(has(a.out, "0.200000")) << a.out;
}

TEST_F(FirstHour, MagTableHeaderWithAndWithoutUnit) {
  const std::string f = kData + "/mag/cubesat-adcs/meas_for_mag_calib.csv";
  const auto r = run("calibrate mag " + f + " --method twostep");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "\n|h| - F:  before mean")) << r.out;
  EXPECT_FALSE(has(r.out, "|h| - F, :"));
  const auto u = run("calibrate mag " + f + " --method twostep --unit uT --field-norm 1");
  ASSERT_EQ(u.code, 0) << u.err;
  EXPECT_TRUE(has(u.out, "\n|h| - F [uT]:  before mean")) << u.out;
}

TEST_F(FirstHour, DemoOutputDirectoryWithTrailingSlash) {
  const auto r = run("demo --hours 0.5 --out " + path("d") + "/");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "Output in " + path("d") + "/:")) << r.out;
  EXPECT_FALSE(has(r.out + r.err, "//")) << r.out << r.err;
}

}  // namespace
