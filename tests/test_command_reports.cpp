// The report pages of the analysis commands other than `analyze`: turnon and
// compare (Allan curves of the runs overlaid, the turn-on bias band), calibrate
// rate-table (plateau residuals before and after) and calibrate mag (points
// before and after, norm error), written by `--report DIR`. Inputs are made by
// the binary (simulate) or here (an ellipsoid of points); every page must be
// self-contained, carry each plot with its .gp/.dat/.svg/.png, never replace
// a report unasked, stop before the work without gnuplot, and render in
// headless Chromium with every image decoded.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/pipeline/calibrate_multiposition.hpp"
#include "cubecal/pipeline/calibrate_temperature.hpp"
#include "cubecal/report/command_report.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/plot.hpp"
#include "report_check.hpp"

namespace cubecal {
namespace {

namespace fs = std::filesystem;
using test::count;
using test::one_error_line;
using test::run_cubecal;
using test::slurp;
using test::spit;

std::string q(const fs::path& p) { return test::shell_quote(p.string()); }

// The numbers of block `index` of a plot's .dat file: rows of columns.
std::vector<std::vector<double>> dat_block(const fs::path& dat, std::size_t index) {
  std::istringstream in(slurp(dat));
  std::vector<std::vector<double>> rows;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("# index ", 0) == 0) {
      inside = std::stoul(line.substr(8)) == index;
      continue;
    }
    if (!inside || line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<double> r;
    std::string tok;
    while (ls >> tok) r.push_back(tok == "NaN" ? NAN : std::stod(tok));
    rows.push_back(std::move(r));
  }
  return rows;
}

double rms_of_column(const std::vector<std::vector<std::vector<double>>>& blocks, std::size_t col) {
  double ss = 0.0;
  std::size_t n = 0;
  for (const auto& b : blocks)
    for (const auto& r : b) {
      ss += r[col] * r[col];
      ++n;
    }
  return n ? std::sqrt(ss / static_cast<double>(n)) : NAN;
}

// report.html in `dir`: self-contained, exactly the expected plots, each in
// the page and with its four files. Returns the page.
std::string expect_report(const fs::path& dir, const std::vector<std::string>& plots) {
  const fs::path html_path = dir / "report.html";
  EXPECT_TRUE(fs::exists(html_path)) << html_path;
  EXPECT_FALSE(fs::exists(dir / "report.html.partial"));
  const std::string html = slurp(html_path);
  std::printf("  %s: %zu bytes, %zu plots\n", html_path.string().c_str(), html.size(), plots.size());
  EXPECT_LT(html.size(), 3u << 20);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);

  // Nothing fetched from anywhere.
  for (const char* bad : {"http://", "https://", "<link", "@import", "url(", "<script src", "<iframe"})
    EXPECT_EQ(html.find(bad), std::string::npos) << bad;
  const std::regex src("(?:src|href)=\"([^\"]{0,40})");
  std::size_t images = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), src); it != std::sregex_iterator(); ++it) {
    const std::string v = (*it)[1].str();
    if (it->str().rfind("src", 0) == 0) {
      ++images;
      EXPECT_EQ(v.rfind("data:image/svg+xml;base64,", 0), 0u) << v;
    } else {
      // Links: in-page anchors or the plot files beside the page.
      EXPECT_TRUE(v.rfind("#", 0) == 0 || v.rfind("plots/", 0) == 0) << v;
    }
  }
  EXPECT_EQ(images, plots.size());
  EXPECT_EQ(count(html, "<img class=\"plot\""), plots.size());

  for (const auto& name : plots) {
    for (const char* ext : {".gp", ".dat", ".svg", ".png"}) {
      const fs::path f = dir / "plots" / (name + ext);
      EXPECT_TRUE(fs::exists(f) && fs::file_size(f) > 0) << f;
    }
    EXPECT_NE(html.find("id=\"fig-" + name + "\""), std::string::npos) << name;
    const std::string gp = slurp(dir / "plots" / (name + ".gp"));
    EXPECT_NE(gp.find("'" + name + ".dat'"), std::string::npos) << name << ": the script reads its data file";
    EXPECT_FALSE(fs::exists(dir / "plots" / (name + ".log"))) << name;
  }
  std::size_t svgs = 0;
  for (const auto& e : fs::directory_iterator(dir / "plots")) svgs += e.path().extension() == ".svg";
  EXPECT_EQ(svgs, plots.size()) << "no plots but the page's in " << dir / "plots";
  // The page's parts.
  for (const char* s : {"id=\"input\"", "id=\"reproduce\"", "id=\"files\"", "<nav class=\"toc\">", "Figure 1."})
    EXPECT_NE(html.find(s), std::string::npos) << s;
  return html;
}

class CommandReports : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char tmpl[] = "/tmp/cubecal-test-command-reports-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    root_ = tmpl;
    // Power-cycled runs of the simulated gyro (10 Hz, 20 min), and one at 50 Hz.
    for (int s = 1; s <= 3; ++s) {
      const auto r = run_cubecal("simulate --preset sport-gyro --rate 10 --duration 20m --seed " + std::to_string(s) +
                                 " --out " + q(run(s)));
      ASSERT_EQ(r.code, 0) << r.err;
    }
    const auto r4 = run_cubecal("simulate --preset sport-gyro --rate 50 --duration 5m --seed 4 --out " + q(run(4)));
    ASSERT_EQ(r4.code, 0) << r4.err;
    write_rate_table();
    write_mag_points();
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }

  static fs::path run(int k) { return root_ / ("run" + std::to_string(k) + ".csv"); }

  // A rate-table run: the simulated gyro turned through 10 plateaus of 40 s
  // (--true-input), with the table's rates appended as columns rx, ry, rz.
  static void write_rate_table() {
    const std::vector<std::array<double, 3>> rates{{0, 0, 0},  {10, 0, 0},  {-10, 0, 0}, {0, 10, 0},   {0, -10, 0},
                                                   {0, 0, 10}, {0, 0, -10}, {20, 20, 0}, {0, -15, 15}, {0, 0, 0}};
    std::string prof = "t,wx,wy,wz\n";
    for (std::size_t k = 0; k < rates.size(); ++k)
      prof += std::to_string(40 * k) + "," + std::to_string(rates[k][0]) + "," + std::to_string(rates[k][1]) + "," +
              std::to_string(rates[k][2]) + "\n";
    spit(root_ / "profile.csv", prof);
    const fs::path raw = root_ / "table_raw.csv";
    const auto r = run_cubecal("simulate --preset sport-gyro --rate 10 --duration 400s --seed 7 --true-input " +
                               q(root_ / "profile.csv") + " --out " + q(raw));
    ASSERT_EQ(r.code, 0) << r.err;
    std::istringstream in(slurp(raw));
    std::string line, out;
    ASSERT_TRUE(std::getline(in, line));
    out = line + ",rx,ry,rz\n";
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      const double t = std::stod(line.substr(0, line.find(',')));
      const auto k = std::min(rates.size() - 1, static_cast<std::size_t>(std::floor(t / 40.0 + 1e-9)));
      char b[96];
      std::snprintf(b, sizeof b, ",%g,%g,%g\n", rates[k][0], rates[k][1], rates[k][2]);
      out += line + b;
    }
    spit(root_ / "table.csv", out);
  }

  // 300 points on an ellipsoid (hard iron b, soft iron M, F = 50 uT, noise
  // 0.2 uT) over the whole sphere, and 3 far outliers for --reject.
  static void write_mag_points() {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> uz(-1.0, 1.0), ut(0.0, 2.0 * 3.141592653589793);
    std::normal_distribution<double> g(0.0, 0.2);
    const double b[3] = {12.0, -20.0, 30.0}, F = 50.0;
    const double M[3][3] = {{1.10, 0.05, -0.03}, {0.05, 0.92, 0.04}, {-0.03, 0.04, 1.02}};
    std::string s = "mx,my,mz\n";
    for (int k = 0; k < 303; ++k) {
      const double z = uz(rng), t = ut(rng), rr = std::sqrt(1.0 - z * z);
      const double u[3] = {rr * std::cos(t), rr * std::sin(t), z};
      const double scale = (k == 50 || k == 150 || k == 250) ? 5.0 : 1.0;
      char line[128];
      double h[3];
      for (int i = 0; i < 3; ++i) h[i] = b[i] + scale * F * (M[i][0] * u[0] + M[i][1] * u[1] + M[i][2] * u[2]) + g(rng);
      std::snprintf(line, sizeof line, "%.5f,%.5f,%.5f\n", h[0], h[1], h[2]);
      s += line;
    }
    spit(root_ / "mag.csv", s);
  }

  static test::CliRun turnon(const fs::path& dir, const std::string& extra = {}) {
    return run_cubecal("turnon " + q(run(1)) + " " + q(run(2)) + " " + q(run(3)) +
                       " --columns gx,gy,gz --unit deg/s --report " + q(dir) + extra);
  }
  static test::CliRun compare(const fs::path& dir, const std::string& extra = {}) {
    return run_cubecal("compare " + q(run(1)) + " " + q(run(2)) + " " + q(run(4)) +
                       " --columns gx,gy,gz --unit deg/s --report " + q(dir) + extra);
  }
  static test::CliRun rate_table(const fs::path& dir, const std::string& extra = {}) {
    return run_cubecal("calibrate rate-table " + q(root_ / "table.csv") +
                       " --columns gx,gy,gz --ref-columns rx,ry,rz --margin 5 --min-plateau 20 --report " + q(dir) +
                       extra);
  }
  static test::CliRun mag(const fs::path& dir, const std::string& extra = {}) {
    return run_cubecal("calibrate mag " + q(root_ / "mag.csv") + " --field-norm 50 --unit uT --reject 3 --report " +
                       q(dir) + extra);
  }

  static bool have_gnuplot() { return report::find_gnuplot().has_value(); }
  static fs::path root_;
};
fs::path CommandReports::root_;

#define REQUIRE_GNUPLOT()                                       \
  if (!have_gnuplot())                                          \
  GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox " \
                  "(scripts/install-deps.sh) to render and check the plots"

const std::vector<std::string> kTurnonPlots{"turnon_bias_gx", "turnon_bias_gy", "turnon_bias_gz",
                                            "runs_allan_gx",  "runs_allan_gy",  "runs_allan_gz"};
const std::vector<std::string> kComparePlots{"runs_allan_gx", "runs_allan_gy", "runs_allan_gz"};
const std::vector<std::string> kRateTablePlots{"rate_residual_before", "rate_residual_after"};
const std::vector<std::string> kMagPlots{"mag_xy", "mag_xz", "mag_yz", "mag_norm_error", "mag_norm_error_after"};

// ---------------------------------------------------------------------------
// The page and the plot pieces, without gnuplot

report::CommandReport evil_report() {
  report::CommandReport r;
  r.title = "Report of <script>alert(1)</script>";
  r.lead_html = "A <b>lead</b>.";
  r.input = {{"file", "<img src=x onerror=alert(2)>.csv", true}, {"rate", "10 Hz & more", false}};
  r.command = "cubecal turnon 'a<b>.csv' --report out";
  r.notes = {"careful: \"quoted\""};
  report::ReportTable t;
  t.title = "Table <1>";
  t.header = {"channel", "value"};
  t.rows = {{"g<x>", "1 ± 0.1"}};
  t.note = "note & more";
  report::ReportFigure f;
  f.plot.name = "evil_plot";
  f.plot.title = "t";
  f.caption_html = "Caption.";
  r.sections.push_back({"results", "Results", {{"<p>Text.</p>", t, {f}}}});
  report::ReportFigure g = f, h = f;
  g.plot.name = "second";
  h.plot.name = "third";
  r.sections.push_back({"more stuff!", "More", {{{}, std::nullopt, {g, h}}}});
  return r;
}

TEST(CommandReportPage, EscapesEveryStringAndLaysOutTheParts) {
  const report::CommandReport r = evil_report();
  const auto plots = report::report_plots(r);
  ASSERT_EQ(plots.size(), 3u);
  EXPECT_EQ(plots[0].name, "evil_plot");
  EXPECT_EQ(plots[2].name, "third");
  const std::string html = report::command_report_html(r, {}, "Plots not rendered: why.");
  for (const char* raw : {"<script>alert", "<img src=x", "g<x>", "Table <1>", "a<b>.csv", "\"quoted\""})
    EXPECT_EQ(html.find(raw), std::string::npos) << raw;
  for (const char* esc :
       {"Report of &lt;script&gt;alert(1)&lt;/script&gt;", "&lt;img src=x onerror=alert(2)&gt;.csv",
        "<th>g&lt;x&gt;</th><td class=\"num\">1 ± 0.1</td>", "Table &lt;1&gt;", "note &amp; more", "10 Hz &amp; more",
        "cubecal turnon &#39;a&lt;b&gt;.csv&#39; --report out", "careful: &quot;quoted&quot;"})
    EXPECT_NE(html.find(esc), std::string::npos) << esc;
  EXPECT_NE(html.find("A <b>lead</b>."), std::string::npos) << "the lead is HTML";
  EXPECT_NE(html.find("<p class=\"note\">Plots not rendered: why.</p>"), std::string::npos);
  EXPECT_NE(html.find("<section id=\"results\">"), std::string::npos);
  EXPECT_NE(html.find("<section id=\"more-stuff-\">"), std::string::npos) << "anchors are sanitized";
  EXPECT_NE(html.find("<a href=\"#more-stuff-\">More</a>"), std::string::npos);
  EXPECT_NE(html.find("<div class=\"figrow\">"), std::string::npos) << "several figures of a block side by side";
  EXPECT_NE(html.find("[plot evil_plot not rendered]"), std::string::npos);
  EXPECT_NE(html.find("<b>Figure 3.</b>"), std::string::npos);
  EXPECT_NE(html.find(".figrow {"), std::string::npos) << "the shared style sheet has the row style";
  EXPECT_EQ(count(html, "<style>"), 1u);
  EXPECT_EQ(count(html, "<script>"), 1u) << "only the page's own image check";
}

TEST(CommandReportPage, RefusesAnExistingReportAndAMissingGnuplot) {
  char tmpl[] = "/tmp/cubecal-test-command-page-XXXXXX";
  ASSERT_NE(::mkdtemp(tmpl), nullptr);
  const fs::path d = tmpl;
  EXPECT_NO_THROW(report::check_report_target((d / "new").string(), false, report::find_gnuplot().value_or("")));
  try {
    report::check_report_target(d.string(), false, (d / "no-such" / "gnuplot").string());
    FAIL() << "no error";
  } catch (const UsageError& e) {
    // The path given is named.
    EXPECT_EQ(std::string(e.what()), report::gnuplot_missing((d / "no-such" / "gnuplot").string()));
    EXPECT_EQ(e.field(), cubecal::Field::gnuplot);
  }
  // Without gnuplot and require_plots = false: the page, saying why.
  report::ReportOptions o;
  o.gnuplot = (d / "no-such" / "gnuplot").string();
  EXPECT_THROW(report::write_command_report(evil_report(), d.string(), o), UsageError);
  EXPECT_FALSE(fs::exists(d / "report.html"));
  o.require_plots = false;
  const auto r = report::write_command_report(evil_report(), d.string(), o);
  EXPECT_TRUE(r.plots.empty());
  EXPECT_NE(slurp(d / "report.html").find("Plots not rendered: no executable gnuplot at "), std::string::npos);
  try {
    report::check_report_target(d.string(), false);
    FAIL() << "no error for an existing report";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("report.html already exists"), std::string::npos) << e.what();
    EXPECT_NE(e.text().find("{force}"), std::string::npos) << e.text();
  }
  o.force = false;
  EXPECT_THROW(report::write_command_report(evil_report(), d.string(), o), UsageError);
  fs::remove_all(d);
}

TEST(CommandReportPlots, BandsEqualAxesAndTicsInTheScript) {
  report::Plot p;
  p.name = "band_demo";
  p.x = {"run", false, 0.5, 3.5};
  p.x_tics = 1.0;
  p.equal_axes = true;
  report::PlotSeries band;
  band.mark = report::Mark::band;
  band.label = "mean ± σ";
  band.x = {0.5, 3.5};
  band.y = {1.0, 1.0};
  band.lo = {0.8, 0.8};
  band.hi = {1.2, 1.2};
  band.opacity = 0.25;
  band.color = "#1f77b4";
  report::PlotSeries key;
  key.mark = report::Mark::band;
  key.label = "legend only";
  p.series = {band, key};
  const std::string gp = report::gnuplot_script(p);
  EXPECT_NE(gp.find("'band_demo.dat' index 0 using 1:3:4 with filledcurves ls 1 fs solid 1.0 noborder title "
                    "'mean ± σ' noenhanced"),
            std::string::npos)
      << gp;
  EXPECT_NE(gp.find("keyentry with filledcurves ls 2 fs solid 1.0 noborder title 'legend only'"), std::string::npos)
      << gp;
  EXPECT_NE(gp.find("lc rgb '#bf1f77b4'"), std::string::npos) << "opacity as gnuplot's alpha";
  EXPECT_NE(gp.find("set size ratio -1"), std::string::npos);
  EXPECT_NE(gp.find("set xtics 1\n"), std::string::npos);
  EXPECT_NE(report::plot_data(p).find("# x y lo hi\n0.5 1 0.8 1.2\n"), std::string::npos);
  if (!report::find_gnuplot()) GTEST_SKIP() << "gnuplot not installed: the script is not run";
  char tmpl[] = "/tmp/cubecal-test-band-XXXXXX";
  ASSERT_NE(::mkdtemp(tmpl), nullptr);
  const auto r = report::render_plots({p}, tmpl);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NE(r[0].svg_text.find("<svg"), std::string::npos);
  fs::remove_all(tmpl);
}

// ---------------------------------------------------------------------------
// The commands

TEST_F(CommandReports, TurnonOverlaysTheRunsAndShowsTheBiasBand) {
  REQUIRE_GNUPLOT();
  const fs::path d = root_ / "turnon";
  const auto r = turnon(d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Turn-on bias over 3 runs"), std::string::npos) << "the table still goes to stdout";
  EXPECT_NE(r.err.find("report.html"), std::string::npos) << r.err;
  const std::string html = expect_report(d, kTurnonPlots);
  for (const char* s : {"Turn-on bias per channel", "Every run", "run1.csv", "run3.csv", "deg/sqrt(h)",
                        "Allan deviation of the runs", "turn-on bias σ"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
  EXPECT_NE(html.find("--report"), std::string::npos) << "the command as typed";

  // The bias plot: the band (mean ± sigma), the mean line and one point per run.
  const fs::path dat = d / "plots" / "turnon_bias_gx.dat";
  const auto band = dat_block(dat, 0), mean = dat_block(dat, 1);
  std::vector<std::vector<double>> runs;
  for (std::size_t k = 2; k <= 4; ++k) {
    const auto one = dat_block(dat, k);
    ASSERT_EQ(one.size(), 1u) << "one series per run, in the run's colour";
    EXPECT_EQ(one[0][0], static_cast<double>(k - 1));
    runs.push_back(one[0]);
  }
  ASSERT_EQ(band.size(), 2u);
  double m = 0.0;
  for (const auto& p : runs) m += p[1] / 3.0;
  double ss = 0.0;
  for (const auto& p : runs) ss += (p[1] - m) * (p[1] - m);
  const double sd = std::sqrt(ss / 2.0);
  EXPECT_NEAR(mean[0][1], m, 1e-6 * std::abs(m) + 1e-9);
  EXPECT_NEAR(band[0][2], m - sd, 1e-6);
  EXPECT_NEAR(band[0][3], m + sd, 1e-6);
  EXPECT_NE(slurp(d / "plots" / "turnon_bias_gx.gp").find("filledcurves"), std::string::npos);
  // The overlay: one block per run, each with its interval.
  const fs::path allan = d / "plots" / "runs_allan_gy.dat";
  EXPECT_EQ(count(slurp(allan), "# index"), 3u);
  for (const auto& row : dat_block(allan, 1)) {
    ASSERT_EQ(row.size(), 4u);
    EXPECT_LE(row[2], row[1]);
    EXPECT_GE(row[3], row[1]);
  }
}

TEST_F(CommandReports, CompareWritesItsReportBesideJsonOut) {
  REQUIRE_GNUPLOT();
  const fs::path d = root_ / "compare";
  const fs::path json_out = root_ / "compare.json";
  const auto r = compare(d, " --format json --out " + q(json_out));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << "the result went to --out";
  const auto j = nlohmann::json::parse(slurp(json_out));
  ASSERT_EQ(j["runs"].size(), 3u);
  const std::string html = expect_report(d, kComparePlots);
  EXPECT_NE(html.find("differ in sampling rate"), std::string::npos);
  const std::string gp = slurp(d / "plots" / "runs_allan_gz.gp");
  EXPECT_NE(gp.find("title '3: run4.csv (50 Hz)'"), std::string::npos) << "runs at other rates are labelled so";
  // The 50 Hz run starts at tau = 0.02 s, the others at 0.1 s.
  EXPECT_NEAR(dat_block(d / "plots" / "runs_allan_gz.dat", 2).front()[0], 0.02, 1e-9);
  EXPECT_NEAR(dat_block(d / "plots" / "runs_allan_gz.dat", 0).front()[0], 0.1, 1e-9);
}

TEST_F(CommandReports, RateTableResidualsBeforeAndAfterCalibration) {
  REQUIRE_GNUPLOT();
  const fs::path d = root_ / "rate";
  const fs::path json_out = root_ / "rate.json";
  const auto r = rate_table(d, " --format json --out " + q(json_out));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json_out));
  const std::string html = expect_report(d, kRateTablePlots);
  for (const char* s : {"Calibration w = A w_g + β", "scale-factor error [ppm]", "Plateau residuals", "Plateaus",
                        "the reference columns", "Error covariance"})
    EXPECT_NE(html.find(s), std::string::npos) << s;

  // Block 0 is the zero line, blocks 1-3 the axes: their RMS is the command's.
  for (const char* which : {"before", "after"}) {
    const fs::path dat = d / "plots" / (std::string("rate_residual_") + which + ".dat");
    std::vector<std::vector<std::vector<double>>> axes;
    for (std::size_t a = 1; a <= 3; ++a) axes.push_back(dat_block(dat, a));
    ASSERT_EQ(axes[0].size(), j["plateaus"].size()) << which;
    const double rms = j[std::string("residual_") + which]["rms"].get<double>();
    EXPECT_NEAR(rms_of_column(axes, 1), rms, 1e-6 * rms) << which;
  }
  // Before calibration the simulated gyro's bias (about 0.2, 1.5, -1.5 deg/s) dominates; after, noise.
  const auto y_before = dat_block(d / "plots" / "rate_residual_before.dat", 2);
  for (const auto& row : y_before) EXPECT_NEAR(row[1], 1.49, 0.05);
  EXPECT_LT(j["residual_after"]["rms"].get<double>(), 0.05);
}

TEST_F(CommandReports, MagnetometerPointsBeforeAndAfterCalibration) {
  REQUIRE_GNUPLOT();
  const fs::path d = root_ / "mag";
  const fs::path json_out = root_ / "mag.json";
  const auto r = mag(d, " --format json --out " + q(json_out));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json_out));
  ASSERT_EQ(j["rejected"].get<int>(), 3);
  const std::string html = expect_report(d, kMagPlots);
  for (const char* s : {"h_cal = A⁻¹ (h − b)", "Norm error |h| − F", "rejected lines", "52, 152, 252", "50 uT"})
    EXPECT_NE(html.find(s), std::string::npos) << s;

  // Projections: raw (0), calibrated (1), rejected (2), the circle of radius F (3), the offset b (4).
  const fs::path xy = d / "plots" / "mag_xy.dat";
  const auto cal = dat_block(xy, 1), circle = dat_block(xy, 3), b = dat_block(xy, 4);
  EXPECT_EQ(cal.size(), 300u);
  EXPECT_EQ(dat_block(xy, 2).size(), 3u);
  for (const auto& p : circle) EXPECT_NEAR(std::hypot(p[0], p[1]), 50.0, 1e-6);
  for (const auto& p : cal) EXPECT_LT(std::hypot(p[0], p[1]), 51.5) << "calibrated points inside the circle";
  ASSERT_EQ(b.size(), 1u);
  EXPECT_NEAR(b[0][0], j["bias"][0].get<double>(), 1e-6);
  EXPECT_NEAR(b[0][1], j["bias"][1].get<double>(), 1e-6);
  EXPECT_NE(slurp(xy.parent_path() / "mag_xy.gp").find("set size ratio -1"), std::string::npos);
  // Norm error: zero line (0), before (1), after (2), rejected (3); the RMS are the command's.
  const fs::path ne = d / "plots" / "mag_norm_error.dat";
  EXPECT_NEAR(rms_of_column({dat_block(ne, 1)}, 1), j["norm_error_before"]["rms"].get<double>(), 1e-6);
  EXPECT_NEAR(rms_of_column({dat_block(ne, 2)}, 1), j["norm_error_after"]["rms"].get<double>(), 1e-6);
  EXPECT_EQ(dat_block(ne, 3).size(), 3u);
}

// A page of tables only: report.html, complete and self-contained, no plots.
std::string expect_table_page(const fs::path& dir) {
  EXPECT_TRUE(fs::exists(dir / "report.html")) << dir;
  EXPECT_FALSE(fs::exists(dir / "report.html.partial"));
  const std::string html = slurp(dir / "report.html");
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  for (const char* bad : {"http://", "https://", "<link", "<img", "<script src"})
    EXPECT_EQ(html.find(bad), std::string::npos) << bad;
  return html;
}

TEST_F(CommandReports, TemperatureAndMultipositionPagesFromTheCli) {
  REQUIRE_GNUPLOT();
  const fs::path mag = root_ / "mag_temp.csv";
  ASSERT_EQ(
      run_cubecal("simulate --preset sport-mag --rate 1 --duration 2h --temp sine:25,10,3600 --seed 3 --out " + q(mag))
          .code,
      0);
  const fs::path dt = root_ / "temperature";
  const auto t = run_cubecal("calibrate temperature " + q(mag) + " --columns mx,my,mz --temp-col temp --unit mGauss " +
                             "--format json --report " + q(dt));
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_EQ(nlohmann::json::parse(t.out)["channels"].size(), 3u) << "the JSON still goes to standard output";
  const std::string tp = expect_table_page(dt);
  EXPECT_NE(tp.find("Temperature calibration: mag_temp.csv"), std::string::npos);
  EXPECT_NE(tp.find("mGauss/degC"), std::string::npos);
  const auto again =
      run_cubecal("calibrate temperature " + q(mag) + " --columns mx,my,mz --temp-col temp --report " + q(dt));
  EXPECT_TRUE(one_error_line(again)) << again.err;
  EXPECT_TRUE(again.out.empty()) << "refused before the work";

  const std::string xsens = std::string(CUBECAL_SHARED_DATA) + "/imu/xsens-multiposition/";
  const fs::path dm = root_ / "multiposition";
  const auto m = run_cubecal("calibrate multiposition " + xsens +
                             "xsens_acc.txt --acc-columns 2,3,4 --time-col 1 "
                             "--g 9.81744 --acc-bias 32768 --report " +
                             q(dm));
  ASSERT_EQ(m.code, 0) << m.err;
  const std::string mp = expect_table_page(dm);
  EXPECT_NE(mp.find("Static poses"), std::string::npos);
  EXPECT_EQ(mp.find("Gravity direction after integration"), std::string::npos) << "no gyroscope given";
}

TEST_F(CommandReports, NeverReplacesAReportWithoutForce) {
  REQUIRE_GNUPLOT();
  const fs::path d = root_ / "replace";
  ASSERT_EQ(rate_table(d).code, 0);
  const auto before = fs::last_write_time(d / "report.html");
  const std::string page = slurp(d / "report.html");
  for (const auto& again : {rate_table(d), mag(d), turnon(d), compare(d)}) {
    EXPECT_TRUE(one_error_line(again)) << again.code << " " << again.err;
    EXPECT_NE(again.err.find("report.html already exists"), std::string::npos) << again.err;
    EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
    EXPECT_TRUE(again.out.empty()) << "refused before the work";
  }
  EXPECT_EQ(fs::last_write_time(d / "report.html"), before);
  EXPECT_EQ(slurp(d / "report.html"), page);
  // A file is no report directory.
  spit(root_ / "a_file", "x");
  const auto file = mag(root_ / "a_file");
  EXPECT_TRUE(one_error_line(file)) << file.err;
  EXPECT_NE(file.err.find("is a file"), std::string::npos) << file.err;
  // A plots/ directory alone is a report too.
  const fs::path p = root_ / "plots_only";
  fs::create_directories(p / "plots");
  EXPECT_TRUE(one_error_line(mag(p)));

  // --force replaces it; plots of an earlier report of the same kind go, other files stay.
  spit(d / "plots" / "rate_residual_old.svg", "<svg/>");
  spit(d / "plots" / "notes.txt", "mine");
  const auto forced = rate_table(d, " --force");
  ASSERT_EQ(forced.code, 0) << forced.err;
  EXPECT_FALSE(fs::exists(d / "plots" / "rate_residual_old.svg"));
  EXPECT_TRUE(fs::exists(d / "plots" / "notes.txt"));
  expect_report(d, kRateTablePlots);
}

TEST_F(CommandReports, MissingGnuplotStopsBeforeTheWork) {
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  const fs::path empty = root_ / "empty-path";
  fs::create_directories(empty);
  ::setenv("PATH", empty.c_str(), 1);  // the binary is run by its full path, by /bin/sh
  const fs::path out = root_ / "never.txt";
  const std::vector<test::CliRun> runs{
      turnon(root_ / "ng1", " --out " + q(out)), compare(root_ / "ng2", " --out " + q(out)),
      rate_table(root_ / "ng3", " --out " + q(out)), mag(root_ / "ng4", " --out " + q(out))};
  ::setenv("PATH", saved.c_str(), 1);
  for (const auto& r : runs) {
    EXPECT_TRUE(one_error_line(r)) << r.code << " " << r.err;
    EXPECT_EQ(r.err, std::string("cubecal: error: ") + report::kGnuplotMissing + "\n");
    EXPECT_TRUE(r.out.empty());
  }
  EXPECT_FALSE(fs::exists(out)) << "no result written";
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  for (const char* d : {"ng1", "ng2", "ng3", "ng4"}) EXPECT_FALSE(fs::exists(root_ / d)) << d;
}

TEST_F(CommandReports, PagesRenderInHeadlessChromium) {
  REQUIRE_GNUPLOT();
  const std::string chromium = test::find_chromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium not installed: install it (scripts/install-deps.sh) to check the pages in a browser";
  struct Page {
    std::string name;
    fs::path dir;
    std::size_t plots;
  };
  const std::vector<Page> pages{{"turnon", root_ / "b_turnon", kTurnonPlots.size()},
                                {"compare", root_ / "b_compare", kComparePlots.size()},
                                {"rate-table", root_ / "b_rate", kRateTablePlots.size()},
                                {"mag", root_ / "b_mag", kMagPlots.size()}};
  ASSERT_EQ(turnon(pages[0].dir).code, 0);
  ASSERT_EQ(compare(pages[1].dir).code, 0);
  ASSERT_EQ(rate_table(pages[2].dir).code, 0);
  ASSERT_EQ(mag(pages[3].dir).code, 0);
  // The four pages at once: each Chromium run has its own profile and files.
  std::vector<std::future<test::BrowserPage>> loads;
  for (const auto& p : pages)
    loads.push_back(std::async(std::launch::async, [&chromium, p] {
      return test::load_in_chromium(chromium, p.dir / "report.html", p.dir / "browser");
    }));
  for (std::size_t k = 0; k < pages.size(); ++k) {
    SCOPED_TRACE(pages[k].name);
    const test::BrowserPage b = loads[k].get();
    ASSERT_TRUE(b.error.empty()) << b.error;
    ASSERT_EQ(b.image.width, 1200u);
    ASSERT_EQ(b.image.height, 2000u);
    std::printf("  %s: %ju bytes on disk; screenshot in %.2f s: %zu colours, %.1f %% ink\n", pages[k].name.c_str(),
                static_cast<std::uintmax_t>(fs::file_size(pages[k].dir / "report.html")), b.seconds, b.colours,
                100.0 * b.ink_fraction);
    EXPECT_GT(b.colours, 100u) << "text, tables and coloured plots are in view";
    EXPECT_GT(b.ink_fraction, 0.03);
    EXPECT_GT(b.shot_bytes, 50000u) << "a blank 1200x2000 page is about 11 kB";
    EXPECT_NE(b.dom.find("data-images=\"ok\""), std::string::npos)
        << b.dom.substr(std::min(b.dom.size(), b.dom.find("<body")), 300);
    EXPECT_NE(b.dom.find("data-image-count=\"" + std::to_string(pages[k].plots) + "\""), std::string::npos);
  }
}

// ---------------------------------------------------------------------------
// calibrate temperature: a page of tables built from the typed result

TEST(CommandReportPage, TemperaturePageFromTheTypedResult) {
  io::Series s;
  s.file = "/data/temp run.csv";
  s.rate_hz = 1.0;
  s.tau0 = 1.0;
  s.names = {"gx", "g<y>"};
  s.channels.resize(2);
  s.extra_names = {"temp"};
  s.extra.resize(1);
  for (int k = 0; k < 2000; ++k) {
    const double T = 20.0 + 5.0 * std::sin(k / 100.0);
    s.extra[0].push_back(T);
    s.channels[0].push_back(1.0 + 0.5 * (T - 20.0) + 0.01 * std::cos(k * 1.7));
    s.channels[1].push_back(-2.0 + 0.01 * std::sin(k * 2.3));
  }
  s.segments = {{0, 2000}};
  pipeline::TemperatureRequest req;
  req.order = 2;
  req.unit = "deg/h";
  const pipeline::TemperatureResult t = pipeline::calibrate_temperature(s, req);
  const report::CommandReport page = report::temperature_report(t, "cubecal calibrate temperature x");
  EXPECT_EQ(page.title, "Temperature calibration: temp run.csv");
  EXPECT_EQ(page.command, "cubecal calibrate temperature x");
  ASSERT_EQ(page.sections.size(), 2u);
  ASSERT_TRUE(page.sections[0].blocks[0].table.has_value());
  EXPECT_EQ(page.sections[0].blocks[0].table->rows.size(), 2u);
  ASSERT_EQ(page.sections[1].blocks.size(), 2u);  // one coefficient table per channel
  const auto& coeffs = *page.sections[1].blocks[0].table;
  ASSERT_EQ(coeffs.rows.size(), 3u);
  EXPECT_EQ(coeffs.rows[1][2], "deg/h/degC");
  EXPECT_EQ(coeffs.rows[1][1].rfind("0.5", 0), 0u) << coeffs.rows[1][1];
  EXPECT_TRUE(report::report_plots(page).empty());
  const std::string html = report::command_report_html(page, {});
  EXPECT_NE(html.find("g&lt;y&gt;"), std::string::npos);
  EXPECT_EQ(html.find("g<y>"), std::string::npos);
  EXPECT_NE(html.find("deg/h/degC^2"), std::string::npos);
}

// ---------------------------------------------------------------------------
// calibrate multiposition: a page of tables built from the typed result

pipeline::TriadSamples xsens_triad(const std::string& name) {
  io::TableOptions to;
  to.columns = {"2", "3", "4"};
  to.extra_columns = {"1"};
  const io::Table t = io::read_table(std::string(CUBECAL_SHARED_DATA) + "/imu/xsens-multiposition/" + name, to);
  pipeline::TriadSamples s;
  s.file = t.file;
  s.t = t.extra[0];
  for (std::size_t i = 0; i < t.rows(); ++i) s.x.push_back({t.data[0][i], t.data[1][i], t.data[2][i]});
  return s;
}

TEST(CommandReportPage, MultipositionPageFromTheTypedResult) {
  pipeline::MultipositionRequest req;
  req.options.g = 9.81744;
  req.options.acc_bias_guess = {32768.0, 32768.0, 32768.0};
  req.options.gyro_scale_guess = 1.598e-4;
  const pipeline::MultipositionResult r =
      pipeline::calibrate_multiposition(xsens_triad("xsens_acc.txt"), xsens_triad("xsens_gyro.txt"), req);
  const report::CommandReport page = report::multiposition_report(r, "cubecal calibrate multiposition x");
  EXPECT_EQ(page.title, "Multi-position calibration: xsens_acc.txt");
  ASSERT_EQ(page.sections.size(), 3u);  // poses, accelerometer, gyroscope
  EXPECT_EQ(page.sections[0].id, "poses");
  ASSERT_TRUE(page.sections[0].blocks[1].table.has_value());
  EXPECT_EQ(page.sections[0].blocks[1].table->rows.size(), r.accelerometer.intervals.size());
  const auto& acc_params = *page.sections[1].blocks[0].table;
  ASSERT_EQ(acc_params.rows.size(), 9u);
  EXPECT_EQ(acc_params.rows[3][0], r.accelerometer.names[3]);
  EXPECT_EQ(acc_params.rows[3][2], "g-unit/raw");
  bool gyro_file = false;
  for (const auto& f : page.input) gyro_file = gyro_file || (f.label == "gyroscope" && f.value == *r.gyro_file);
  EXPECT_TRUE(gyro_file);
  EXPECT_TRUE(report::report_plots(page).empty());
  const std::string html = report::command_report_html(page, {});
  EXPECT_NE(html.find("Tedaldi, Pretto &amp; Menegatti 2014"), std::string::npos);
  EXPECT_NE(html.find("Gravity direction after integration"), std::string::npos);
}

}  // namespace
}  // namespace cubecal
