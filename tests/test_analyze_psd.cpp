// analyze --psd: on a simulated SPORT gyro the spectrum's N and K agree with
// the Allan curve's and with the simulated truth; the spectral part is what
// `psd --bins-per-decade 20` gives; the streamed analysis refuses it; the
// report shows both views; files with and without it load.
// The values are read through analysis.json, as a user of the command
// would; tests/test_analyze.cpp checks the typed result.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <tuple>

#include "cli_runner.hpp"
#include "report_check.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/report/plot.hpp"
#include "cubecal/sim/presets.hpp"

namespace cubecal::test {
namespace {

namespace fs = std::filesystem;

class AnalyzePsd : public TempDirTest {
 protected:
  // The SPORT gyro preset at 10 Hz (gx, gy, gz in deg/s, and temp).
  std::string simulate(const std::string& duration, int seed) {
    const std::string file = path("gyro.csv");
    const CliRun r = run_cubecal("simulate --preset sport-gyro --rate 10 --duration " + duration + " --seed " +
                                 std::to_string(seed) + " --out " + file);
    EXPECT_EQ(r.code, 0) << r.err;
    return file;
  }
  static nlohmann::json read_json(const std::string& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  }
};

// A term of analysis.json's spectral part by its letter.
const nlohmann::json& spectral_term(const nlohmann::json& channel, const std::string& letter) {
  for (const auto& t : channel.at("spectral").at("terms"))
    if (t.at("term") == letter) return t;
  throw std::runtime_error("no term " + letter);
}

TEST_F(AnalyzePsd, TwoViewsAgreeWithEachOtherAndWithTheSimulatedTruth) {
  // 72 h at 10 Hz, seed 1 (docs/formulas/spectral.md §7.3). The truth of
  // each axis: K = sigma_mu sqrt(dt) (the walk's increments sigma_mu dt per
  // sample); N = sqrt(sigma_n^2 + q^2 / 12) sqrt(dt), the white noise and
  // the quantizer's (q = 1 / lsb: with sigma_n about 2 q the truncation error
  // is uniform and independent of the signal to exp(-2 pi^2 sigma_n^2 / q^2)
  // ~ 1e-34, Widrow's condition).
  const std::string file = simulate("72h", 1);
  const CliRun r = run_cubecal("analyze " + file + " --columns gx,gy,gz --unit deg/s --psd --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const TriadModel model = preset("sport-gyro");
  const double dt = 0.1, q = 1.0 / model.lsb;
  const Unit u = *parse_unit("deg/s");
  ASSERT_EQ(j.at("channels").size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) {
    const auto& ch = j.at("channels")[c];
    const AxisModel& a = model.axes[c];
    const double n_true = std::sqrt(a.white_sigma * a.white_sigma + q * q / 12.0) * std::sqrt(dt);
    const double k_true = a.bias_sigma * std::sqrt(dt);
    for (const auto& [letter, term, truth] : {std::tuple{"N", Term::N, n_true}, std::tuple{"K", Term::K, k_true}}) {
      // In deg/sqrt(h) and deg/h/sqrt(h), as analysis.json holds the terms.
      const double shown = display(TermEstimate{true, truth, 0.0, 0.0, 0.0}, term, u).value;
      const auto& t = spectral_term(ch, letter);
      const double s = t.at("value").get<double>(), ss = t.at("sigma").get<double>();
      const double f = t.at("allan_fit").at("value").get<double>(), fs_ = t.at("allan_fit").at("sigma").get<double>();
      const double d = t.at("difference_sigmas").get<double>();
      std::printf(
          "  %s %s: truth %.5g, spectrum %.5g +- %.2g (%+.2f sigma), Allan fit %.5g +- %.2g (%+.2f sigma); "
          "spectrum - fit %+.2f combined sigma\n",
          ch.at("name").get<std::string>().c_str(), letter, shown, s, ss, (s - shown) / ss, f, fs_, (f - shown) / fs_,
          d);
      EXPECT_EQ(t.at("unit"), display(TermEstimate{}, term, u).unit);
      EXPECT_NEAR(d, (s - f) / std::hypot(ss, fs_), 1e-9);
      EXPECT_LT(std::abs(d), 3.0) << letter << " of " << ch.at("name");
      EXPECT_LT(std::abs(s - shown), 3.0 * ss) << letter << " of " << ch.at("name") << " from the spectrum";
      EXPECT_LT(std::abs(f - shown), 3.0 * fs_) << letter << " of " << ch.at("name") << " from the Allan curve";
      EXPECT_GT(ss, 0.0);
      EXPECT_LT(ss, 0.02 * s);  // the test means something: the spectrum knows N and K to 2 %
    }
  }
}

TEST_F(AnalyzePsd, SpectralPartIsPsdAtTwentyBandsPerDecade) {
  const std::string file = simulate("6h", 2);
  const std::string dir = path("out");
  const CliRun a = run_cubecal("analyze " + file + " --columns gx,gy,gz --unit deg/s --psd --out " + dir);
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("spectrum  N "), std::string::npos) << a.out;
  const CliRun p = run_cubecal("psd " + file + " --columns gx,gy,gz --unit deg/s --bins-per-decade 20 --format json");
  ASSERT_EQ(p.code, 0) << p.err;
  const auto aj = read_json(dir + "/analysis.json");
  const auto pj = nlohmann::json::parse(p.out);
  ASSERT_EQ(aj.at("channels").size(), 3u);
  ASSERT_EQ(pj.at("channels").size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) {
    const auto& s = aj.at("channels")[c].at("spectral");
    const auto& q = pj.at("channels")[c];
    EXPECT_EQ(aj.at("channels")[c].at("name"), q.at("name"));
    for (const char* key : {"frequency_hz", "density", "edf", "bins"})
      EXPECT_EQ(s.at("spectrum").at(key), q.at(key)) << key;
    EXPECT_EQ(s.at("spectrum").at("density_unit"), q.at("density_unit"));
    EXPECT_EQ(s.at("fit"), q.at("fit"));
    for (const char* key : {"window", "segment_length", "overlap", "overlap_samples", "detrend", "segments",
                            "samples_used", "resolution_hz", "enbw_hz"})
      EXPECT_EQ(s.at("welch").at(key), pj.at("welch").at(key)) << key;
    EXPECT_EQ(s.at("welch").at("pieces"), pj.at("pieces"));
    // Each term is the one psd prints for the same coefficient.
    std::size_t matched = 0;
    for (const auto& t : q.at("allan_terms")) {
      const auto& mine = spectral_term(aj.at("channels")[c], t.at("term").get<std::string>());
      EXPECT_EQ(mine.at("alpha"), t.at("alpha"));
      EXPECT_EQ(mine.at("unit"), t.at("display").at("unit"));
      if (t.at("valid").get<bool>()) {
        EXPECT_EQ(mine.at("value"), t.at("display").at("value"));
        EXPECT_EQ(mine.at("sigma"), t.at("display").at("sigma"));
        ++matched;
      } else {
        EXPECT_TRUE(mine.at("value").is_null());
      }
    }
    EXPECT_GE(matched, 2u);  // N and K at least
  }
}

TEST_F(AnalyzePsd, StreamedAnalysisRefusesPsdInOneLine) {
  const std::string file = simulate("1h", 3);
  const CliRun r =
      run_cubecal("analyze " + file + " --columns gx,gy,gz --unit deg/s --psd --stream --out " + path("out"));
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_FALSE(fs::exists(path("out"))) << "refused before --out is made";
  EXPECT_NE(r.err.find("--psd: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("whole record"), std::string::npos) << r.err;
  // The same run without it streams.
  const CliRun s = run_cubecal("analyze " + file + " --columns gx,gy,gz --unit deg/s --stream");
  EXPECT_EQ(s.code, 0) << s.err;
}

TEST_F(AnalyzePsd, ReportShowsBothViewsAndFilesWithAndWithoutThemLoad) {
  if (!report::find_gnuplot()) GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox (scripts/install-deps.sh)";
  const std::string file = simulate("2h", 4);
  const std::string dir = path("with");
  const CliRun a = run_cubecal("analyze " + file + " --columns gx,gy,gz --unit deg/s --psd --out " + dir + " --report");
  ASSERT_EQ(a.code, 0) << a.err;
  const auto page = [&](const std::string& d) { return slurp(fs::path(d) / "report.html"); };
  std::string html = page(dir);
  EXPECT_EQ(count(html, ": Allan curve vs spectrum"), 3u);
  EXPECT_NE(html.find("K, rate random walk"), std::string::npos);
  for (const char* ch : {"gx", "gy", "gz"})
    for (const char* ext : {".dat", ".gp", ".svg", ".png"})
      EXPECT_TRUE(fs::exists(fs::path(dir) / "plots" / (std::string("psd_") + ch + ext))) << ch << ext;
  // Again from analysis.json alone (cubecal report): the same section.
  const CliRun rep = run_cubecal("report " + dir + " --force");
  ASSERT_EQ(rep.code, 0) << rep.err;
  EXPECT_EQ(count(page(dir), ": Allan curve vs spectrum"), 3u);
  // A file with the spectral part feeds simulate --model.
  const CliRun sim = run_cubecal("simulate --model " + dir + "/analysis.json --duration 60s --out " + path("twin.csv"));
  EXPECT_EQ(sim.code, 0) << sim.err;
  // One without it (as every file before analyze --psd): no section, no
  // spectrum plots, and the stale ones of the earlier page removed.
  const CliRun plain = run_cubecal("analyze " + file + " --columns gx,gy,gz --unit deg/s --out " + dir + " --force");
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(read_json(dir + "/analysis.json").at("channels")[0].count("spectral"), 0u);
  const CliRun old = run_cubecal("report " + dir + " --force");
  ASSERT_EQ(old.code, 0) << old.err;
  html = page(dir);
  EXPECT_EQ(count(html, "Allan curve vs spectrum"), 0u);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "plots" / "psd_gx.svg"));
  EXPECT_NE(html.find("allan_rate"), std::string::npos);
}

TEST_F(AnalyzePsd, HelpNamesTheOption) {
  const CliRun r = run_cubecal("analyze --help");
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--psd"), std::string::npos);
  EXPECT_NE(r.out.find("not with --stream"), std::string::npos);
}

}  // namespace
}  // namespace cubecal::test
