// The binary end to end on issue 10's "silent wrong results": each case
// here gave a wrong number or accepted a wrong option with exit 0 before.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;

using Result = cubecal::test::CliRun;
using cubecal::test::one_error_line;
Result run(const std::string& args) { return cubecal::test::run_cubecal(args); }

class CliHardening : public cubecal::test::TempDirTest {};

[[maybe_unused]] std::string read_file(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// --- 1. simulate --model keeps the model's rate ---------------------------

TEST_F(CliHardening, SimulateModelRescalesToTheRequestedRate) {
  // A 100 Hz sensor measured by analyze, simulated again at 10 Hz and at its
  // own rate: the ARW (N) of the new record is the measured one within the
  // reported uncertainties (3 sigma of the difference); before, at 10 Hz it
  // came out sqrt(10) = 3.2 times too large.
  const std::string rec = path("g100.csv");
  ASSERT_EQ(run("simulate --preset sport-gyro --rate 100 --duration 1h --seed 3 --temp const:25 --out " + rec).code, 0);
  const Result an = run("analyze " + rec + " --columns gx --unit deg/s --out " + path("an") + " --format json");
  ASSERT_EQ(an.code, 0) << an.err;
  const auto j100 = nlohmann::json::parse(an.out)["channels"][0]["noise"]["arw"];
  const std::string model = path("an") + "/analysis.json";

  const Result s10 =
      run("simulate --model " + model + " --rate 10 --duration 4h --seed 5 --temp const:25 --out " + path("g10.csv"));
  ASSERT_EQ(s10.code, 0) << s10.err;
  EXPECT_NE(s10.err.find("at 10 Hz"), std::string::npos) << s10.err;
  const Result a10 = run("analyze " + path("g10.csv") + " --columns gx --unit deg/s --format json");
  ASSERT_EQ(a10.code, 0) << a10.err;
  const auto j10 = nlohmann::json::parse(a10.out)["channels"][0]["noise"]["arw"];
  const double n100 = j100["value"].get<double>(), n10 = j10["value"].get<double>();
  const double s = std::hypot(j100["sigma"].get<double>(), j10["sigma"].get<double>());
  EXPECT_LT(std::abs(n10 - n100), 3 * s) << "ARW at 10 Hz " << n10 << " vs measured at 100 Hz " << n100;

  // Without --rate the model is simulated at the rate it was measured at.
  const Result s_own = run("simulate --model " + model + " --duration 10m --temp const:25 --out " + path("own.csv"));
  ASSERT_EQ(s_own.code, 0) << s_own.err;
  EXPECT_NE(s_own.err.find("60000 samples at 100 Hz"), std::string::npos) << s_own.err;
}

TEST_F(CliHardening, PresetsKeepTheirNoiseDensityAtAnyRate) {
  // sport-gyro's x axis: sigma_n = 13.9e-3 deg/s per sample at 10 Hz, so
  // N = 13.9e-3 * sqrt(0.1 s) = 4.396e-3 deg/s/sqrt(Hz) whatever the rate.
  // Before, the 10 Hz per-sample sigma was used at every rate: N came out
  // sqrt(10) times too small at 100 Hz and sqrt(10) too large at 1 Hz. The
  // preset's quantizer (145.6 LSB per deg/s) stays per sample and adds its
  // own white noise, q^2/12 per sample: N^2 = 4.396e-3^2 + q^2/12 * dt.
  const double q = 1.0 / 145.6;
  for (const char* rate : {"1", "100"}) {
    const double dt = 1.0 / std::stod(rate);
    const double truth = std::sqrt(13.9e-3 * 13.9e-3 * 0.1 + q * q / 12.0 * dt);
    const std::string rec = path(std::string("p") + rate + ".csv");
    const std::string dur = std::string(rate) == "1" ? "48h" : "1h";
    ASSERT_EQ(run(std::string("simulate --preset sport-gyro --rate ") + rate + " --duration " + dur +
                  " --seed 11 --temp const:25 --out " + rec)
                  .code,
              0);
    const Result an = run("analyze " + rec + " --columns gx --unit deg/s --format json");
    ASSERT_EQ(an.code, 0) << an.err;
    // The simulator's white noise separated from its random walk: the
    // five-term fit's white term (deg/sqrt(h) = 60 deg/s/sqrt(Hz)). The
    // reported N is read at tau = 1 s, where at 1 Hz the preset's random walk
    // already adds a few per cent (its curve has its minimum at 8 s).
    const auto fit = nlohmann::json::parse(an.out)["channels"][0]["noise"]["fit"]["arw"];
    ASSERT_EQ(fit["unit"], "deg/sqrt(h)");
    const double n = fit["value"].get<double>() / 60.0, s = fit["sigma"].get<double>() / 60.0;
    EXPECT_LT(std::abs(n - truth), 3.0 * s) << rate << " Hz: N " << n << " ± " << s;
  }
}

// --- 2. default columns skip time and temperature ------------------------

TEST_F(CliHardening, DefaultColumnsLeaveOutTimeAndTemperature) {
  // simulate writes t,gx,gy,gz,temp: analyze without --columns took temp as
  // a fourth gyro channel.
  const std::string rec = path("s.csv");
  ASSERT_EQ(run("simulate --preset sport-gyro --rate 10 --duration 20m --seed 3 --out " + rec).code, 0);
  const Result an = run("analyze " + rec + " --unit deg/s --format json");
  ASSERT_EQ(an.code, 0) << an.err;
  const auto j = nlohmann::json::parse(an.out);
  ASSERT_EQ(j["channels"].size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(j["channels"][c]["name"], std::string("g") + "xyz"[c]);
  EXPECT_NE(an.err.find("columns gx,gy,gz (left out: t,temp;"), std::string::npos) << an.err;

  // The temperature column named by --temp-col is still the temperature.
  const Result tc = run("analyze " + rec + " --unit deg/s --temp-col temp --format json");
  ASSERT_EQ(tc.code, 0) << tc.err;
  EXPECT_EQ(nlohmann::json::parse(tc.out)["channels"].size(), 3u);

  // dev: a time column chosen by --time-col and a "Temperature" column are left out too.
  const std::string f = write("clock.csv", "clock,Temperature,y\n0,20,1\n1,20,2\n2,20,1.5\n3,20,1.2\n4,21,1.1\n");
  const Result d = run("dev " + f + " --time-col clock --taus 1 --format json");
  ASSERT_EQ(d.code, 0) << d.err;
  const auto dj = nlohmann::json::parse(d.out)["columns"];
  ASSERT_EQ(dj.size(), 1u);
  EXPECT_EQ(dj[0]["name"], "y");
  EXPECT_NE(d.err.find("columns y (left out: clock,Temperature;"), std::string::npos) << d.err;

  // Nothing left: one line saying so, exit 2.
  const std::string only = write("only.csv", "t,temp\n0,20\n0.1,20\n0.2,20\n0.3,20\n");
  const Result o = run("dev " + only);
  EXPECT_EQ(o.code, 2);
  EXPECT_TRUE(one_error_line(o)) << o.err;
  EXPECT_NE(o.err.find("only.csv: no data columns besides the time and temperature columns (t, temp)"),
            std::string::npos)
      << o.err;
}

// --- 3. --rate must agree with the time column -----------------------------

TEST_F(CliHardening, RateContradictingTheTimeColumnIsAnError) {
  const std::string rec = path("r.csv");
  ASSERT_EQ(run("simulate --preset sport-gyro --rate 10 --duration 10m --seed 3 --out " + rec).code, 0);
  for (const std::string cmd : {"dev", "analyze"}) {
    for (const std::string extra : {"", " --time-col t"}) {
      const Result r =
          run(cmd + " " + rec + " --columns gx --rate 20" + extra + (cmd == "analyze" ? " --unit deg/s" : ""));
      EXPECT_EQ(r.code, 2) << cmd << extra << ": " << r.err;
      EXPECT_TRUE(one_error_line(r)) << r.err;
      if (!extra.empty()) continue;  // --time-col: each stamp is checked against --rate (a "gap" at line 3)
      EXPECT_NE(
          r.err.find("--rate: " + rec +
                     ": the rate 20 Hz contradicts the time column 't' (10 Hz, median "
                     "interval 0.1 s): leave the rate out to take it from the time stamps, or fix the time column"),
          std::string::npos)
          << r.err;
    }
  }
  EXPECT_EQ(run("dev " + rec + " --columns gx --rate 5").code, 2);
  // Agreeing within the 1 % jitter tolerance, or without --rate: accepted.
  const Result ok = run("dev " + rec + " --columns gx --rate 10.05 --taus 1");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(run("dev " + rec + " --columns gx --taus 1").code, 0);
  // A file without a time column still takes --rate.
  const std::string nt = write("nt.csv", "y\n1\n2\n1.5\n1.2\n1.1\n");
  EXPECT_EQ(run("dev " + nt + " --rate 20 --taus 0.05").code, 0);
}

// --- 4. every printed number finite, or one clear error -------------------

TEST_F(CliHardening, RatesAndMagnitudesOutOfRangeAreRefused) {
  const std::string y = write("y.csv", "y\n1\n2\n1.5\n1.2\n1.1\n1.3\n1.7\n");
  for (const std::string rate : {"1e-300", "1e300"}) {
    // dev --rate 1e-300 printed -nan with exit 0.
    const Result r = run("dev " + y + " --rate " + rate);
    EXPECT_EQ(r.code, 2) << rate << ": " << r.out;
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_NE(r.err.find("--rate: the sampling rate " + rate.substr(0, 1) + "e"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Hz is outside the range 1e-09 to 1e+09 Hz"), std::string::npos) << r.err;
  }
  // Values near 1e300: analyze printed inf and -nan with exit 0.
  const std::string big = write("big.csv", "y\n1e300\n-1e300\n1.5e300\n1.2e300\n-1e300\n1.3e300\n1.7e300\n");
  for (const std::string& cmd : {"dev " + big + " --rate 1", "analyze " + big + " --rate 1 --unit deg/s"}) {
    const Result r = run(cmd);
    EXPECT_EQ(r.code, 2) << cmd << ": " << r.out;
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_NE(r.err.find("big.csv:2:1: value 1e+300 exceeds the magnitude 1e+100"), std::string::npos) << r.err;
  }
  const std::string tiny = write("tiny.csv", "y\n1e-300\n2e-300\n1e-300\n3e-300\n");
  const Result t = run("dev " + tiny + " --rate 1");
  EXPECT_EQ(t.code, 2) << t.out;
  EXPECT_NE(t.err.find("tiny.csv:5:1: value 3e-300 is the largest of its column"), std::string::npos) << t.err;
  // Time stamps 1 ps apart: a 1e12 Hz rate, refused at the time column.
  const std::string ps = write("ps.csv", "t,y\n0,1\n1e-12,2\n2e-12,3\n3e-12,4\n");
  const Result p = run("dev " + ps);
  EXPECT_EQ(p.code, 2) << p.out;
  EXPECT_NE(p.err.find("ps.csv:3:1: time stamps 1e-12 s apart give a rate of 1e+12 Hz"), std::string::npos) << p.err;

  // Inside the range, at both ends of rate and magnitude: every number printed is finite.
  std::string text = "y\n";
  std::uint64_t x = 12345;
  for (int i = 0; i < 3000; ++i) {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    text += std::to_string(static_cast<double>(x >> 11) / 9007199254740992.0 - 0.5) + "e99\n";
  }
  const std::string edge = write("edge.csv", text);
  for (const std::string rate : {"1e-9", "1e9"})
    for (const std::string cmd : {"dev", "analyze"}) {
      const Result r =
          run(cmd + " " + edge + " --rate " + rate + (cmd == "analyze" ? " --unit deg/s" : "") + " --format json");
      ASSERT_EQ(r.code, 0) << cmd << " " << rate << ": " << r.err;
      EXPECT_EQ(r.out.find("nan"), std::string::npos) << cmd << " " << rate;
      EXPECT_EQ(r.out.find("inf"), std::string::npos) << cmd << " " << rate;
      EXPECT_EQ(r.out.find("NaN"), std::string::npos) << cmd << " " << rate;
    }
}

// --- 5. every numeric option validated -----------------------------------

TEST_F(CliHardening, NumericOptionsOutOfRangeAreRefusedWithTheirName) {
  // analyze --drift-window -5 silently became 1000 s; negative counts wrapped
  // to 2^64 - 1 (--skip-rows, --cov-samples, --max-samples, --seed).
  const std::string rec = path("s.csv");
  ASSERT_EQ(run("simulate --preset sport-gyro --rate 10 --duration 10m --seed 3 --out " + rec).code, 0);
  const std::string a = "analyze " + rec + " --unit deg/s ";
  const std::string d = "dev " + rec + " --columns gx ";
  const std::string sim = "simulate --preset sport-gyro --duration 1m --out " + path("n.csv") + " ";
  const std::string demo = "demo --out " + path("demo") + " ";
  const struct {
    std::string args, expect;
  } cases[] = {
      {a + "--drift-window -5", "--drift-window: '-5' is not a positive number"},
      {a + "--drift-window 0", "--drift-window: '0' is not a positive number"},
      {a + "--cov-samples 1", "--cov-samples: '1' is not a whole number from 2 to"},
      {a + "--cov-samples -1", "--cov-samples: '-1' is not a whole number from 2 to"},
      {a + "--max-samples -1", "--max-samples: '-1' is not a whole number from 3 to"},
      {a + "--ci 1.5", "--ci: '1.5' is not a number from 0 to 1"},
      {a + "--temp-order 0", "--temp-order"},
      {d + "--ci -0.5", "--ci: '-0.5' is not a number from 0 to 1"},
      {d + "--alpha 7", "--alpha"},
      {d + "--rate -1", "--rate: '-1' is not a positive number"},
      {d + "--rate nan", "--rate: 'nan' is not a positive number"},
      {d + "--lsb -2", "--lsb: '-2' is not a positive number"},
      {d + "--skip-rows -1", "--skip-rows: '-1' is not a whole number from 0 to"},
      {d + "--threads 99999", "--threads: '99999' is not a whole number from 0 to 4096"},
      {sim + "--rate 1e300", "--rate: '1e300' is not a number from 1e-09 to 1e+09"},
      {sim + "--rate 0", "--rate: '0' is not a number from 1e-09 to 1e+09"},
      {sim + "--seed -1", "--seed: '-1' is not a whole number from 0 to"},
      {sim + "--seed 1.5", "--seed: '1.5' is not a whole number from 0 to"},
      {demo + "--seed -1", "--seed: '-1' is not a whole number from 0 to"},
      {demo + "--hours -1", "--hours: '-1' is not a number from 0.5 to 1000"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_TRUE(one_error_line(r)) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(path("n.csv")));
  EXPECT_FALSE(fs::exists(path("demo")));
  // In range: accepted.
  const Result ok = run(a + "--drift-window 60 --cov-samples 100 --max-samples 3000 --ci 0.95 --format json");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(run(d + "--skip-rows 0 --threads 1 --lsb 2 --taus 1").code, 0);
}

}  // namespace

// --- Standard output that cannot take the output (issue 33, item 6) ------

namespace {

// A run whose standard output is `redirect` (a shell redirection).
void expect_stdout_failure(const std::string& args, const std::string& redirect) {
  const Result r = run(args + " " + redirect);
  EXPECT_EQ(r.code, 1) << args << " " << redirect << "\n" << r.err;
  EXPECT_NE(r.err.find("cubecal: error: cannot write to standard output"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
}

}  // namespace

TEST_F(CliHardening, FullOrClosedStandardOutputFailsTheRun) {
  std::string csv = "t,g_dps\n";
  for (int i = 0; i < 64; ++i) csv += std::to_string(0.01 * i) + "," + std::to_string(1.0 + 0.01 * (i % 7)) + "\n";
  const std::string f = write("a.csv", csv);
  for (const std::string& args : {"dev " + f, "dev " + f + " --format json", "psd " + f, "analyze " + f}) {
    expect_stdout_failure(args, "> /dev/full");
    expect_stdout_failure(args, ">&-");
    const Result ok = run(args + " > /dev/null");
    EXPECT_EQ(ok.code, 0) << args << "\n" << ok.err;
  }
}

TEST_F(CliHardening, ClosedStandardOutputIsNotTakenByAnOutputFile) {
  // With descriptor 1 closed, the --out file must not become standard output.
  const std::string out = path("s.csv");
  const Result r = run("simulate --preset sport-gyro --duration 60 --rate 10 --out " + out + " >&-");
  EXPECT_EQ(r.code, 0) << r.err;
  const std::string text = read_file(out);
  EXPECT_EQ(text.rfind("t,gx,gy,gz", 0), 0u) << text.substr(0, 80);
}

// --- A noise type a statistic cannot take (issue 33, item 7) -------------

TEST_F(CliHardening, NoiseTypeBeyondTheStatisticIsRefused) {
  std::string csv = "t,g_dps\n";
  for (int i = 0; i < 256; ++i) csv += std::to_string(0.01 * i) + "," + std::to_string(1.0 + 0.01 * (i % 7)) + "\n";
  const std::string f = write("a.csv", csv) + " --columns g_dps";
  // The Allan family converges down to -2 (RWFM): -3 and -4 gave EDF 0 and [0, 0] with exit 0.
  for (const std::string stat : {"oadev", "mtotdev", "mdev", "totdev"})
    for (const std::string alpha : {"-3", "-4"}) {
      const Result r = run("dev " + f + " --stat " + stat + " --alpha " + alpha);
      EXPECT_TRUE(one_error_line(r)) << stat << " " << alpha << "\n" << r.out << r.err;
      EXPECT_NE(r.err.find("--alpha " + alpha + ": a noise type " + stat + " does not converge for (it takes -2 to +2"),
                std::string::npos)
          << r.err;
    }
  // Streamed, and with missing samples skipped, the same.
  EXPECT_TRUE(one_error_line(run("dev " + f + " --alpha -3 --stream")));
  const Result skipping = run("dev " + f + " --alpha -3 --gaps skip");  // a note on the missing samples first
  EXPECT_EQ(skipping.code, 2);
  EXPECT_NE(skipping.err.find("cubecal: error: --alpha -3: a noise type oadev does not converge"), std::string::npos)
      << skipping.err;
  // The Hadamard family takes them, with a positive EDF.
  const Result h = run("dev " + f + " --stat hdev --alpha -4 --format json");
  ASSERT_EQ(h.code, 0) << h.err;
  const auto j = nlohmann::json::parse(h.out);
  for (const auto& edf : j["columns"][0]["edf"]) EXPECT_GT(edf.get<double>(), 0.0) << j.dump();
  // Deviations without intervals need no noise type.
  EXPECT_EQ(run("dev " + f + " --alpha -3 --no-ci").code, 0);
}
