// The cubecal binary end to end: output formats, exit codes, one-line errors,
// and that no file is replaced without being asked.
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "../src/cli/calibration_hints.hpp"

#include <algorithm>
#include <array>
#include <cmath>
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

using Result = cubecal::test::CliRun;
Result run(const std::string& args) { return cubecal::test::run_cubecal(args); }

class Cli : public cubecal::test::TempDirTest {};

const std::string kPhaseDat = std::string(CUBECAL_SHARED_DATA) + "/stable32/phasedat/PHASE.DAT";

using cubecal::test::one_error_line;

// "sigma_mu X mGauss/s" as the analyze console prints a model (4 digits).
std::string fmt_sigma_mu(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "sigma_mu %.4g mGauss/s", v);
  return b;
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

// The noise type of every AF of an all-tau run, through the pipeline that
// evaluates the grid in blocks on several threads: Stable32's run rule
// (beyond half the largest AF, the previous AF's type) must hold across the
// blocks. Reference: Stable32's phase_dat_oadev.txt, every row.
TEST_F(Cli, AllTauNoiseTypesFollowStable32sRun) {
  const Result r = run("dev " + kPhaseDat + " --type phase --rate 1 --stat oadev --taus all --threads 2 --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto c = nlohmann::json::parse(r.out)["columns"][0];
  std::ifstream table(std::string(CUBECAL_SHARED_DATA) + "/stable32/phasedat/phase_dat_oadev.txt");
  std::string line;
  std::size_t rows = 0;
  while (std::getline(table, line)) {
    if (line.find('#') != std::string::npos) continue;
    std::istringstream ss(line);
    double af = 0, tau = 0, n = 0, alpha = 0;
    if (!(ss >> af >> tau >> n >> alpha)) continue;
    const auto k = static_cast<std::size_t>(af) - 1;  // --taus all: every AF from 1
    ASSERT_LT(k, c["alpha"].size());
    EXPECT_EQ(c["alpha"][k].get<int>(), static_cast<int>(alpha)) << "AF " << af;
    ++rows;
  }
  EXPECT_EQ(rows, 139u);
}

// --short-ci widest: the same intervals where 30 or more averages remain,
// wider ones (never narrower) below, on PHASE.DAT's octave OADEV.
TEST_F(Cli, ShortCiWidestWidensOnlyTheShortSeriesIntervals) {
  const std::string cmd = "dev " + kPhaseDat + " --type phase --rate 1 --stat oadev --format json";
  const Result a = run(cmd);
  const Result b = run(cmd + " --short-ci widest");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  const auto ca = nlohmann::json::parse(a.out)["columns"][0];
  const auto cb = nlohmann::json::parse(b.out)["columns"][0];
  ASSERT_EQ(ca["tau"].size(), cb["tau"].size());
  std::size_t wider = 0;
  for (std::size_t i = 0; i < ca["tau"].size(); ++i) {
    const double m = ca["tau"][i].get<double>();
    const bool short_series = (1000.0 / m) < 30.0;
    const double la = ca["lo"][i], ha = ca["hi"][i], lb = cb["lo"][i], hb = cb["hi"][i];
    if (!short_series) {
      EXPECT_EQ(la, lb) << "tau " << m;
      EXPECT_EQ(ha, hb) << "tau " << m;
    } else {
      EXPECT_LE(lb, la) << "tau " << m;
      EXPECT_GE(hb, ha) << "tau " << m;
      wider += (hb - lb) > (ha - la) * 1.01;
    }
  }
  EXPECT_GE(wider, 2u) << "the B1 rows (AF 64, 128) should widen";
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

// Lines of `text` that contain `what`.
std::vector<std::string> lines_with(const std::string& text, const std::string& what) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.find(what) != std::string::npos) out.push_back(line);
  return out;
}

// A listed tau beyond the statistic's largest averaging factor is said on
// stderr (one warning line for the run, whatever the format) and in the
// JSON, never dropped silently. PHASE.DAT: 1001 phase points, so OADEV
// reaches m = 250 and ADEV m = 200.
TEST_F(Cli, ListedTausBeyondTheLimitAreReported) {
  const Result j = run("dev " + kPhaseDat + " --type phase --rate 1 --taus 1,10,1e6 --format json");
  ASSERT_EQ(j.code, 0) << j.err;
  const auto w = lines_with(j.err, "warning");
  ASSERT_EQ(w.size(), 1u) << j.err;
  EXPECT_EQ(w[0],
            "cubecal: warning: --taus: 1 listed tau not evaluated: 1e+06 s (oadev needs at least "
            "4m+1 = 4000001 phase samples for m = 1000000, the record has 1001) (record longer data "
            "or list smaller taus)");
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["columns"][0]["tau"], nlohmann::json({1.0, 10.0}));
  ASSERT_EQ(doc["excluded_taus"].size(), 1u);
  EXPECT_EQ(doc["excluded_taus"][0]["tau_s"], 1e6);
  EXPECT_EQ(doc["excluded_taus"][0]["af"], 1000000);
  EXPECT_EQ(doc["excluded_taus"][0]["needs_samples"], 4000001);
  EXPECT_EQ(doc["excluded_taus"][0]["samples"], 1001);
  EXPECT_TRUE(doc["merged_taus"].empty());

  // Each statistic its own limit: 200 fits ADEV, 201 does not; the table
  // says it on stderr too, and a merged tau gets a note.
  const Result t = run("dev " + kPhaseDat + " --type phase --rate 1 --stat adev --taus 200,201,250,10,10.2");
  ASSERT_EQ(t.code, 0) << t.err;
  const auto tw = lines_with(t.err, "warning");
  ASSERT_EQ(tw.size(), 1u) << t.err;
  EXPECT_NE(tw[0].find("2 listed taus not evaluated: 201 s (adev needs at least 5m+1 = 1006 phase samples for "
                       "m = 201, the record has 1001); 250 s (adev needs at least 5m+1 = 1251"),
            std::string::npos)
      << tw[0];
  EXPECT_EQ(lines_with(t.err, "note: --taus"),
            std::vector<std::string>{"cubecal: note: --taus: listed taus on the same averaging factor are one "
                                     "point: 10.2 s with 10 s (m = 10)"});

  // A generated grid ends at the limit: nothing to say.
  const Result o = run("dev " + kPhaseDat + " --type phase --rate 1 --taus all --no-ci --format csv");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(o.err.find("--taus"), std::string::npos) << o.err;
}

TEST_F(Cli, AnalyzeReportsListedTausBeyondTheLimit) {
  std::string csv = "gx_dps\n";
  for (int i = 0; i < 2000; ++i) csv += std::to_string(0.01 * std::sin(0.7 * i * i)) + "\n";
  const std::string f = write("w.csv", csv);
  const std::string out = path("an");
  const Result r = run("analyze " + f + " --rate 10 --taus 0.1,1,10,50,100 --max-samples 1000 --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto w = lines_with(r.err, "warning: --taus");
  ASSERT_EQ(w.size(), 1u) << r.err;
  EXPECT_EQ(w[0],
            "cubecal: warning: --taus: 1 listed tau not evaluated: 100 s (oadev needs at least 4m = 4000 "
            "samples for m = 1000, the record has 2000); 1 listed tau left out of the model fit: 50 s (oadev "
            "needs at least 4m = 2000 samples for m = 500, the part the model is fitted on has 1000) (record "
            "longer data or list smaller taus)");
  std::ifstream in(dir_ / "an" / "analysis.json");
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["excluded_taus"].size(), 1u);
  EXPECT_EQ(j["excluded_taus"][0]["tau_s"], 100.0);
  EXPECT_EQ(j["excluded_taus"][0]["reason"],
            "oadev needs at least 4m = 4000 samples for m = 1000, the record has 2000");
  ASSERT_EQ(j["model_excluded_taus"].size(), 1u);
  EXPECT_EQ(j["model_excluded_taus"][0]["tau_s"], 50.0);
  EXPECT_EQ(j["channels"][0]["adev"]["tau"].size(), 4u);
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
  for (int i = 0; i < 200; ++i)
    text += std::to_string(i < 100 ? i * 0.1 : 20.0 + i * 0.1) + "," + std::to_string((i * 7919) % 13) + "\n";
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
  const Result r = run("demo --hours 2 --out " + dir_.string() + "/d");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"sport_static.csv.gz", "analysis.json", "adev.csv", "drift.csv", "imu.yaml"})
    EXPECT_TRUE(fs::exists(dir_ / "d" / f)) << f;
  EXPECT_NE(r.out.find("N paper"), std::string::npos);
  const Result again = run("demo --hours 2 --out " + dir_.string() + "/d");
  EXPECT_EQ(again.code, 0) << again.err;  // its own earlier output is replaced
  fs::create_directories(dir_ / "mine");
  write("mine/analysis.json", "user data");
  const Result foreign = run("demo --hours 2 --out " + (dir_ / "mine").string());
  EXPECT_EQ(foreign.code, 2);
  std::ifstream kept(dir_ / "mine" / "analysis.json");
  std::string s;
  std::getline(kept, s);
  EXPECT_EQ(s, "user data");
}

TEST_F(Cli, DemoAnalysisIsWhatItsReproduceCommandGives) {
  // The demo analyzes the record it holds in memory; the command it prints
  // analyzes the file it wrote: the same numbers, key for key.
  const std::string d = (dir_ / "demo").string();
  const Result r = run("demo --hours 2 --seed 5 --out " + d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string tag = "Reproduce the analysis: cubecal ";
  const auto at = r.out.find(tag);
  ASSERT_NE(at, std::string::npos) << r.out;
  std::string cmd = r.out.substr(at + tag.size());
  cmd = cmd.substr(0, cmd.find('\n'));
  const Result re = run(cmd + " --out " + (dir_ / "re").string());
  ASSERT_EQ(re.code, 0) << re.err;
  auto load = [](const fs::path& p) {
    std::ifstream f(p);
    return nlohmann::json::parse(f);
  };
  nlohmann::json a = load(dir_ / "demo" / "analysis.json"), b = load(dir_ / "re" / "analysis.json");
  EXPECT_EQ(a["command"], "cubecal " + cmd);
  a.erase("command");
  b.erase("command");
  EXPECT_EQ(a["channels"][0]["noise"]["arw"], b["channels"][0]["noise"]["arw"]);
  EXPECT_TRUE(a == b) << "the demo's analysis.json and the reproduced one differ";
  // And the page of the demo says the confidence level of its intervals.
  std::ifstream page(dir_ / "demo" / "report.html");
  std::stringstream html;
  html << page.rdbuf();
  EXPECT_NE(html.str().find("<th>confidence of the intervals</th><td>68.3 %</td>"), std::string::npos);
}

TEST_F(Cli, ReportShowsTheConfidenceLevelOfTheResult) {
  const std::string rec = (dir_ / "c.csv").string();
  ASSERT_EQ(run("simulate --preset sport-gyro --rate 10 --duration 1h --temp const:25 --out " + rec).code, 0);
  const std::string out = (dir_ / "c").string();
  const Result an = run("analyze " + rec + " --columns gx,gy,gz --unit deg/s --ci 0.95 --out " + out);
  ASSERT_EQ(an.code, 0) << an.err;
  std::ifstream f(dir_ / "c" / "analysis.json");
  EXPECT_EQ(nlohmann::json::parse(f)["ci"], 0.95);
  // cubecal report DIR reads it from analysis.json, not from the command line.
  const Result rep = run("report " + out);
  if (rep.code != 0 && rep.err.find("gnuplot not found") != std::string::npos) GTEST_SKIP() << "no gnuplot";
  ASSERT_EQ(rep.code, 0) << rep.err;
  std::ifstream page(dir_ / "c" / "report.html");
  std::stringstream html;
  html << page.rdbuf();
  EXPECT_NE(html.str().find("<th>confidence of the intervals</th><td>95 %</td>"), std::string::npos);
  EXPECT_NE(html.str().find("id=\"fig-drift_rate\""), std::string::npos) << "drift series from drift.csv";
}

TEST_F(Cli, SimulateThenAnalyzeRoundTrip) {
  // simulate writes what the readers take; analyze recovers the preset's
  // white noise; --model analysis.json simulates the measured sensor again.
  const std::string rec = (dir_ / "g.csv").string();
  const Result s = run("simulate --preset sport-gyro --rate 10 --duration 2h --seed 3 --temp const:25 --out " + rec);
  ASSERT_EQ(s.code, 0) << s.err;
  const Result same = run("simulate --preset sport-gyro --rate 10 --duration 2h --seed 3 --temp const:25 --out " +
                          (dir_ / "g2.csv").string());
  ASSERT_EQ(same.code, 0) << same.err;
  std::ifstream a(rec), b(dir_ / "g2.csv");
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  EXPECT_EQ(sa.str(), sb.str()) << "same seed, same bytes";
  EXPECT_EQ(run("simulate --preset sport-gyro --duration 1h --out " + rec).code, 2) << "existing file kept";

  const std::string out = (dir_ / "an").string();
  const Result an =
      run("analyze " + rec + " --columns gx,gy,gz --unit deg/s --model-lsb 145.6 --out " + out + " --format json");
  ASSERT_EQ(an.code, 0) << an.err;
  const auto j = nlohmann::json::parse(an.out);
  const double sn = j["channels"][2]["model"]["sigma_n"].get<double>();
  EXPECT_NEAR(sn / 13.0e-3, 1.0, 0.03);  // sport-gyro z white noise
  for (const char* f : {"analysis.json", "adev.csv", "drift.csv", "imu.yaml"})
    EXPECT_TRUE(fs::exists(dir_ / "an" / f)) << f;
  const Result again = run("analyze " + rec + " --columns gx,gy,gz --unit deg/s --out " + out);
  EXPECT_EQ(again.code, 2) << "results are not replaced without --force";

  const Result re = run("simulate --model " + out + "/analysis.json --duration 1h --out " + (dir_ / "re.csv").string());
  ASSERT_EQ(re.code, 0) << re.err;
  std::ifstream rr(dir_ / "re.csv");
  std::string header;
  std::getline(rr, header);
  EXPECT_EQ(header, "t,gx,gy,gz,temp");
}

TEST_F(Cli, SimulateAndAnalyzeUsageErrors) {
  const std::string rec = (dir_ / "x.csv").string();
  EXPECT_EQ(run("simulate --preset nope --out " + rec).code, 2);
  EXPECT_EQ(run("simulate --preset sport-gyro --duration 3x --out " + rec).code, 2);
  EXPECT_EQ(run("simulate --out " + rec).code, 2);
  const Result bad_model = run("simulate --model " + kPhaseDat + " --out " + rec);
  EXPECT_EQ(bad_model.code, 2);
  EXPECT_TRUE(one_error_line(bad_model)) << bad_model.err;
  EXPECT_EQ(run("analyze " + kPhaseDat + " --rate 1 --unit furlongs").code, 2);
  EXPECT_EQ(run("analyze " + kPhaseDat + " --rate 1 --unit deg/s,deg/s").code, 2);
}

}  // namespace

namespace {

TEST_F(Cli, TurnonAndCompareOnSimulatedPowerCycles) {
  // Five power cycles of the paper's gyro: each run draws a new turn-on bias
  // (std (23.9, 11.9, 14.9) mdeg/s); turnon must see runs differing by about that.
  std::string files;
  for (int s = 1; s <= 5; ++s) {
    const std::string f = (dir_ / ("run" + std::to_string(s) + ".csv")).string();
    ASSERT_EQ(run("simulate --preset sport-gyro --rate 10 --duration 20m --temp const:25 --seed " + std::to_string(s) +
                  " --out " + f)
                  .code,
              0);
    files += " " + f;
  }
  const Result t = run("turnon" + files + " --columns gx,gy,gz --unit deg/s --format json");
  ASSERT_EQ(t.code, 0) << t.err;
  const auto j = nlohmann::json::parse(t.out);
  ASSERT_EQ(j["runs"].size(), 5u);
  ASSERT_EQ(j["channels"].size(), 3u);
  const auto& x = j["channels"][0];
  EXPECT_LT(x["turn_on_bias_lo"].get<double>(), x["turn_on_bias"].get<double>());
  EXPECT_GT(x["turn_on_bias_hi"].get<double>(), x["turn_on_bias"].get<double>());
  // 5 draws of a 23.9 mdeg/s std plus the bias random walk over 20 min: the
  // interval of the estimate must reach the preset value.
  EXPECT_LT(x["turn_on_bias_lo"].get<double>(), 0.0239 * 1.5);
  const Result c = run("compare" + files + " --columns gx,gy,gz --unit deg/s");
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.out.find("run5.csv"), std::string::npos);
  EXPECT_EQ(run("turnon " + (dir_ / "run1.csv").string() + " --unit deg/s").code, 2) << "one run is not enough";
}

TEST_F(Cli, CalibrateTemperatureRecoversCoefficient) {
  const std::string f = (dir_ / "mag.csv").string();
  ASSERT_EQ(run("simulate --preset sport-mag --rate 1 --duration 48h --temp sine:25,10,21600 --seed 2 --out " + f).code,
            0);
  const Result r =
      run("calibrate temperature " + f + " --columns mx,my,mz --temp-col temp --unit mGauss --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (int a = 0; a < 3; ++a) {
    const auto& c = j["channels"][a];
    const double k = c["coeff"][1].get<double>(), s = c["coeff_sigma"][1].get<double>();
    EXPECT_NEAR(k, 0.7, 4 * s) << c["name"];
    EXPECT_EQ(c["coeff_units"][1], "mGauss/degC");
  }
  EXPECT_EQ(run("calibrate temperature " + f + " --columns mx --temp-col nope").code, 2);
}

// analyze with a temperature column fits the sensor models to the
// compensated series as well and reports both. The simulator draws the same
// noise whatever the model (common random numbers), so the same seed without
// the temperature term is the compensated record's truth: its model must
// match the compensated one, while the record's own model is inflated by the
// temperature swing.
TEST_F(Cli, AnalyzeWithTemperatureReportsTheCompensatedModel) {
  const std::string swing = path("swing.csv"), flat = path("flat.csv");
  ASSERT_EQ(
      run("simulate --preset sport-mag --rate 1 --duration 24h --temp sine:25,5,21600 --seed 4 --out " + swing).code,
      0);
  ASSERT_EQ(run("simulate --preset sport-mag --rate 1 --duration 24h --temp const:25 --seed 4 --out " + flat).code, 0);
  const Result r = run("analyze " + swing + " --columns mx,my,mz --unit mGauss --temp-col temp --model-lsb 1.3 --out " +
                       path("swing"));
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(run("analyze " + flat + " --columns mx,my,mz --unit mGauss --model-lsb 1.3 --out " + path("flat")).code, 0);
  EXPECT_NE(r.out.find("jointly with the random-walk bias (least squares"), std::string::npos) << r.out;
  const auto read = [&](const std::string& dir) {
    std::ifstream f(path(dir) + "/analysis.json");
    return nlohmann::json::parse(f);
  };
  const auto j = read("swing"), k = read("flat");
  for (int a = 0; a < 3; ++a) {
    const auto& c = j["channels"][a];
    const auto& t = c["temperature"];
    const std::string w = c["name"].get<std::string>();
    EXPECT_EQ(t["method"], "random_walk_gls") << w;
    EXPECT_NEAR(t["coeff"][0].get<double>(), 0.7, 3 * t["coeff_sigma"][0].get<double>()) << w;
    EXPECT_TRUE(t["ols"]["coeff"].is_array()) << w;
    const double comp = t["compensated_model"]["sigma_mu"].get<double>();
    const double record = c["model"]["sigma_mu"].get<double>();
    const double truth = k["channels"][a]["model"]["sigma_mu"].get<double>();
    EXPECT_NEAR(comp / truth, 1.0, 0.05) << w << ": the compensated model is the temperature-free record's";
    EXPECT_GT(record / truth, 3.0) << w << ": the swing inflates the record's own sigma_mu";
    EXPECT_NEAR(t["compensated_model"]["sigma_n"].get<double>(), k["channels"][a]["model"]["sigma_n"].get<double>(),
                0.01 * k["channels"][a]["model"]["sigma_n"].get<double>())
        << w;
    // The console line of the compensated model, with this sigma_mu.
    EXPECT_NE(r.out.find(fmt_sigma_mu(comp)), std::string::npos) << w << "\n" << r.out;
  }
}

// ---------------------------------------------------------------------------
// Hints by CalibrationReason (src/cli/calibration_hints.cpp): the table
// itself, then end to end (the core throws CalibrationError with the reason;
// a plain std::invalid_argument would get no hint).

using cubecal::CalibrationReason;
using cubecal::cli::calibration_hint;
using cubecal::cli::CalibrationCommand;
using cubecal::cli::HintContext;

TEST(CalibrationHints, OneHintPerCommandAndReason) {
  HintContext mag{CalibrationCommand::mag};
  mag.bias_only = true;
  EXPECT_EQ(calibration_hint(CalibrationReason::poor_coverage, mag), "add --allow-partial to fit anyway");
  mag.bias_only = false;
  EXPECT_EQ(calibration_hint(CalibrationReason::poor_coverage, mag),
            "add --allow-partial to fit anyway and judge the uncertainties, or use --method twostep");
  mag.field_col = true;
  EXPECT_EQ(calibration_hint(CalibrationReason::field_norm, mag), "check --field-col");
  EXPECT_EQ(calibration_hint(CalibrationReason::not_converged, mag), "");

  HintContext mp{CalibrationCommand::multiposition};
  for (auto r : {CalibrationReason::too_few_intervals, CalibrationReason::initial_static})
    EXPECT_EQ(calibration_hint(r, mp), "check --init-static (the sensor must be still then) and --rate/--time-col");
  // A scale guess that leads nowhere: the accelerometer's guesses in the
  // accelerometer step, the gyroscope's in the gyroscope step.
  EXPECT_NE(calibration_hint(CalibrationReason::scale_guess, mp).find("--acc-scale"), std::string::npos);
  mp.gyroscope = true;
  EXPECT_EQ(calibration_hint(CalibrationReason::scale_guess, mp), "give --gyro-scale in rad/s per count");
  EXPECT_EQ(calibration_hint(CalibrationReason::poor_coverage, mp), "");

  HintContext rt{CalibrationCommand::rate_table};
  rt.reference_columns = true;
  EXPECT_NE(calibration_hint(CalibrationReason::no_plateaus, rt).find("--ref-columns"), std::string::npos);
  rt.reference_columns = false;
  EXPECT_NE(calibration_hint(CalibrationReason::no_plateaus, rt).find("schedule"), std::string::npos);
  EXPECT_EQ(calibration_hint(CalibrationReason::degenerate, rt), "the run must turn the gyro about each of its 3 axes");
}

// Points on a cap of the sphere (directions within 23 deg of +z): too little
// for TWOSTEP without --allow-partial.
std::string cap_points() {
  std::string text = "mx,my,mz\n";
  for (int k = 0; k < 300; ++k) {
    const double th = 0.4 * (k % 17) / 16.0, ph = 0.37 * k;
    text += std::to_string(40 * std::sin(th) * std::cos(ph) + 3) + "," +
            std::to_string(40 * std::sin(th) * std::sin(ph) - 2) + "," + std::to_string(40 * std::cos(th) + 1) + "\n";
  }
  return text;
}

TEST_F(Cli, CalibrateMagPoorCoverageHintsAllowPartial) {
  const std::string cap = write("cap.csv", cap_points());
  const Result two = run("calibrate mag " + cap + " --method twostep");
  EXPECT_EQ(two.code, 2);
  EXPECT_TRUE(one_error_line(two)) << two.err;
  EXPECT_NE(two.err.find("(add --allow-partial to fit anyway)"), std::string::npos) << two.err;
  const Result ell =
      run("calibrate mag " + std::string(CUBECAL_SHARED_DATA) + "/mag/cubesat-adcs/meas_for_mag_calib.csv");
  EXPECT_EQ(ell.code, 2);
  EXPECT_NE(ell.err.find("--allow-partial"), std::string::npos) << ell.err;
  EXPECT_NE(ell.err.find("or use --method twostep"), std::string::npos) << ell.err;
  EXPECT_EQ(run("calibrate mag " + cap + " --method twostep --allow-partial").code, 0);
}

TEST_F(Cli, CalibrateMagBadFieldColumnHintsFieldCol) {
  std::string text = "mx,my,mz,F\n";
  for (int k = 0; k < 200; ++k) {
    const double th = 3.14159 * (k % 19) / 18.0, ph = 0.37 * k;
    text += std::to_string(40 * std::sin(th) * std::cos(ph)) + "," + std::to_string(40 * std::sin(th) * std::sin(ph)) +
            "," + std::to_string(40 * std::cos(th)) + ",0\n";
  }
  const std::string f = write("f.csv", text);
  const Result r = run("calibrate mag " + f + " --columns mx,my,mz --method twostep --field-col F");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("(check --field-col)"), std::string::npos) << r.err;
}

TEST_F(Cli, CalibrateMultipositionTooFewPosesHintsInitStatic) {
  const Result r = run("calibrate multiposition " + std::string(CUBECAL_SHARED_DATA) +
                       "/imu/mpu6050/example_data_calibration.csv --skip-rows 4 --acc-columns ax,ay,az "
                       "--gyro-columns gx,gy,gz --rate 100 --g 9.81 --init-static 30 --gyro-scale 1.3323e-4");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("fewer than 12 static intervals"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(check --init-static (the sensor must be still then) and --rate/--time-col)"),
            std::string::npos)
      << r.err;
}

}  // namespace
