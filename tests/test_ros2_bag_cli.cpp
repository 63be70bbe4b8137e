// ROS 2 bags on the command line (issue 12, item 1): the real Phidgets
// recording as MCAP and as a rosbag2 SQLite directory, read by dev and
// analyze like a ROS 1 bag.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.hpp"

namespace {

using cubecal::test::run_cubecal;

const std::string kData = std::string(CUBECAL_SHARED_DATA) + "/rosbag/";
const std::string kMcap = kData + "ros2-mcap/phidgets_imu_upside_down.mcap";
const std::string kDb3Dir = kData + "ros2-db3/phidgets_imu_upside_down";
const std::string kDb3 = kDb3Dir + "/phidgets_imu_upside_down_0.db3";

class Ros2BagCli : public cubecal::test::TempDirTest {};

TEST_F(Ros2BagCli, DevReadsTheNamedTopicOfAnMcap) {
  const auto r = run_cubecal("dev " + kMcap + " --topic /imu/data_raw --rate 250 --columns gx,gy,gz");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx — oadev (freq data), 13964 samples at 250 Hz"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gz — oadev"), std::string::npos);
  EXPECT_EQ(r.out.find("ax — oadev"), std::string::npos);
}

TEST_F(Ros2BagCli, TheOnlyImuTopicIsTakenAndNamed) {
  for (const std::string& bag : {kMcap, kDb3Dir, kDb3}) {
    const auto r = run_cubecal("dev " + bag + " --gaps split");
    ASSERT_EQ(r.code, 0) << bag << r.err;
    EXPECT_NE(r.err.find(bag + ": topic /imu/data_raw (sensor_msgs/msg/Imu, 13964 messages) (--topic chooses others)"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("az — oadev (freq data), 13964 samples at 250.003 Hz"), std::string::npos) << r.out;
  }
}

TEST_F(Ros2BagCli, MissingTopicListsTheTopicsWithTypesAndCounts) {
  for (const std::string& bag : {kMcap, kDb3Dir}) {
    const auto r = run_cubecal("dev " + bag + " --topic /imu/nope");
    EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.code << r.err;
    EXPECT_NE(r.err.find(bag + ": topic /imu/nope not found; topics are: /imu/data_raw (sensor_msgs/msg/Imu, 13964 "
                               "messages), /imu/mag (sensor_msgs/msg/MagneticField, 13964 messages)"),
              std::string::npos)
        << r.err;
  }
}

TEST_F(Ros2BagCli, AnalyzeReadsABagDirectoryAndKnowsTheUnits) {
  const auto r = run_cubecal("analyze " + kDb3Dir + " --gaps split --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("units from the message types: gx,gy,gz rad/s; ax,ay,az m/s^2"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("gx [rad/s, rate]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("az [m/s^2, acceleration]"), std::string::npos) << r.out;
}

TEST_F(Ros2BagCli, CompareTakesAnMcapAndABagDirectory) {
  const auto r = run_cubecal("compare " + kMcap + " " + kDb3Dir + " --gaps split --columns gx");
  ASSERT_EQ(r.code, 0) << r.err;
  // One row per run: both read, 13964 samples each.
  EXPECT_NE(r.out.find("idgets_imu_upside_down.mcap"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("b3/phidgets_imu_upside_down"), std::string::npos) << r.out;
  std::size_t rows = 0;
  for (std::size_t p = r.out.find("13964 gx"); p != std::string::npos; p = r.out.find("13964 gx", p + 1)) ++rows;
  EXPECT_EQ(rows, 2u) << r.out;
  EXPECT_NE(r.err.find("units from the message types: gx rad/s"), std::string::npos) << r.err;
}

TEST_F(Ros2BagCli, LogTimeOnRequest) {
  const auto r = run_cubecal("dev " + kMcap + " --time-col record --gaps split --columns gx");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx — oadev (freq data), 13964 samples at"), std::string::npos) << r.out;
}

TEST_F(Ros2BagCli, TruncatedMcapIsOneLineAndExitTwo) {
  std::ifstream in(kMcap, std::ios::binary);
  const std::string bytes(std::istreambuf_iterator<char>(in), {});
  const std::string cut = path("cut.mcap");
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const auto r = run_cubecal("dev " + cut + " --rate 250");
  EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.code << r.err;
  EXPECT_NE(r.err.find(cut + ": byte "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the MCAP file is truncated or corrupt"), std::string::npos) << r.err;
}

TEST_F(Ros2BagCli, Db3FromStandardInputIsRefusedWithAHint) {
  const auto r = cubecal::test::run_cubecal_piped("cat " + kDb3, "dev - --rate 250");
  EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.code << r.err;
  EXPECT_NE(r.err.find("is read from its file"), std::string::npos) << r.err;
}

// The check for an SQLite file by path must not read from a pipe: a pipe
// named by its path (/dev/stdin, a FIFO, <(...)) still reads whole.
TEST_F(Ros2BagCli, APipeNamedByItsPathIsNotProbedForSqlite) {
  const std::string csv = write("p.csv", "t,gx_dps\n0,1\n0.01,2\n0.02,3\n0.03,2\n0.04,1\n");
  const auto r = cubecal::test::run_cubecal_piped("cat " + csv, "dev /dev/stdin");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx_dps — oadev (freq data), 5 samples at 100 Hz"), std::string::npos) << r.out;
}

}  // namespace
