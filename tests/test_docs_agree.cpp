// What the program says about itself agrees with what it does (issue 33,
// item 15): help that names every subcommand and every format a command
// reads, terms printed with their units, table headers that name the units of
// their columns, and calibrate temperature's coefficient unit taken from the
// column names as analyze takes it, never labelled counts by default. The
// numbers the docs quote are checked by scripts/check-doc-commands.py
// (ctest docs.commands).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

namespace {

using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The line of `text` that starts with `start` (after spaces), or "".
std::string line_starting(const std::string& text, const std::string& start) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find_first_not_of(' ');
    if (first != std::string::npos && line.compare(first, start.size(), start) == 0) return line;
  }
  return "";
}

// The first line of `text` holding `part`, or "".
std::string line_containing(const std::string& text, const std::string& part) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (has(line, part)) return line;
  return "";
}

class DocsAgree : public cubecal::test::TempDirTest {
 protected:
  // A gyro record of `hours` at 10 Hz in deg/s, seeded.
  std::string gyro_run(const std::string& name, int seed, double hours = 2.0) {
    const std::string f = path(name);
    const auto r = run_cubecal("simulate --preset sport-gyro --rate 10 --duration " + std::to_string(hours) +
                               "h --seed " + std::to_string(seed) + " --out " + f);
    EXPECT_EQ(r.code, 0) << r.err;
    return f;
  }
  // t, the columns named `names`, temp: a bias of 0.01 unit/degC under a
  // sinusoidal temperature.
  std::string temperature_record(const std::string& name, const std::string& names, int columns) {
    std::ostringstream text;
    text << "t," << names << ",temp\n";
    for (int i = 0; i < 2000; ++i) {
      const double t = 25 + 5 * std::sin(i / 300.0);
      text << 0.1 * i;
      for (int c = 0; c < columns; ++c) text << ',' << 0.01 * t + 1e-3 * std::sin(7.3 * i + c);
      text << ',' << t << '\n';
    }
    return write(name, text.str());
  }
};

TEST_F(DocsAgree, CalibrateHelpNamesEverySubcommand) {
  for (const std::string args : {"--help", "calibrate --help"}) {
    const auto r = run_cubecal(args);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string line = args == "--help" ? line_starting(r.out, "calibrate") : r.out.substr(0, r.out.find('\n'));
    for (const char* sub : {"rate-table", "mag", "temperature", "multiposition"})
      EXPECT_TRUE(has(line, sub)) << args << ": " << line;
  }
}

TEST_F(DocsAgree, TurnonAndCompareHelpNameEveryFormatTheyRead) {
  for (const std::string cmd : {"turnon", "compare"}) {
    const auto r = run_cubecal(cmd + " --help");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string files = line_starting(r.out, "files TEXT");
    for (const char* format : {"delimited text", "NumPy .npy", "HDF5", "raw binary", "ROS 1 .bag", "MCAP", ".db3",
                               "PX4 ULog", "recording directory"})
      EXPECT_TRUE(has(files, format)) << cmd << ": " << files;
  }
}

TEST_F(DocsAgree, CompareAndTurnonPrintBWithItsUnit) {
  const std::string a = gyro_run("a.csv", 1), b = gyro_run("b.csv", 2);
  const std::regex b_with_unit(R"([0-9.]+ ± [0-9.e+-]+ deg/h)");
  const auto c = run_cubecal("compare " + a + " " + b + " --unit deg/s");
  ASSERT_EQ(c.code, 0) << c.err;
  const std::string row = line_containing(c.out, "a.csv");
  ASSERT_FALSE(row.empty()) << c.out;
  EXPECT_TRUE(has(row, "deg/sqrt(h)")) << row;
  EXPECT_TRUE(std::regex_search(row, b_with_unit)) << "B of compare without its unit: " << row;
  const auto t = run_cubecal("turnon " + a + " " + b + " --unit deg/s");
  ASSERT_EQ(t.code, 0) << t.err;
  const std::string run = line_containing(t.out, "a.csv");
  ASSERT_FALSE(run.empty()) << t.out;
  EXPECT_TRUE(std::regex_search(run, b_with_unit)) << "B of turnon without its unit: " << run;
}

TEST_F(DocsAgree, DemoTablesNameTheUnitsOfTheirColumns) {
  const auto r = run_cubecal("demo --hours 0.5 --out " + path("demo"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(has(r.out, "Gyro (deg/s)")) << "N and B of the gyro are not in deg/s";
  EXPECT_FALSE(has(r.out, "Magnetometer (mGauss)")) << "N of the magnetometer is not in mGauss";
  EXPECT_TRUE(has(r.out, "N in deg/sqrt(h), B in deg/h, T in s, sigma_n (sn) in deg/s, sigma_mu (smu) in deg/s/s"))
      << r.out;
  EXPECT_TRUE(has(r.out, "N in mGauss*sqrt(h), B in mGauss, sigma_n (sn) in mGauss")) << r.out;
}

TEST_F(DocsAgree, CalibrateTemperatureTakesTheUnitFromTheColumnNames) {
  const std::string named = temperature_record("named.csv", "gx_dps,gy_dps", 2);
  const auto r = run_cubecal("calibrate temperature " + named + " --temp-col temp");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "deg/s/degC")) << r.out;
  EXPECT_FALSE(has(r.out, "counts")) << "physical values labelled counts: " << r.out;
  EXPECT_TRUE(has(r.err, "units from the column names: gx_dps,gy_dps deg/s")) << r.err;
  // --unit still names them, and a name without a unit is asked for one.
  EXPECT_TRUE(has(run_cubecal("calibrate temperature " + named + " --temp-col temp --unit mGauss").out, "mGauss/degC"));
  const auto bare =
      run_cubecal("calibrate temperature " + temperature_record("bare.csv", "gx", 1) + " --temp-col temp");
  EXPECT_TRUE(one_error_line(bare)) << bare.err;
  EXPECT_TRUE(has(bare.err, "no unit in the name of column gx: give --unit")) << bare.err;
  EXPECT_TRUE(has(
      run_cubecal("calibrate temperature " + temperature_record("raw.csv", "gx", 1) + " --temp-col temp --unit counts")
          .out,
      "counts/degC"));
  const auto mixed =
      run_cubecal("calibrate temperature " + temperature_record("mixed.csv", "gx_dps,ax_g", 2) + " --temp-col temp");
  EXPECT_TRUE(one_error_line(mixed)) << mixed.err;
  EXPECT_TRUE(has(mixed.err, "channel gx_dps is in deg/s and ax_g in g")) << mixed.err;
  const auto help = run_cubecal("calibrate temperature --help");
  EXPECT_FALSE(has(help.out, "--unit TEXT=counts")) << help.out;
}

}  // namespace
