// Issue 12 item 3: per-column scale (--lsb and --unit lists), so that one run
// of `analyze` on a raw 6-axis log gives gyro and accelerometer terms and one
// imu.yaml, and per-file reader options of compare and turnon
// (FILE:key=value,...) for runs of different layouts.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;

const std::string kMpu = std::string(CUBECAL_SHARED_DATA) + "/imu/mpu6050/";

std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The line of `key` in an imu.yaml (key: value  # comment), or "".
std::string yaml_line(const std::string& yaml, const std::string& key) {
  std::istringstream in(yaml);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return line;
  return {};
}

class PerColumnScale : public cubecal::test::TempDirTest {};

// The MPU-6050 log (raw int16 counts, ax,ay,az,gx,gy,gz, 4 preamble lines,
// 100 Hz) at its default scales in one run, against a run per sensor.
TEST_F(PerColumnScale, OneAnalyzeGivesBothSensorsAsTwoSingleSensorRuns) {
  for (const std::string file : {"imu_static_test.csv", "example_data_tinit_calc.csv"}) {
    const std::string in = "'" + kMpu + file + "' --skip-rows 4 --rate 100";
    const auto both =
        run_cubecal("analyze " + in + " --lsb 16384,16384,16384,131,131,131 --unit g,g,g,deg/s,deg/s,deg/s --out " +
                    path(file + ".both"));
    ASSERT_EQ(both.code, 0) << both.err;
    const auto gyro =
        run_cubecal("analyze " + in + " --columns gx,gy,gz --lsb 131 --unit deg/s --out " + path(file + ".g"));
    ASSERT_EQ(gyro.code, 0) << gyro.err;
    const auto accel = run_cubecal("analyze " + in + " --columns ax,ay,az --lsb 16384 --unit g --for kalibr --out " +
                                   path(file + ".a"));
    ASSERT_EQ(accel.code, 0) << accel.err;

    const std::string y = slurp(path(file + ".both") + "/imu.yaml");
    const std::string yg = slurp(path(file + ".g") + "/imu.yaml"), ya = slurp(path(file + ".a") + "/imu.yaml");
    for (const std::string key : {"gyroscope_noise_density", "gyroscope_random_walk"}) {
      EXPECT_FALSE(yaml_line(y, key).empty()) << file << ": " << key << "\n" << y;
      EXPECT_EQ(yaml_line(y, key), yaml_line(yg, key)) << file;
    }
    for (const std::string key : {"accelerometer_noise_density", "accelerometer_random_walk"}) {
      EXPECT_FALSE(yaml_line(y, key).empty()) << file << ": " << key << "\n" << y;
      EXPECT_EQ(yaml_line(y, key), yaml_line(ya, key)) << file;
    }
    // Every number of every channel, the sensor model with its per-column
    // quantizer included, is the single-sensor run's.
    const auto j = nlohmann::json::parse(slurp(path(file + ".both") + "/analysis.json"));
    const auto jg = nlohmann::json::parse(slurp(path(file + ".g") + "/analysis.json"));
    const auto ja = nlohmann::json::parse(slurp(path(file + ".a") + "/analysis.json"));
    ASSERT_EQ(j["channels"].size(), 6u);
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_EQ(j["channels"][c], ja["channels"][c]) << file << " " << c;
      EXPECT_EQ(j["channels"][c + 3], jg["channels"][c]) << file << " " << c;
    }
    EXPECT_EQ(j["channels"][0]["model"]["lsb"], 16384.0) << j["channels"][0]["model"].dump();
    EXPECT_EQ(j["channels"][3]["model"]["lsb"], 131.0) << j["channels"][3]["model"].dump();
  }
}

TEST_F(PerColumnScale, AnLsbCountThatIsNotTheColumnsIsRefused) {
  const std::string in = "'" + kMpu + "imu_static_test.csv' --skip-rows 4 --rate 100";
  for (const std::string cmd : {"dev", "analyze --unit counts", "calibrate temperature --temp-col gz --order 1"}) {
    const auto r = run_cubecal(cmd + " " + in + " --columns gx,gy,gz --lsb 131,131");
    EXPECT_TRUE(one_error_line(r)) << cmd << ": " << r.err;
    EXPECT_TRUE(has(r.err, "--lsb: ")) << r.err;
    EXPECT_TRUE(has(r.err,
                    "imu_static_test.csv: 2 LSB values for 3 columns (gx,gy,gz): give one value for every "
                    "column, or one per column"))
        << cmd << ": " << r.err;
  }
  const auto bad = run_cubecal("dev " + in + " --lsb 131,zero");
  EXPECT_TRUE(one_error_line(bad)) << bad.err;
  EXPECT_TRUE(has(bad.err, "--lsb: 'zero' is not a positive number of counts per unit")) << bad.err;
  const auto units = run_cubecal("analyze " + in + " --lsb 131 --unit deg/s,deg/s");
  EXPECT_TRUE(one_error_line(units)) << units.err;
  EXPECT_TRUE(has(units.err, "--unit: 2 units for 6 columns")) << units.err;
}

// dev takes the list; where one value is all that makes sense, a list is
// refused with the reason.
TEST_F(PerColumnScale, DevScalesEachColumnAndSingleScaleCommandsRefuseLists) {
  const std::string in = "'" + kMpu + "imu_static_test.csv' --skip-rows 4 --rate 100 --taus 1,10 --format json";
  const auto list = run_cubecal("dev " + in + " --columns az,gz --lsb 16384,131");
  ASSERT_EQ(list.code, 0) << list.err;
  const auto az = run_cubecal("dev " + in + " --columns az --lsb 16384");
  const auto gz = run_cubecal("dev " + in + " --columns gz --lsb 131");
  ASSERT_EQ(az.code, 0) << az.err;
  ASSERT_EQ(gz.code, 0) << gz.err;
  const auto j = nlohmann::json::parse(list.out);
  ASSERT_EQ(j["columns"].size(), 2u) << list.out;
  EXPECT_EQ(j["columns"][0], nlohmann::json::parse(az.out)["columns"][0]);
  EXPECT_EQ(j["columns"][1], nlohmann::json::parse(gz.out)["columns"][0]);

  const auto mag = run_cubecal("calibrate mag '" + kMpu +
                               "imu_static_test.csv' --skip-rows 4 --columns ax,ay,az "
                               "--lsb 1,2,3");
  EXPECT_TRUE(one_error_line(mag)) << mag.err;
  EXPECT_TRUE(has(mag.err, "--lsb: '1,2,3': one value here, for all three axes")) << mag.err;
  const auto temp = run_cubecal("calibrate temperature " + in.substr(0, in.find(" --taus")) +
                                " --columns gx,ax --temp-col gz --lsb 131,16384 --unit deg/s,g");
  EXPECT_TRUE(one_error_line(temp)) << temp.err;
  EXPECT_TRUE(has(temp.err, "--unit: one unit here")) << temp.err;
}

class PerFileOptions : public cubecal::test::TempDirTest {
 protected:
  // The gyro of the MPU-6050 log in another layout: every second sample
  // (50 Hz), a time column, deg/s, the columns in another order, no preamble.
  std::string other_layout() {
    std::ifstream in(kMpu + "imu_static_test.csv");
    std::string line, text = "time,gz,gx\n";
    for (int k = 0; k < 5; ++k) std::getline(in, line);
    char buf[96];
    for (int i = 0; std::getline(in, line); ++i) {
      if (i % 2 != 0) continue;
      int v[6];
      if (std::sscanf(line.c_str(), "%d,%d,%d,%d,%d,%d", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]) != 6) continue;
      std::snprintf(buf, sizeof buf, "%.2f,%.17g,%.17g\n", (i / 2) * 0.02, v[5] / 131.0, v[3] / 131.0);
      text += buf;
    }
    return write("other:layout.csv", text);  // a ':' in the path
  }
};

// Two files of different layouts and rates in one compare and one turnon.
TEST_F(PerFileOptions, CompareAndTurnonReadEachFileWithItsOwnOptions) {
  const std::string raw = kMpu + "imu_static_test.csv";
  const std::string other = other_layout();
  const std::string a = "'" + raw + ":skip-rows=4,rate=100,columns=gx,gz,lsb=131'";
  const std::string b = "'" + other + ":columns=gx,gz'";
  const auto r = run_cubecal("compare " + a + " " + b + " --unit deg/s --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out)["runs"];
  ASSERT_EQ(j.size(), 2u) << r.out;
  EXPECT_EQ(j[0]["file"], raw);
  EXPECT_EQ(j[0]["rate_hz"], 100.0);
  EXPECT_EQ(j[1]["file"], other);
  EXPECT_EQ(j[1]["rate_hz"], 50.0);
  for (std::size_t k = 0; k < 2; ++k) {
    ASSERT_EQ(j[k]["channels"].size(), 2u) << r.out;
    EXPECT_EQ(j[k]["channels"][0]["name"], "gx");
    EXPECT_EQ(j[k]["channels"][1]["name"], "gz");
  }
  // Each run is what a command with those options gives on that file alone.
  const auto alone = run_cubecal("compare '" + raw +
                                 "' --skip-rows 4 --rate 100 --columns gx,gz --lsb 131 "
                                 "--unit deg/s --format json");
  ASSERT_EQ(alone.code, 0) << alone.err;
  EXPECT_EQ(j[0], nlohmann::json::parse(alone.out)["runs"][0]);

  // A unit per file in compare; turnon wants one unit for all runs.
  const auto units = run_cubecal("compare '" + raw + ":skip=4,rate=100,columns=gx,lsb=131,unit=deg/s' '" + other +
                                 ":columns=gx,unit=deg/s' --format json");
  ASSERT_EQ(units.code, 0) << units.err;
  EXPECT_EQ(nlohmann::json::parse(units.out)["runs"][0]["channels"][0]["unit"], "deg/s") << units.out;

  const auto t = run_cubecal("turnon " + a + " " + b + " --unit deg/s --format json");
  ASSERT_EQ(t.code, 0) << t.err;
  const auto tj = nlohmann::json::parse(t.out);
  ASSERT_EQ(tj["runs"].size(), 2u) << t.out;
  // The same gyro at the same scale: the run biases agree to the samples
  // dropped from the 50 Hz copy.
  const double b0 = tj["runs"][0]["channels"][0]["mean"], b1 = tj["runs"][1]["channels"][0]["mean"];
  EXPECT_NEAR(b0, b1, 1e-3) << t.out;
  const auto u = run_cubecal("turnon '" + raw + ":skip=4,rate=100,columns=gx,lsb=131,unit=deg/s' " + b);
  EXPECT_TRUE(one_error_line(u)) << u.err;
  EXPECT_TRUE(has(u.err, "turnon averages the runs' biases, so every run is in the same unit")) << u.err;
}

TEST_F(PerFileOptions, BadPerFileOptionsAreOneLineErrors) {
  const std::string raw = kMpu + "imu_static_test.csv";
  for (const auto& [arg, says] :
       std::vector<std::pair<std::string, std::string>>{{raw + ":rate=100,foo=3", "unknown key 'foo'"},
                                                        {raw + ":rate=100,rate=50", "'rate' given twice"},
                                                        {raw + ":skip=4,skip-rows=4", "'skip-rows' given twice"},
                                                        {raw + ":rate=-1", "rate=-1 is not a non-negative number"},
                                                        {raw + ":skip=2.5", "skip=2.5 is not a whole number of lines"},
                                                        {raw + ":lsb=131,x", "--lsb: 'x' is not a positive number"},
                                                        {raw + ":unit=furlong", "unknown unit 'furlong'"},
                                                        {raw + ":gaps=ignore", "gaps=ignore is not error or split"},
                                                        {raw + ":columns=", "'columns=' has no value"}}) {
    const auto r = run_cubecal("compare '" + arg + "' '" + raw + "'");
    EXPECT_TRUE(one_error_line(r)) << arg << ": " << r.err;
    EXPECT_TRUE(has(r.err, says)) << arg << ": " << r.err;
  }
  // Text after ':' that is no key=value list is part of the path.
  const auto p = run_cubecal("compare '" + path("run:3.csv") + "' '" + raw + "'");
  EXPECT_TRUE(one_error_line(p)) << p.err;
  EXPECT_TRUE(has(p.err, "run:3.csv")) << p.err;
}

}  // namespace
