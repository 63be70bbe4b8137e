// cubecal psd: the spectrum the command prints is the library's, its fitted
// terms are there in every format, bad input is one error line with exit 2,
// and an existing --out is kept unless --force.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "report_check.hpp"
#include "cubecal/pipeline/welch_psd.hpp"
#include "cubecal/report/plot.hpp"
#include "cubecal/spectral/log_bins.hpp"

namespace cubecal::test {
namespace {

class PsdCli : public TempDirTest {
 protected:
  // gx, gy in deg/s at 10 Hz: white noise of 0.05 deg/s per sample plus a
  // walk on gx; written with 17 digits so the file holds the doubles.
  std::string record(std::size_t n, std::vector<double>* gx = nullptr) {
    std::mt19937_64 rng(42);
    std::normal_distribution<double> g(0.0, 1.0);
    std::ostringstream text;
    text.precision(17);
    text << "t,gx,gy\n";
    double walk = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      walk += 1e-3 * g(rng);
      const double x = 0.05 * g(rng) + walk;
      const double y = 0.05 * g(rng);
      if (gx) gx->push_back(x);
      text << static_cast<double>(i) / 10.0 << ',' << x << ',' << y << '\n';
    }
    return write("log.csv", text.str());
  }
};

TEST_F(PsdCli, JsonIsTheLibrarySpectrumWithTheFittedTerms) {
  std::vector<double> gx;
  const std::string file = record(20000, &gx);
  const CliRun r = run_cubecal("psd " + file + " --unit deg/s --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("command"), "psd");
  EXPECT_TRUE(j.at("one_sided").get<bool>());
  ASSERT_EQ(j.at("channels").size(), 2u);
  const auto& c = j.at("channels")[0];
  EXPECT_EQ(c.at("name"), "gx");
  EXPECT_EQ(c.at("density_unit"), "(deg/s)^2/Hz");
  const Psd p = pipeline::welch_psd(gx, 10.0);  // the defaults: hann, 2048, half overlap, constant
  EXPECT_EQ(j.at("welch").at("segment_length").get<std::size_t>(), p.segment_length);
  const auto density = c.at("density").get<std::vector<double>>();
  ASSERT_EQ(density.size(), p.size());  // json keeps every bin by default
  for (std::size_t k = 0; k < p.size(); ++k) EXPECT_NEAR(density[k], p.density[k], 1e-12 * p.density[k]) << k;
  // The (deg/h)^2/Hz column of a rate sensor is 3600^2 times the density.
  const auto rate_values = c.at("density_rate").at("values").get<std::vector<double>>();
  EXPECT_NEAR(rate_values[7] / density[7], 3600.0 * 3600.0, 1e-6);
  // The white noise of gy: N = 0.05 deg/s * sqrt(0.1 s) = 0.9487 deg/sqrt(h)
  // (x 60), within 4 stated sigma.
  const auto& gy = j.at("channels")[1];
  bool found = false;
  for (const auto& t : gy.at("allan_terms"))
    if (t.at("term") == "N") {
      found = true;
      EXPECT_EQ(t.at("display").at("unit"), "deg/sqrt(h)");
      const double n = t.at("display").at("value").get<double>();
      const double s = t.at("display").at("sigma").get<double>();
      EXPECT_NEAR(n, 0.05 * std::sqrt(0.1) * 60.0, 4.0 * s);
      EXPECT_GT(s, 0.0);
    }
  EXPECT_TRUE(found);
}

TEST_F(PsdCli, TableIsLogBinnedAndCsvKeepsEveryBin) {
  std::vector<double> gx;
  const std::string file = record(20000, &gx);
  const CliRun t = run_cubecal("psd " + file + " --unit deg/s --columns gx");
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("IEEE 952 terms"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("deg/sqrt(h)"), std::string::npos);
  EXPECT_NE(t.out.find("(deg/h)^2/Hz"), std::string::npos);
  const Psd lb = log_bin(pipeline::welch_psd(gx, 10.0), 10);
  // One table row per log band: count the lines that start with a number
  // after the header row of the spectrum.
  std::istringstream lines(t.out.substr(t.out.find("frequency [Hz]")));
  std::string line;
  std::getline(lines, line);
  std::size_t rows = 0;
  while (std::getline(lines, line)) ++rows;
  EXPECT_EQ(rows, lb.size());

  const CliRun c = run_cubecal("psd " + file +
                               " --columns gx --format csv --window blackman --segment 1000 "
                               "--overlap 0.25 --detrend linear");
  ASSERT_EQ(c.code, 0) << c.err;
  WelchOptions o;
  o.window = Window::blackman;
  o.segment_length = 1000;
  o.overlap = 0.25;
  o.detrend = Detrend::linear;
  const Psd p = pipeline::welch_psd(gx, 10.0, o);
  std::istringstream csv(c.out);
  std::getline(csv, line);
  EXPECT_EQ(line, "column,density_unit,frequency_hz,bins,edf,psd");
  std::size_t k = 0;
  while (std::getline(csv, line)) {
    ASSERT_LT(k, p.size());
    const double psd = std::stod(line.substr(line.rfind(',') + 1));
    EXPECT_NEAR(psd, p.density[k], 1e-12 * p.density[k]);
    EXPECT_EQ(line.substr(0, line.find(',', 3) + 1), "gx,u^2/Hz,");  // no unit given, none in the name
    ++k;
  }
  EXPECT_EQ(k, p.size());
  EXPECT_NE(c.err.find("no unit"), std::string::npos) << c.err;
}

TEST_F(PsdCli, BadInputIsOneErrorLineWithExitTwo) {
  const std::string bad = write("bad.csv", "t,gx\n0,1\n0.1,2\n0.2,x3\n0.3,4\n");
  CliRun r = run_cubecal("psd " + bad + " --unit deg/s");
  EXPECT_TRUE(one_error_line(r)) << r.code << " " << r.err;
  EXPECT_NE(r.err.find("bad.csv:4:"), std::string::npos) << r.err;

  const std::string file = record(500);
  r = run_cubecal("psd " + file + " --segment 1000");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--segment:"), std::string::npos) << r.err;

  r = run_cubecal("psd " + file + " --fmin 0.001");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--fmin:"), std::string::npos) << r.err;

  r = run_cubecal("psd " + file + " --window kaiser");
  EXPECT_TRUE(one_error_line(r)) << r.err;

  r = run_cubecal("psd " + file + " --overlap 1");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--overlap:"), std::string::npos) << r.err;

  r = run_cubecal("psd " + file + " --fit-min 4 --fit-max 4.2");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--fit-min/--fit-max:"), std::string::npos) << r.err;

  r = run_cubecal("psd " + file + " --segment 64 --fmin 0.5");
  EXPECT_TRUE(one_error_line(r)) << r.err;

  r = run_cubecal("psd " + file + " --unit furlongs");
  EXPECT_TRUE(one_error_line(r)) << r.err;

  r = run_cubecal("psd " + path("missing.csv"));
  EXPECT_TRUE(one_error_line(r)) << r.err;
}

TEST_F(PsdCli, AShortRecordGetsItsSpectrumAndSaysWhyNoFit) {
  // 500 samples: segments of 32, bins 10..15 hold two log bands, fewer than
  // the default model needs; a band asked for is an error instead (above).
  const std::string file = record(500);
  CliRun r = run_cubecal("psd " + file + " --unit deg/s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("power-law fit not made: the band"), std::string::npos) << r.out;
  r = run_cubecal("psd " + file + " --unit deg/s --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& c = j.at("channels")[0];
  EXPECT_TRUE(c.at("fit").is_null());
  EXPECT_FALSE(c.at("fit_error").get<std::string>().empty());
  EXPECT_EQ(c.at("density").size(), 17u);
  r = run_cubecal("psd " + file + " --unit deg/s --no-fit --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(r.out).at("channels")[0].contains("fit"));
}

TEST_F(PsdCli, OutIsRefusedWhenItExistsUnlessForced) {
  const std::string file = record(2000);
  const std::string out = write("psd.json", "keep me\n");
  CliRun r = run_cubecal("psd " + file + " --format json --out " + out);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  {
    std::ifstream in(out);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text, "keep me\n");
  }
  r = run_cubecal("psd " + file + " --format json --out " + out + " --force");
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("command"), "psd");
}

// --report: the page with one spectrum plot per channel (its points the
// log-binned spectrum, its lines the fitted terms over the fitted band) and
// the table of terms; an existing page is kept unless --force.
TEST_F(PsdCli, ReportDrawsTheSpectrumAndTheFittedTerms) {
  if (!report::find_gnuplot()) GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox (scripts/install-deps.sh)";
  const std::string file = record(20000);
  const std::string dir = path("rep");
  const CliRun r = run_cubecal("psd " + file + " --unit deg/s --format csv --report " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  namespace fs = std::filesystem;
  for (const char* ch : {"gx", "gy"})
    for (const char* ext : {".dat", ".gp", ".svg", ".png"})
      EXPECT_TRUE(fs::exists(fs::path(dir) / "plots" / (std::string("psd_") + ch + ext))) << ch << ext;
  std::ifstream page(fs::path(dir) / "report.html");
  std::stringstream html;
  html << page.rdbuf();
  EXPECT_EQ(count(html.str(), "data:image/svg+xml;base64,"), 2u) << "the plots inline";
  EXPECT_NE(html.str().find("f^-2 (rate random walk K)"), std::string::npos) << "gx's walk in its table";
  // The plotted points of gx are the spectrum averaged over 20 bands per
  // decade: what --bins-per-decade 20 prints, to the nine digits the plot
  // data keep (bands of zero frequency or density are off the log axes).
  const CliRun banded = run_cubecal("psd " + file + " --unit deg/s --format json --bins-per-decade 20");
  ASSERT_EQ(banded.code, 0) << banded.err;
  const auto bj = nlohmann::json::parse(banded.out);
  const auto& b = bj.at("channels")[0];
  std::vector<double> want;
  const auto f = b.at("frequency_hz").get<std::vector<double>>();
  const auto d = b.at("density").get<std::vector<double>>();
  for (std::size_t k = 0; k < f.size(); ++k)
    if (f[k] > 0.0 && d[k] > 0.0) want.push_back(f[k]);
  std::ifstream dat(fs::path(dir) / "plots" / "psd_gx.dat");
  std::string line;
  std::vector<double> x;
  bool in_points = false;
  while (std::getline(dat, line)) {
    if (line.rfind("# index", 0) == 0) {
      in_points = line.find("measured") != std::string::npos;
      continue;
    }
    if (!in_points || line.empty() || line[0] == '#') continue;
    x.push_back(std::stod(line));
  }
  ASSERT_EQ(x.size(), want.size());
  for (std::size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(x[k], want[k], 1e-8 * want[k]) << k;
  const CliRun again = run_cubecal("psd " + file + " --unit deg/s --report " + dir);
  EXPECT_TRUE(one_error_line(again)) << again.err;
}

TEST_F(PsdCli, HelpNamesEveryOption) {
  const CliRun r = run_cubecal("psd --help");
  ASSERT_EQ(r.code, 0);
  for (const char* opt : {"--unit", "--window", "--segment", "--fmin", "--overlap", "--detrend", "--bins-per-decade",
                          "--fit-min", "--fit-max", "--no-fit", "--format", "--out", "--force", "--columns"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

}  // namespace
}  // namespace cubecal::test
