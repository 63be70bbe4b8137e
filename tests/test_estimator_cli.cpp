// `cubecal analyze --for ... --inflate K` and `--config FILE` through the
// binary: the files written, their numbers against analysis.json, outputs
// refused before the work, and the config file's precedence and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "estimator_yaml.hpp"

namespace cubecal::test {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class EstimatorCli : public TempDirTest {
 protected:
  // 100 Hz, three gyro axes (deg/s, white 0.02 per sample) and three
  // accelerometer axes (g, white 0.002 per sample, z at 1 g).
  std::string record() {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g(0.0, 1.0);
    std::string s = "t,gx,gy,gz,ax,ay,az\n";
    char b[200];
    for (int i = 0; i < 20000; ++i) {
      std::snprintf(b, sizeof b, "%.2f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", i / 100.0, 0.02 * g(rng), 0.02 * g(rng),
                    0.02 * g(rng), 0.002 * g(rng), 0.002 * g(rng), 1.0 + 0.002 * g(rng));
      s += b;
    }
    return write("imu.csv", s);
  }
  static constexpr const char* kUnits = " --time-col t --unit deg/s,deg/s,deg/s,g,g,g";
};

TEST_F(EstimatorCli, ForWritesEachFormatAndInflateScalesIt) {
  const std::string rec = record();
  const auto plain =
      run_cubecal("analyze " + rec + kUnits + " --out " + path("a") + " --for kalibr,openvins,vins,kf-gins");
  ASSERT_EQ(plain.code, 0) << plain.err;
  const auto inflated = run_cubecal("analyze " + rec + kUnits + " --out " + path("b") +
                                    " --for kalibr --for openvins,vins --for kf-gins --inflate 3");
  ASSERT_EQ(inflated.code, 0) << inflated.err;
  for (const char* f : {"imu.yaml", "kalibr_imu_chain.yaml", "vins_imu.yaml", "kf-gins_imunoise.yaml"})
    for (const char* d : {"a", "b"}) EXPECT_TRUE(fs::exists(dir_ / d / f)) << d << "/" << f;

  // analysis.json records the request, and its ARW gives the Kalibr density:
  // N [rad/s/sqrt(Hz)] = ARW [deg/sqrt(h)] / 60 * pi / 180, the largest axis.
  const auto j = nlohmann::json::parse(slurp(dir_ / "b" / "analysis.json"));
  EXPECT_EQ(j["estimator_files"]["noise_factor"], 3.0);
  EXPECT_EQ(j["estimator_files"]["for"], nlohmann::json({"kalibr", "openvins", "vins", "kf-gins"}));
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "a" / "analysis.json"))["estimator_files"]["noise_factor"], 1.0);
  // One N: analysis.json's arw (the read-off at tau = 1 s) is the reported
  // N and the one the console prints (4 digits), for every channel.
  double arw = 0.0, arw_sigma = 0.0;
  std::vector<double> console;
  for (std::size_t at = plain.out.find("\n  N         "); at != std::string::npos;
       at = plain.out.find("\n  N         ", at + 1))
    console.push_back(std::stod(plain.out.substr(at + 13)));
  ASSERT_EQ(console.size(), 6u) << plain.out;
  // White noise only: every channel's curve still falls at its last tau and
  // shows no random walk; the console says so rather than printing numbers.
  std::size_t no_min = 0, no_k = 0;
  for (std::size_t at =
           plain.out.find("\n  B         no minimum within the record (the curve is lowest at its last tau");
       at != std::string::npos; at = plain.out.find("\n  B         no minimum within the record", at + 1))
    ++no_min;
  for (std::size_t at = plain.out.find("\n  K         not "); at != std::string::npos;
       at = plain.out.find("\n  K         not ", at + 1))
    ++no_k;
  EXPECT_EQ(no_min, 6u) << plain.out;
  EXPECT_EQ(no_k, 6u) << plain.out;
  EXPECT_NE(plain.out.find("(upper bound)"), std::string::npos);
  const auto ja = nlohmann::json::parse(slurp(dir_ / "a" / "analysis.json"));
  for (int c = 0; c < 6; ++c) {
    const auto& n = ja["channels"][c]["noise"];
    EXPECT_EQ(n["reported"]["white_noise"]["value"], n["arw"]["value"]) << c;
    EXPECT_NEAR(console[static_cast<std::size_t>(c)] / n["arw"]["value"].get<double>(), 1.0, 5e-4) << c;
  }
  for (int c = 0; c < 3; ++c) {
    const auto& N = j["channels"][c]["noise"]["arw"];
    ASSERT_EQ(N["unit"], "deg/sqrt(h)");
    if (N["value"].get<double>() > arw) {
      arw = N["value"].get<double>();
      arw_sigma = N["sigma"].get<double>();
    }
  }
  const auto ka = yaml_keys(slurp(dir_ / "a" / "imu.yaml"));
  const auto kb = yaml_keys(slurp(dir_ / "b" / "imu.yaml"));
  EXPECT_NEAR(number(ka, "gyroscope_noise_density") / (arw / 60.0 * std::numbers::pi / 180.0), 1.0, 1e-8);
  // The simulated truth: 0.02 deg/s per sample at 100 Hz is 0.002 deg/s/sqrt(Hz) = 0.12 deg/sqrt(h),
  // within 3 sigma of the largest axis's N (read at 1 s: 4 % per point on this 200 s record).
  EXPECT_NEAR(arw, 0.12, 3.0 * arw_sigma);
  EXPECT_LT(arw_sigma, 0.05 * arw);

  for (const char* key :
       {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density", "accelerometer_random_walk"})
    EXPECT_NEAR(number(kb, key) / number(ka, key), 3.0, 3e-9) << key;
  const auto va = yaml_keys(slurp(dir_ / "a" / "vins_imu.yaml"));
  const auto vb = yaml_keys(slurp(dir_ / "b" / "vins_imu.yaml"));
  for (const char* key : {"acc_n", "gyr_n", "acc_w", "gyr_w"})
    EXPECT_NEAR(number(vb, key) / number(va, key), 3.0, 3e-9);
  EXPECT_EQ(number(vb, "g_norm"), number(va, "g_norm"));
  const auto ga = yaml_keys(slurp(dir_ / "a" / "kf-gins_imunoise.yaml"));
  const auto gb = yaml_keys(slurp(dir_ / "b" / "kf-gins_imunoise.yaml"));
  // KF-GINS arw is the analysis.json ARW of each axis, in its own unit.
  for (int c = 0; c < 3; ++c) {
    const auto& N = j["channels"][c]["noise"]["arw"];
    EXPECT_NEAR(triple(ga, "arw")[c] / N["value"].get<double>(), 1.0, 1e-8) << c;
    EXPECT_NEAR(triple(gb, "arw")[c] / triple(ga, "arw")[c], 3.0, 3e-9) << c;
  }
  EXPECT_NE(slurp(dir_ / "b" / "kf-gins_imunoise.yaml").find("x inflate 3.0"), std::string::npos);
}

TEST_F(EstimatorCli, ExistingEstimatorFileIsRefusedBeforeTheWork) {
  const std::string rec = record();
  fs::create_directories(dir_ / "o");
  std::ofstream(dir_ / "o" / "kf-gins_imunoise.yaml") << "mine\n";
  const auto r = run_cubecal("analyze " + rec + kUnits + " --out " + path("o") + " --for kf-gins");
  EXPECT_TRUE(one_error_line(r)) << r.code << " " << r.err;
  EXPECT_NE(r.err.find("kf-gins_imunoise.yaml already exists"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o" / "analysis.json")) << "refused only after the analysis";
  EXPECT_EQ(slurp(dir_ / "o" / "kf-gins_imunoise.yaml"), "mine\n");
}

TEST_F(EstimatorCli, BadRequestsAreUsageErrors) {
  const std::string rec = record();
  for (const std::string& args : std::vector<std::string>{" --out " + path("x") + " --for okvis", " --for kalibr",
                                                          " --out " + path("y") + " --for vins --inflate 0.5",
                                                          " --out " + path("z") + " --for vins --inflate nan"}) {
    const auto r = run_cubecal("analyze " + rec + kUnits + args);
    EXPECT_TRUE(one_error_line(r)) << args << ": " << r.code << " " << r.err;
  }
  // A record without an IMU channel: refused with what is missing.
  const auto r = run_cubecal("analyze " + rec + " --time-col t --unit mGauss --out " + path("m") + " --for vins");
  EXPECT_TRUE(one_error_line(r)) << r.code << " " << r.err;
  EXPECT_NE(r.err.find("no gyroscope (deg/s, rad/s) or accelerometer (g, m/s^2) channel"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "m" / "analysis.json"));
}

TEST_F(EstimatorCli, ConfigFileSetsOptionsAndTheCommandLineOverridesIt) {
  const std::string rec = record();
  const std::string cfg = write("run.toml", "# a repeatable run\n[analyze]\nfile = \"" + rec +
                                                "\"\ntime-col = \"t\"\nunit = \"deg/s,deg/s,deg/s,g,g,g\"\n"
                                                "for = [\"kalibr\", \"vins\"]\ninflate = 2\n");
  const auto one = run_cubecal("analyze --config " + cfg + " --out " + path("c"));
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_TRUE(fs::exists(dir_ / "c" / "vins_imu.yaml")) << "--for from the file";
  EXPECT_FALSE(fs::exists(dir_ / "c" / "kf-gins_imunoise.yaml"));
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "c" / "analysis.json"))["estimator_files"]["noise_factor"], 2.0);
  const auto two = run_cubecal("analyze --config " + cfg + " --out " + path("d") + " --inflate 5");
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "d" / "analysis.json"))["estimator_files"]["noise_factor"], 5.0);
  const auto c = yaml_keys(slurp(dir_ / "c" / "vins_imu.yaml"));
  const auto d = yaml_keys(slurp(dir_ / "d" / "vins_imu.yaml"));
  EXPECT_NEAR(number(d, "gyr_n") / number(c, "gyr_n"), 2.5, 2.5e-9);
}

TEST_F(EstimatorCli, UnknownConfigKeyIsAClearError) {
  const std::string rec = record();
  const std::string cfg = write("bad.toml", "[analyze]\ninflat = 2\n");
  const auto r = run_cubecal("analyze " + rec + kUnits + " --config " + cfg + " --out " + path("e"));
  EXPECT_TRUE(one_error_line(r)) << r.code << " " << r.err;
  EXPECT_NE(r.err.find(cfg + ": unknown key 'analyze.inflat'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "e"));
}

}  // namespace
}  // namespace cubecal::test
