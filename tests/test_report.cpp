// The report layer: plot descriptions to gnuplot files, the self-contained
// HTML page of an analysis (escaping, no network references, every plot with
// its script), its errors, and the page rendered in headless Chromium.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>

#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/report/html.hpp"
#include "cubecal/report/plot.hpp"
#include "cubecal/report/report.hpp"
#include "report_check.hpp"

namespace cubecal {
namespace {

namespace fs = std::filesystem;
using test::count;
using test::slurp;
using test::spit;

// White noise + bias random walk (+ a temperature term), the paper's model.
std::vector<double> channel(std::size_t n, double dt, double sigma, double walk, double bias, double tc,
                            const std::vector<double>& temp, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double b = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    y[i] = bias + b + sigma * g(rng) + tc * (temp[i] - 25.0);
    b += walk * dt * g(rng);
  }
  return y;
}

// A 6-channel analysis (gyro + magnetometer, 4 h at 10 Hz, daily temperature
// swing), its files written as `analyze --out` writes them.
void write_analysis(const fs::path& dir, const std::vector<std::string>& names, const std::string& file,
                    const std::string& command, double hours = 4.0) {
  const double rate = 10.0, dt = 1.0 / rate;
  const auto n = static_cast<std::size_t>(hours * 3600.0 * rate);
  std::vector<double> temp(n);
  for (std::size_t i = 0; i < n; ++i)
    temp[i] = 25.0 + 5.0 * std::sin(2.0 * std::numbers::pi * static_cast<double>(i) * dt / 14400.0);
  io::Series s;
  s.file = file;
  s.rate_hz = rate;
  s.tau0 = dt;
  s.names = names;
  const double sig[] = {13.9e-3, 14.5e-3, 13.0e-3, 3.0, 4.9, 2.96};
  const double walk[] = {3.5e-3, 0.87e-3, 0.66e-3, 0.0034, 0.0042, 0.0036};
  const double bias[] = {0.7, 1.4, -1.6, 210.0, -95.0, 430.0};
  for (std::size_t c = 0; c < names.size(); ++c)
    s.channels.push_back(channel(n, dt, sig[c % 6], walk[c % 6], bias[c % 6], c % 6 >= 3 ? 0.7 : 0.0, temp, 11 + c));
  s.extra_names = {"temp"};
  s.extra = {temp};
  s.segments = {{0, n}};
  pipeline::AnalyzeRequest req;
  for (std::size_t c = 0; c < names.size(); ++c) req.units.push_back(*parse_unit(c % 6 < 3 ? "deg/s" : "mGauss"));
  req.grid = parse_tau_grid("log:10");
  req.temp_index = 0;
  const auto r = pipeline::run_analyze(s, req);
  const pipeline::OutputContext ctx{command, "/imu0"};
  fs::create_directories(dir);
  spit(dir / "analysis.json", pipeline::analysis_json(r, ctx));
  spit(dir / "adev.csv", pipeline::adev_csv(r));
  spit(dir / "drift.csv", pipeline::drift_csv(r));
}

class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char tmpl[] = "/tmp/cubecal-test-report-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    root_ = tmpl;
    write_analysis(root_ / "base", {"gx", "gy", "gz", "mx", "my", "mz"}, "sport_static.csv",
                   "cubecal analyze sport_static.csv --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp "
                   "--out base");
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  // A copy of the base analysis in a directory of its own.
  static fs::path fresh(const std::string& name) {
    const fs::path d = root_ / name;
    fs::create_directories(d);
    for (const char* f : {"analysis.json", "adev.csv", "drift.csv"})
      fs::copy_file(root_ / "base" / f, d / f, fs::copy_options::overwrite_existing);
    return d;
  }
  static bool have_gnuplot() { return report::find_gnuplot().has_value(); }
  static fs::path root_;
};
fs::path ReportTest::root_;

#define REQUIRE_GNUPLOT()                                       \
  if (!have_gnuplot())                                          \
  GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox " \
                  "(scripts/install-deps.sh) to render and check the plots"

// ---------------------------------------------------------------------------
// Pieces

TEST(Html, EscapesMarkupAndQuotes) {
  EXPECT_EQ(report::html_escape("<a href=\"x\">O'Neil & co</a>"),
            "&lt;a href=&quot;x&quot;&gt;O&#39;Neil &amp; co&lt;/a&gt;");
  EXPECT_EQ(report::html_escape("deg/sqrt(h) ± σ"), "deg/sqrt(h) ± σ");
}

TEST(Html, FormatsValuesWithTheirUncertainty) {
  EXPECT_EQ(report::format_pm(0.26644, 0.000134), "0.26644 ± 0.00013");
  EXPECT_EQ(report::format_pm(12.926, 0.0503), "12.926 ± 0.050");
  EXPECT_EQ(report::format_pm(206.3, 42.4), "206 ± 42");
  EXPECT_EQ(report::format_pm(7.734e-5, 1.1e-8), "(7.7340 ± 0.0011)e-05");
  EXPECT_EQ(report::format_pm(1.5, std::nullopt), "1.5");
  EXPECT_EQ(report::format_pm(std::nullopt, 0.1), "—");
  EXPECT_EQ(report::base64("cubecal"), "Y3ViZWNhbA==");
}

report::Plot sample_plot() {
  report::Plot p;
  p.name = "demo_plot";
  p.title = "it's a plot";
  p.x = {"τ [s]", true, std::nullopt, std::nullopt};
  p.y = {"σ(τ)", true, std::nullopt, std::nullopt};
  report::PlotSeries a;
  a.label = "g_x's data";
  a.x = {0.1, 1, 10};
  a.y = {1, 0.3, 0.1};
  a.lo = {0.9, 0.25, 0.08};
  a.hi = {1.1, 0.35, 0.12};
  a.mark = report::Mark::errorlines;
  report::PlotSeries b;
  b.label = "model";
  b.x = {0.1, 10};
  b.y = {1.1, 0.11};
  b.dash = report::Dash::dashed;
  report::PlotSeries key;
  key.label = "legend only";
  p.series = {a, b, key};
  return p;
}

TEST(Plot, ScriptAndDataAreReadable) {
  const report::Plot p = sample_plot();
  const std::string gp = report::gnuplot_script(p);
  EXPECT_NE(gp.find("set terminal svg size 900,600 dynamic enhanced font 'sans,12'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("pngcairo"), std::string::npos);
  EXPECT_NE(gp.find("set output 'demo_plot.svg'"), std::string::npos);
  EXPECT_NE(gp.find("set output 'demo_plot.png'"), std::string::npos);
  EXPECT_NE(gp.find("'demo_plot.dat' index 0 using 1:2:3:4 with yerrorlines ls 1 title 'g_x''s data' noenhanced"),
            std::string::npos)
      << gp;
  EXPECT_NE(gp.find("'' index 1 using 1:2 with lines ls 2"), std::string::npos) << gp;
  EXPECT_NE(gp.find("keyentry with lines ls 3 title 'legend only'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set title 'it''s a plot' noenhanced"), std::string::npos);
  EXPECT_NE(gp.find("set xrange [0.1:10]"), std::string::npos) << "decade-wide log range";
  const std::string dat = report::plot_data(p);
  EXPECT_NE(dat.find("# index 0: g_x's data\n# x y lo hi\n0.1 1 0.9 1.1\n"), std::string::npos) << dat;
  EXPECT_NE(dat.find("\n\n\n# index 1: model\n# x y\n0.1 1.1\n"), std::string::npos) << dat;
}

TEST(Plot, RendersSvgAndPngAndReportsScriptErrors) {
  if (!report::find_gnuplot())
    GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox (scripts/install-deps.sh) to render plots";
  const report::Plot p = sample_plot();
  char tmpl[] = "/tmp/cubecal-test-plot-XXXXXX";
  ASSERT_NE(::mkdtemp(tmpl), nullptr);
  const fs::path dir = tmpl;
  const auto r = report::render_plots({p}, dir);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(fs::exists(dir / "demo_plot.gp"));
  EXPECT_TRUE(fs::exists(dir / "demo_plot.dat"));
  EXPECT_GT(fs::file_size(dir / "demo_plot.png"), 1000u);
  EXPECT_NE(r[0].svg_text.find("<svg"), std::string::npos);
  EXPECT_NE(r[0].svg_text.find("s data"), std::string::npos) << "the legend text is in the SVG";
  EXPECT_FALSE(fs::exists(dir / "demo_plot.log")) << "the log is removed after success";

  // A broken script (as a user might leave it) fails with gnuplot's complaint.
  spit(dir / "demo_plot.gp", "set terminal svg\nset output 'demo_plot.svg'\nplot nonsense_function(x)\n");
  report::RenderOptions keep;
  keep.keep_scripts = true;
  try {
    report::render_plots({p}, dir, keep);
    ADD_FAILURE() << "no error for a failing script";
  } catch (const UsageError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("gnuplot failed on"), std::string::npos) << m;
    EXPECT_NE(m.find("demo_plot.gp"), std::string::npos) << m;
    EXPECT_NE(m.find("nonsense_function"), std::string::npos) << m;
  }
  fs::remove_all(dir);
}

TEST(Plot, DecimationKeepsTheExtremes) {
  std::vector<double> x, y;
  for (int i = 0; i < 100000; ++i) {
    x.push_back(i);
    y.push_back(std::sin(i * 1e-3));
  }
  y[54321] = 7.0;
  y[777] = -9.0;
  report::decimate_minmax(x, y, 2000);
  EXPECT_LE(x.size(), 2000u);
  EXPECT_GE(x.size(), 1900u);
  EXPECT_EQ(*std::max_element(y.begin(), y.end()), 7.0);
  EXPECT_EQ(*std::min_element(y.begin(), y.end()), -9.0);
  EXPECT_TRUE(std::is_sorted(x.begin(), x.end()));
}

// ---------------------------------------------------------------------------
// Errors

TEST_F(ReportTest, DirectoryWithoutAnalysisIsAnError) {
  const fs::path d = root_ / "empty";
  fs::create_directories(d);
  try {
    report::write_report(d.string());
    FAIL() << "no error";
  } catch (const UsageError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("analysis.json not found"), std::string::npos) << m;
    EXPECT_NE(m.find("cubecal analyze"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line";
  }
  EXPECT_FALSE(fs::exists(d / "report.html"));

  spit(d / "analysis.json", "{\"not\": \"an analysis\"}");
  EXPECT_THROW(report::write_report(d.string()), UsageError);
  spit(d / "analysis.json", "{ truncated");
  EXPECT_THROW(report::write_report(d.string()), UsageError);
  EXPECT_FALSE(fs::exists(d / "report.html"));
}

TEST_F(ReportTest, MissingGnuplotIsAClearError) {
  const fs::path d = fresh("nognuplot");
  report::ReportOptions o;
  o.gnuplot = (root_ / "no-such-dir" / "gnuplot").string();
  try {
    report::write_report(d.string(), o);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    // The path given is named (it used to say "install gnuplot-nox" for a typo in it).
    EXPECT_EQ(std::string(e.what()), report::gnuplot_missing(o.gnuplot));
    EXPECT_EQ(e.field(), cubecal::Field::gnuplot);
    EXPECT_NE(std::string(e.what()).find("no executable gnuplot at " + o.gnuplot), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(d / "report.html"));
  // The demo's way: the page without plots, saying why.
  o.require_plots = false;
  const auto r = report::write_report(d.string(), o);
  EXPECT_TRUE(r.plots.empty());
  const std::string html = slurp(d / "report.html");
  EXPECT_NE(html.find("Plots not rendered: no executable gnuplot at "), std::string::npos);
  EXPECT_NE(html.find("fixed bias"), std::string::npos);
}

// ---------------------------------------------------------------------------
// The page

TEST_F(ReportTest, SelfContainedPageWithEveryPlotAndItsScript) {
  REQUIRE_GNUPLOT();
  const fs::path d = fresh("page");
  const auto r = report::write_report(d.string());
  std::printf("  report.html %zu bytes, %zu plots, written in %.2f s\n", r.html_bytes, r.plots.size(), r.seconds);
  ASSERT_TRUE(fs::exists(d / "report.html"));
  EXPECT_FALSE(fs::exists(d / "report.html.partial"));
  const std::string html = slurp(d / "report.html");
  EXPECT_EQ(html.size(), r.html_bytes);
  EXPECT_LT(html.size(), 3u << 20);

  // Nothing fetched from anywhere: no URLs, no external style sheets, scripts or fonts.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  const std::regex src("src=\"([^\"]{0,40})");
  std::size_t images = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), src); it != std::sregex_iterator(); ++it, ++images)
    EXPECT_EQ((*it)[1].str().rfind("data:image/svg+xml;base64,", 0), 0u) << (*it)[1];

  // Allan, drift, temperature and compensated plots of the rate and field sensors.
  const std::vector<std::string> expected{"allan_rate",       "allan_field",      "drift_rate",
                                          "drift_field",      "temperature_rate", "temperature_field",
                                          "compensated_rate", "compensated_field"};
  for (const auto& e : expected) EXPECT_NE(std::find(r.plots.begin(), r.plots.end(), e), r.plots.end()) << e;
  EXPECT_EQ(images, r.plots.size());
  for (const auto& name : r.plots) {
    for (const char* ext : {".gp", ".dat", ".svg", ".png"})
      EXPECT_TRUE(fs::exists(d / "plots" / (name + ext))) << name << ext;
    const std::string gp = slurp(d / "plots" / (name + ".gp"));
    EXPECT_NE(gp.find("'" + name + ".dat'"), std::string::npos) << name << ": the script reads its data file";
    EXPECT_NE(gp.find("# Written by cubecal"), std::string::npos);
    EXPECT_NE(html.find("id=\"fig-" + name + "\""), std::string::npos) << name;
  }
  // The drift series are decimated.
  const std::string dat = slurp(d / "plots" / "drift_rate.dat");
  EXPECT_LT(count(dat, "\n"), 6u * 2000u + 100u);

  // The parameter table, model, covariance and the command that reproduces it.
  for (const char* s : {"fixed bias", "N, white noise", "B, bias instability", "T, time constant",
                        "K, rate random walk", "Q, quantization", "R, rate ramp", "σ<sub>n</sub>", "σ<sub>μ</sub>",
                        "Gauss–Markov", "c<sub>1</sub>, temperature coefficient", "Covariance", "Correlation",
                        "deg/sqrt(h)", "mGauss/degC", "10 Hz", "sport_static.csv"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
  EXPECT_NE(html.find("cubecal analyze sport_static.csv --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp "
                      "--out base"),
            std::string::npos);
  EXPECT_NE(html.find(" ± "), std::string::npos) << "uncertainties shown";
}

TEST_F(ReportTest, EscapesEveryStringFromTheData) {
  REQUIRE_GNUPLOT();
  const fs::path d = root_ / "evil";
  write_analysis(d, {"g<b>x</b>", "gy&amp;", "g'z\"", "m<i>x", "my", "mz"}, "<img src=x onerror=alert(1)>.csv",
                 "cubecal analyze '<script>alert(\"pwned\")</script>' --out evil", 1.0);
  report::write_report(d.string());
  const std::string html = slurp(d / "report.html");
  for (const char* raw : {"<b>x</b>", "<i>x", "<img src=x", "<script>alert", "gy&amp;<", "g'z\""})
    EXPECT_EQ(html.find(raw), std::string::npos) << raw;
  for (const char* esc :
       {"g&lt;b&gt;x&lt;/b&gt;", "gy&amp;amp;", "g&#39;z&quot;", "&lt;img src=x onerror=alert(1)&gt;.csv",
        "&lt;script&gt;alert(&quot;pwned&quot;)&lt;/script&gt;"})
    EXPECT_NE(html.find(esc), std::string::npos) << esc;
  EXPECT_EQ(count(html, "<script>"), 1u) << "only the page's own image check";
  // The legends of the plots carry the names too, quoted for gnuplot.
  EXPECT_NE(slurp(d / "plots" / "allan_rate.gp").find("title 'g''z\"' noenhanced"), std::string::npos);
}

TEST_F(ReportTest, NeverReplacesAReportUnasked) {
  REQUIRE_GNUPLOT();
  const fs::path d = fresh("replace");
  report::write_report(d.string());
  const auto before = fs::last_write_time(d / "report.html");
  try {
    report::write_report(d.string());
    FAIL() << "replaced without force";
  } catch (const UsageError& e) {
    EXPECT_NE(e.text().find("already exists (add {force}"), std::string::npos) << e.text();
  }
  EXPECT_EQ(fs::last_write_time(d / "report.html"), before);
  report::ReportOptions o;
  o.force = true;
  EXPECT_NO_THROW(report::write_report(d.string(), o));
}

TEST_F(ReportTest, RestyledScriptsAreKeptOnRequest) {
  REQUIRE_GNUPLOT();
  const fs::path d = fresh("restyle");
  report::write_report(d.string());
  const fs::path gp = d / "plots" / "allan_field.gp";
  std::string s = slurp(gp);
  const auto t = s.find("set title '");
  ASSERT_NE(t, std::string::npos);
  s.replace(t, s.find('\n', t) - t, "set title 'My restyled magnetometer plot' noenhanced");
  spit(gp, s);
  report::ReportOptions o;
  o.force = true;
  o.keep_scripts = true;
  report::write_report(d.string(), o);
  EXPECT_NE(slurp(d / "plots" / "allan_field.svg").find("My restyled magnetometer plot"), std::string::npos);
  o.keep_scripts = false;
  report::write_report(d.string(), o);
  EXPECT_EQ(slurp(gp).find("My restyled"), std::string::npos) << "without --keep-scripts the script is rewritten";
}

TEST_F(ReportTest, ModelCurvesWithoutAdevCsv) {
  REQUIRE_GNUPLOT();
  const fs::path d = fresh("noadev");
  fs::remove(d / "adev.csv");
  fs::remove(d / "drift.csv");
  const auto r = report::write_report(d.string());
  EXPECT_EQ(std::count(r.plots.begin(), r.plots.end(), "drift_rate"), 0) << "no drift.csv, no drift plot";
  const std::string dat = slurp(d / "plots" / "allan_rate.dat");
  // Measured curve, then the random-walk model computed from analysis.json.
  EXPECT_GE(count(dat, "# index"), 6u);
  EXPECT_NE(slurp(d / "report.html").find("model curves were computed"), std::string::npos);
}

// ---------------------------------------------------------------------------
// In a browser

TEST_F(ReportTest, RendersInHeadlessChromium) {
  REQUIRE_GNUPLOT();
  const std::string chromium = test::find_chromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium not installed: install it (scripts/install-deps.sh) to check the page in a browser";
  const fs::path d = fresh("browser");
  const auto r = report::write_report(d.string());
  const test::BrowserPage page = test::load_in_chromium(chromium, d / "report.html", d);
  ASSERT_TRUE(page.error.empty()) << page.error;

  // Screenshot.
  ASSERT_EQ(page.image.width, 1200u);
  ASSERT_EQ(page.image.height, 2000u);
  std::printf("  report %zu bytes written in %.2f s; chromium screenshot in %.2f s: %zu colours, %.1f %% ink\n",
              r.html_bytes, r.seconds, page.seconds, page.colours, 100.0 * page.ink_fraction);
  EXPECT_GT(page.colours, 100u) << "text, tables and a coloured plot are in view";
  EXPECT_GT(page.ink_fraction, 0.03);
  EXPECT_GT(page.shot_bytes, 50000u) << "a blank 1200x2000 page is about 11 kB";

  // The DOM after the page's scripts ran: every image decoded.
  const std::string& dumped = page.dom;
  EXPECT_NE(dumped.find("data-images=\"ok\""), std::string::npos)
      << dumped.substr(std::min(dumped.size(), dumped.find("<body")), 300);
  EXPECT_NE(dumped.find("data-image-count=\"" + std::to_string(r.plots.size()) + "\""), std::string::npos);
  EXPECT_EQ(count(dumped, "<img class=\"plot\""), r.plots.size());
}

}  // namespace
}  // namespace cubecal
