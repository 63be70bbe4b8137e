// cubecal plan: the table and the JSON the command prints, each model
// source (preset, datasheet, analysis.json, cubecal model JSON), bad input
// as one error line with exit 2 naming the flag, and the --report page with
// its precision-against-length plot.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "report_check.hpp"
#include "cubecal/report/plot.hpp"

namespace cubecal::test {
namespace {

namespace fs = std::filesystem;

class PlanCli : public TempDirTest {};

TEST_F(PlanCli, TableGivesTheLengthEachTargetNeeds) {
  const CliRun r = run_cubecal("plan --preset sport-gyro --target B:10%,K:20%");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("plan for sport-gyro (preset) at 10 Hz"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("record length each target needs"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("precision from a record of"), std::string::npos) << "no --duration, no such section";
  for (const char* ch : {"gx", "gy", "gz"}) EXPECT_NE(r.out.find(std::string("  ") + ch + "  "), std::string::npos);
  EXPECT_NE(r.out.find("deg/h/sqrt(h)"), std::string::npos) << "K in the unit quoted for gyros";
  EXPECT_NE(r.out.find("10 %"), std::string::npos);
}

TEST_F(PlanCli, DefaultsPlanBothAndSaySo) {
  const CliRun r = run_cubecal("plan --preset sport-mag");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("neither --target nor --duration"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("record length each target needs"), std::string::npos);
  EXPECT_NE(r.out.find("precision from a record of 72 h"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mGauss"), std::string::npos);
}

TEST_F(PlanCli, JsonIsAListOfRowsWithReasons) {
  // A datasheet without K: K cannot be planned, said in the row.
  const CliRun r =
      run_cubecal("plan --datasheet N=0.15deg/rth --rate 100 --target N:1%,K:20% --duration 24h --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 4u);  // 2 targets, and N, K at 24 h
  for (const auto& row : j) {
    EXPECT_EQ(row.at("channel"), "datasheet");
    for (const char* key : {"term", "precision", "duration_s", "value", "unit", "reason", "why"})
      EXPECT_TRUE(row.contains(key)) << key;
  }
  EXPECT_EQ(j[0].at("term"), "N");
  EXPECT_EQ(j[0].at("kind"), "target");
  EXPECT_TRUE(j[0].at("reason").is_null());
  EXPECT_GT(j[0].at("duration_s").get<double>(), 0.0);
  EXPECT_NEAR(j[0].at("value").get<double>(), 0.15, 1e-3);
  EXPECT_EQ(j[0].at("unit"), "deg/sqrt(h)");
  EXPECT_EQ(j[1].at("term"), "K");
  EXPECT_TRUE(j[1].at("duration_s").is_null());
  EXPECT_EQ(j[1].at("reason"), "not in model");
  EXPECT_FALSE(j[1].at("why").get<std::string>().empty());
  EXPECT_EQ(j[2].at("kind"), "duration");
  EXPECT_EQ(j[2].at("duration_s"), 86400.0);
  // The table says the same in words.
  const CliRun t = run_cubecal("plan --datasheet N=0.15deg/rth --rate 100 --target N:1%,K:20% --duration 24h");
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find(j[1].at("why").get<std::string>()), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("precision from a record of 24 h"), std::string::npos) << t.out;
}

TEST_F(PlanCli, AnalysisAndModelFilesAreModels) {
  const CliRun sim =
      run_cubecal("simulate --preset sport-gyro --duration 2h --seed 3 --temp const:25 --out " + path("sim.csv"));
  ASSERT_EQ(sim.code, 0) << sim.err;
  const CliRun an = run_cubecal("analyze " + path("sim.csv") + " --columns gx --unit deg/s --out " + path("res"));
  ASSERT_EQ(an.code, 0) << an.err;
  const CliRun a = run_cubecal("plan --model " + path("res/analysis.json") + " --target N:5% --format json");
  ASSERT_EQ(a.code, 0) << a.err;
  const auto ja = nlohmann::json::parse(a.out);
  ASSERT_EQ(ja.size(), 1u);
  EXPECT_EQ(ja[0].at("channel"), "gx");
  // The gyro's N: sigma_n sqrt(dt) = 13.9e-3 sqrt(0.1) deg/s sqrt(s) = 0.264 deg/sqrt(h), as analyze measured it.
  EXPECT_NEAR(ja[0].at("value").get<double>(), 13.9e-3 * std::sqrt(0.1) * 60.0, 0.03);
  const CliRun table = run_cubecal("plan --model " + path("res/analysis.json") + " --target N:5%");
  ASSERT_EQ(table.code, 0) << table.err;
  EXPECT_NE(table.out.find("(twin: the twin (composite model) of each channel)"), std::string::npos) << table.out;

  const CliRun fit = run_cubecal("model " + path("sim.csv") +
                                 " --columns gx --unit deg/s --model WN+RW --format json "
                                 "--out " +
                                 path("model.json"));
  ASSERT_EQ(fit.code, 0) << fit.err;
  const CliRun m = run_cubecal("plan --model " + path("model.json") + " --target N:5%");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_NE(m.out.find("(model: the composite model of each channel (WN+RW))"), std::string::npos) << m.out;
}

TEST_F(PlanCli, BadInputIsOneLineNamingTheFlag) {
  const auto expect = [](const std::string& args, const std::string& says) {
    const CliRun r = run_cubecal("plan " + args);
    EXPECT_TRUE(one_error_line(r)) << args << ": " << r.code << " " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
  };
  expect("--preset sport-gyro --target X:10%", "--target");
  expect("--preset sport-gyro --target B:0%", "--target");
  expect("--preset sport-gyro --target B:100%", "--target");
  expect("--preset sport-gyro --target B:150%", "--target");
  expect("--datasheet N=0.15deg/rth", "--rate");
  expect("--datasheet N=0.15deg/h --rate 100", "--datasheet: N=0.15deg/h: deg/h is not a unit of N");
  expect("--datasheet N=0.15deg/rth,B=3uT --rate 100", "--datasheet");
  expect("--target B:10%", "no sensor model: give --preset");
  expect("--preset sport-gyro --datasheet N=0.15deg/rth --rate 100", "--preset and --datasheet");
  expect("--preset nosuch", "--preset: unknown preset 'nosuch'");
  expect("--preset sport-gyro --duration 3x", "--duration");
  expect("--preset sport-gyro --ci 1.5", "--ci");
  expect("--model " + std::string("/nonexistent/analysis.json"), "--model");
  expect("--preset sport-gyro --format yaml", "--format");
}

// --report: the table and, per channel, precision against record length
// with the targets and the planned lengths; the marks at the lengths the JSON gives.
TEST_F(PlanCli, ReportDrawsPrecisionAgainstLength) {
  if (!report::find_gnuplot()) GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox (scripts/install-deps.sh)";
  const std::string dir = path("rep");
  const CliRun r = run_cubecal("plan --preset sport-gyro --target B:10%,N:1% --format json --report " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* ch : {"gx", "gy", "gz"})
    for (const char* ext : {".dat", ".gp", ".svg", ".png"})
      EXPECT_TRUE(fs::exists(fs::path(dir) / "plots" / (std::string("plan_") + ch + ext))) << ch << ext;
  const std::string html = slurp(fs::path(dir) / "report.html");
  EXPECT_EQ(count(html, "data:image/svg+xml;base64,"), 3u) << "the plots inline";
  EXPECT_NE(html.find("record length"), std::string::npos);
  const auto j = nlohmann::json::parse(r.out);
  double planned_b = 0.0;
  for (const auto& row : j)
    if (row.at("channel") == "gx" && row.at("term") == "B" && row.at("duration_s").is_number())
      planned_b = row.at("duration_s").get<double>();
  ASSERT_GT(planned_b, 0.0);
  // The mark of B's planned length in plan_gx.dat, in hours.
  std::ifstream dat(fs::path(dir) / "plots" / "plan_gx.dat");
  std::string line;
  bool in_block = false;
  std::vector<double> x;
  while (std::getline(dat, line)) {
    if (line.rfind("# index", 0) == 0) {
      in_block = line.find("B planned length") != std::string::npos;
      continue;
    }
    if (!in_block || line.empty() || line[0] == '#') continue;
    x.push_back(std::stod(line));
  }
  ASSERT_EQ(x.size(), 1u);
  EXPECT_NEAR(x[0], planned_b / 3600.0, 1e-8 * planned_b / 3600.0);
  const CliRun again = run_cubecal("plan --preset sport-gyro --report " + dir);
  EXPECT_TRUE(one_error_line(again)) << again.err;
}

TEST_F(PlanCli, HelpNamesEveryOption) {
  const CliRun r = run_cubecal("plan --help");
  ASSERT_EQ(r.code, 0);
  for (const char* opt : {"--preset", "--model", "--datasheet", "--rate", "--target", "--ci", "--duration", "--taus",
                          "--format", "--out", "--force", "--report"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

}  // namespace
}  // namespace cubecal::test
