// The cubecal binary end to end: output formats, exit codes, one-line errors,
// and that no file is replaced without being asked.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
};

Result run(const std::string& args) {
  static int counter = 0;
  const fs::path errf = fs::temp_directory_path() / ("cubecal_cli_err_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string cmd = std::string(CUBECAL_BINARY) + " " + args + " 2>" + errf.string();
  Result r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = ::pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream e(errf);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  fs::remove(errf);
  return r;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cubecal_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  fs::path dir_;
};

const std::string kPhaseDat = std::string(CUBECAL_SHARED_DATA) + "/stable32/phasedat/PHASE.DAT";

bool one_error_line(const Result& r) {
  return r.err.rfind("cubecal: error: ", 0) == 0 && r.err.find('\n') == r.err.size() - 1;
}

TEST_F(Cli, JsonShapeAndValuesOnPhaseDat) {
  const Result r = run("dev " + kPhaseDat + " --type phase --rate 1 --stat oadev --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["stat"], "oadev");
  EXPECT_EQ(j["type"], "phase");
  EXPECT_DOUBLE_EQ(j["rate_hz"].get<double>(), 1.0);
  ASSERT_EQ(j["columns"].size(), 1u);
  const auto& c = j["columns"][0];
  for (const char* k : {"name", "tau", "dev", "lo", "hi", "n", "edf", "alpha"}) EXPECT_TRUE(c.contains(k)) << k;
  // Stable32 phase_dat_oadev_octave.txt, AF 1, 64 and 128.
  EXPECT_NEAR(c["dev"][0].get<double>(), 2.9223e-01, 2.9223e-01 * 1e-4);
  EXPECT_EQ(c["n"][0].get<int>(), 999);
  EXPECT_EQ(c["tau"].size(), 8u);
  EXPECT_NEAR(c["dev"][7].get<double>(), 2.7674e-02, 2.7674e-02 * 1e-4);
  EXPECT_NEAR(c["lo"][6].get<double>(), 3.1755e-02, 3.1755e-02 * 1e-3);
  EXPECT_NEAR(c["hi"][6].get<double>(), 4.3377e-02, 4.3377e-02 * 1e-3);
}

TEST_F(Cli, CsvAndTable) {
  const Result csv = run("dev " + kPhaseDat + " --type phase --rate 1 --format csv --taus 1,10");
  ASSERT_EQ(csv.code, 0) << csv.err;
  EXPECT_EQ(csv.out.substr(0, csv.out.find('\n')), "column,af,tau,n,alpha,edf,lo,dev,hi");
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 3);
  const Result t = run("dev " + kPhaseDat + " --type phase --rate 1 --stat totdev");
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("totdev"), std::string::npos);
}

TEST_F(Cli, MissingFile) {
  const Result r = run("dev " + (dir_ / "nope.csv").string() + " --rate 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("nope.csv"), std::string::npos);
}

TEST_F(Cli, NonNumericFieldNamesLineAndColumn) {
  const std::string f = write("bad.csv", "t,gx\n0,1.0\n0.1,2.0\n0.2,abc\n0.3,1\n");
  const Result r = run("dev " + f + " --taus 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("bad.csv:4:5:"), std::string::npos) << r.err;
}

TEST_F(Cli, UnknownColumn) {
  const std::string f = write("u.csv", "t,gx\n0,1\n0.1,2\n0.2,3\n0.3,1\n");
  const Result r = run("dev " + f + " --columns gq");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("gq"), std::string::npos);
}

TEST_F(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(run("dev " + kPhaseDat + " --rate 1 --taus log:zz").code, 2);
  EXPECT_EQ(run("dev " + kPhaseDat + " --rate 1 --stat nonsense").code, 2);
  const Result r = run("dev " + kPhaseDat + " --rate 1 --bogus");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("dev --help").code, 0);
}

TEST_F(Cli, NoRateNoTimeColumn) {
  const Result r = run("dev " + kPhaseDat);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--rate"), std::string::npos) << r.err;
}

TEST_F(Cli, TooShortForStatistic) {
  const std::string f = write("short.txt", "1\n2\n3\n4\n");
  const Result r = run("dev " + f + " --rate 1 --stat hdev");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
}

TEST_F(Cli, NeverOverwritesWithoutForce) {
  const std::string out = write("result.json", "precious");
  const Result r = run("dev " + kPhaseDat + " --type phase --rate 1 --format json --out " + out);
  EXPECT_EQ(r.code, 2);
  std::ifstream in(out);
  std::string s;
  std::getline(in, s);
  EXPECT_EQ(s, "precious");
  const Result f = run("dev " + kPhaseDat + " --type phase --rate 1 --format json --out " + out + " --force");
  EXPECT_EQ(f.code, 0) << f.err;
  std::ifstream replaced(out);
  const auto j = nlohmann::json::parse(replaced, nullptr, false);
  EXPECT_FALSE(j.is_discarded());
  EXPECT_EQ(j["stat"], "oadev");
}

TEST_F(Cli, GapsSplitSaysSo) {
  std::string text = "t,g\n";
  for (int i = 0; i < 200; ++i) text += std::to_string(i < 100 ? i * 0.1 : 20.0 + i * 0.1) + "," + std::to_string((i * 7919) % 13) + "\n";
  const std::string f = write("gap.csv", text);
  const Result e = run("dev " + f + " --taus 0.1,0.2");
  EXPECT_EQ(e.code, 2);
  EXPECT_TRUE(one_error_line(e)) << e.err;
  EXPECT_NE(e.err.find("--gaps split"), std::string::npos) << e.err;
  const Result s = run("dev " + f + " --taus 0.1,0.2 --gaps split --format json");
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.err.find("segment"), std::string::npos) << s.err;
  const auto j = nlohmann::json::parse(s.out);
  EXPECT_EQ(j["segments"], 2);
  // Two segments of 100 samples: 99 + 99 overlapping terms at m = 1.
  EXPECT_EQ(j["columns"][0]["n"][0], 198);
}

TEST_F(Cli, DemoRunsAndKeepsForeignFiles) {
  const Result r = run("demo --hours 0.5 --out " + dir_.string() + "/d");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "d" / "gyro_oadev.json"));
  const Result again = run("demo --hours 0.5 --out " + dir_.string() + "/d");
  EXPECT_EQ(again.code, 0) << again.err;  // its own earlier output is replaced
  fs::create_directories(dir_ / "mine");
  write("mine/gyro_static.csv", "user data");
  const Result foreign = run("demo --hours 0.5 --out " + (dir_ / "mine").string());
  EXPECT_EQ(foreign.code, 2);
}

}  // namespace
