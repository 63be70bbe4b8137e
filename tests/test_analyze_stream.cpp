// The streamed analysis against the in-memory one on records both can
// hold: the accumulators of the one pass (moments and covariance, bias
// drift, least-squares temperature fit) against their whole-record forms,
// and run_analyze_stream against run_analyze: equal where the stride is 1,
// within the in-memory intervals where the window bound puts terms at a
// stride, and the compensated curves equal to the in-memory curves of the
// record compensated with the same coefficients.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/sample_stream.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/noise/covariance.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/streaming_covariance.hpp"
#include "cubecal/noise/streaming_drift.hpp"
#include "cubecal/noise/streaming_temperature.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/analyze_stream.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

using test::TempDirTest;

// Pieces of pseudo-random lengths 1 .. max_piece covering [0, n).
std::vector<std::size_t> piece_ends(std::size_t n, std::size_t max_piece, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> len(1, max_piece);
  std::vector<std::size_t> ends;
  for (std::size_t at = 0; at < n;) {
    at = std::min(n, at + len(rng));
    ends.push_back(at);
  }
  return ends;
}

void expect_rel(double a, double b, double tol, const std::string& what) {
  EXPECT_LE(std::abs(a - b), tol * std::max(std::abs(a), std::abs(b))) << what << ": " << a << " vs " << b;
}

TEST(StreamingCovariance, EqualsTheWholeRecordInAnyPieces) {
  const std::size_t n = 50'000;
  const auto a = test::white_plus_walk(n, 0.01, 0.3, 0.5, 1, 1e3);  // a large mean: no cancellation allowed
  const auto b = test::white_plus_walk(n, 0.01, 1.5, 0.02, 2, -3.0);
  std::vector<double> c(n);
  for (std::size_t i = 0; i < n; ++i) c[i] = 0.5 * a[i] - b[i];  // correlated with both
  const std::vector<std::span<const double>> all{a, b, c};
  for (const std::size_t limit : {std::size_t{0}, std::size_t{12'345}}) {
    StreamingCovariance s(3, limit);
    std::size_t at = 0;
    for (const std::size_t end : piece_ends(n, 3000, 3)) {
      const std::span<const double> p[3] = {std::span(a).subspan(at, end - at), std::span(b).subspan(at, end - at),
                                            std::span(c).subspan(at, end - at)};
      s.add(p);
      at = end;
    }
    const auto want = covariance_matrix(all, limit);
    const auto got = s.matrix();
    EXPECT_EQ(s.count(), limit > 0 ? limit : n);
    // Rounding on the scale of the two channels' deviations (an
    // off-diagonal term may be far smaller than that); n eps = 5e-12 bounds
    // the summation error of either side.
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j)
        EXPECT_LE(std::abs(got(i, j) - want(i, j)), 1e-10 * std::sqrt(want(i, i) * want(j, j))) << i << "," << j;
    double mean = 0.0;
    for (std::size_t i = 0; i < s.count(); ++i) mean += a[i];
    expect_rel(s.mean(0), mean / static_cast<double>(s.count()), 1e-13, "mean");
  }
}

TEST(StreamingDrift, EqualsBiasDriftForEveryWindowShape) {
  const std::size_t n = 20'011;
  const auto y = test::white_plus_walk(n, 0.1, 0.2, 0.05, 4, 40.0);
  // window / 10 exact, with a remainder, below 10 (stride 1), and a stride given.
  for (const auto& [window, stride] : std::vector<std::pair<std::size_t, std::size_t>>{
           {3000, 0}, {3007, 0}, {7, 0}, {1000, 333}, {20'011, 0}, {20'012, 0}}) {
    StreamingDrift s(window, stride);
    std::size_t at = 0;
    for (const std::size_t end : piece_ends(n, 700, window)) {
      s.add(std::span(y).subspan(at, end - at));
      at = end;
    }
    const double mean = 40.1;
    const DriftSeries want = bias_drift(y, 0.1, window, stride, mean);
    const DriftSeries got = s.finish(0.1, mean);
    ASSERT_EQ(got.t.size(), want.t.size()) << window;
    for (std::size_t i = 0; i < want.t.size(); ++i) {
      EXPECT_DOUBLE_EQ(got.t[i], want.t[i]);
      EXPECT_NEAR(got.drift[i], want.drift[i], 1e-10) << window << " at " << i;
    }
    EXPECT_EQ(got.window, window);
  }
}

TEST(StreamingTemperatureFit, EqualsTheInMemoryFit) {
  const std::size_t n = 200'000;
  auto y = test::white_plus_walk(n, 0.1, 0.05, 0.002, 5, 0.7);
  std::vector<double> temp(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(n);
    temp[i] = 31.0 + 6.0 * std::sin(7.0 * t) + 0.01 * std::round(100.0 * std::cos(40.0 * t));
    y[i] += 0.02 * (temp[i] - 30.0) - 0.001 * (temp[i] - 30.0) * (temp[i] - 30.0);
  }
  for (std::size_t order = 1; order <= 3; ++order) {
    StreamingTemperatureFit s(order);
    std::size_t at = 0;
    for (const std::size_t end : piece_ends(n, 5000, order)) {
      s.add(std::span(y).subspan(at, end - at), std::span(temp).subspan(at, end - at));
      at = end;
    }
    const TemperatureFit want = fit_temperature(y, temp, order);
    const TemperatureFit got = s.finish();
    ASSERT_EQ(got.coeff.size(), order + 1);
    expect_rel(got.t_ref, want.t_ref, 1e-12, "t_ref");
    for (std::size_t k = 0; k <= order; ++k) {
      expect_rel(got.coeff[k], want.coeff[k], 1e-8, "coeff " + std::to_string(k));
      // The batches are made of whole blocks: their boundaries move by at
      // most 1/640 of the record, the sigmas by little.
      expect_rel(got.coeff_sigma[k], want.coeff_sigma[k], 0.05, "sigma " + std::to_string(k));
    }
    expect_rel(got.residual_rms, want.residual_rms, 1e-9, "residual rms");
    expect_rel(got.r2, want.r2, 1e-9, "r2");
  }
}

TEST(StreamingTemperatureFit, RefusesWhatTheInMemoryFitRefuses) {
  const std::vector<double> y(100, 1.0), flat(100, 25.0);
  StreamingTemperatureFit constant(1);
  constant.add(y, flat);
  EXPECT_THROW(
      try { (void)constant.finish(); } catch (const CalibrationError& e) {
        EXPECT_EQ(e.reason(), CalibrationReason::degenerate);
        throw;
      },
      CalibrationError);
  std::vector<double> two(100);
  for (std::size_t i = 0; i < two.size(); ++i) two[i] = i % 2 ? 25.0 : 26.0;
  StreamingTemperatureFit quadratic(2);
  quadratic.add(y, two);
  EXPECT_THROW((void)quadratic.finish(), CalibrationError);  // two values, three coefficients
  EXPECT_THROW(StreamingTemperatureFit(6), CalibrationError);
}

class AnalyzeStreamTest : public TempDirTest {
 protected:
  // 10 Hz, 12 h: gx and gy white noise plus a bias random walk, a
  // temperature that drives gy.
  std::string record() {
    const std::size_t n = 432'000;
    const auto gx = test::white_plus_walk(n, 0.1, 0.05, 0.0005, 11, 0.3);
    auto gy = test::white_plus_walk(n, 0.1, 0.08, 0.0002, 12, -0.2);
    std::string t = "t,gx,gy,temp\n";
    t.reserve(n * 40);
    for (std::size_t i = 0; i < n; ++i) {
      const double temp = 25.0 + 4.0 * std::sin(2.0 * M_PI * static_cast<double>(i) / 200'000.0);
      gy[i] += 0.01 * (temp - 25.0);
      t += std::to_string(static_cast<double>(i) / 10.0) + "," + std::to_string(gx[i]) + "," + std::to_string(gy[i]) +
           "," + std::to_string(temp) + "\n";
    }
    return write("r.csv", t);
  }
  pipeline::AnalyzeRequest request(bool temperature) {
    pipeline::AnalyzeRequest req;
    req.units = {*parse_unit("deg/s")};
    req.grid = parse_tau_grid("log:10");
    req.max_samples = 42'000;
    if (temperature) req.temp_index = 0;
    return req;
  }
  io::SeriesOptions options(bool temperature) {
    io::SeriesOptions so;
    so.table.columns = {"gx", "gy"};
    if (temperature) so.table.extra_columns = {"temp"};
    return so;
  }
};

void expect_same_curve(const std::vector<StabilityPoint>& got, const std::vector<StabilityPoint>& want,
                       const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t k = 0; k < want.size(); ++k) {
    EXPECT_EQ(got[k].m, want[k].m) << what << " " << k;
    EXPECT_EQ(got[k].n, want[k].n) << what << " " << k;
    expect_rel(got[k].dev, want[k].dev, 1e-9, what + " dev " + std::to_string(k));
    EXPECT_EQ(got[k].alpha, want[k].alpha) << what << " " << k;
    expect_rel(got[k].edf, want[k].edf, 1e-9, what + " edf " + std::to_string(k));
  }
}

TEST_F(AnalyzeStreamTest, EqualsTheInMemoryAnalysisAtStrideOne) {
  const std::string file = record();
  const io::SeriesOptions so = options(false);
  const pipeline::AnalyzeRequest req = request(false);
  const pipeline::AnalysisResult mem = pipeline::run_analyze(io::read_series(file, so), req);
  const auto in = io::SampleStream::open(file, so, 1 << 16);
  const pipeline::AnalysisResult str = pipeline::run_analyze_stream(*in, req, 1 << 20);
  ASSERT_EQ(str.channels.size(), 2u);
  EXPECT_EQ(str.samples, mem.samples);
  EXPECT_EQ(str.window_bound, std::size_t{1} << 20);
  for (std::size_t c = 0; c < 2; ++c) {
    const auto& a = str.channels[c];
    const auto& b = mem.channels[c];
    expect_same_curve(a.noise.adev, b.noise.adev, "record " + a.name);
    for (std::size_t s : a.adev_strides) EXPECT_EQ(s, 1u);
    expect_same_curve(a.model.adev, b.model.adev, "model head " + a.name);
    EXPECT_EQ(a.model.samples, 42'000u);
    ASSERT_TRUE(a.model.ok && b.model.ok);
    expect_rel(a.model.random_walk.sigma_n, b.model.random_walk.sigma_n, 1e-6, "sigma_n");
    expect_rel(a.noise.readoffs.N.value, b.noise.readoffs.N.value, 1e-9, "N");
    expect_rel(a.mean, b.mean, 1e-12, "mean");
    expect_rel(a.stddev, b.stddev, 1e-10, "stddev");
    ASSERT_EQ(a.drift.drift.size(), b.drift.drift.size());
    for (std::size_t i = 0; i < b.drift.drift.size(); ++i) EXPECT_NEAR(a.drift.drift[i], b.drift.drift[i], 1e-12);
  }
  for (std::size_t i = 0; i < 2; ++i)
    for (std::size_t j = 0; j < 2; ++j) expect_rel(str.covariance(i, j), mem.covariance(i, j), 1e-10, "cov");
}

TEST_F(AnalyzeStreamTest, StridedTermsLieWithinTheInMemoryIntervals) {
  const std::string file = record();
  const io::SeriesOptions so = options(false);
  const pipeline::AnalyzeRequest req = request(false);
  const io::Series whole = io::read_series(file, so);
  const auto in = io::SampleStream::open(file, so);
  const pipeline::AnalysisResult str = pipeline::run_analyze_stream(*in, req, 64);
  std::size_t strided = 0;
  for (std::size_t c = 0; c < 2; ++c) {
    const auto& got = str.channels[c].noise.adev;
    ASSERT_EQ(str.channels[c].adev_strides.size(), got.size());
    // The in-memory OADEV at the factors as the stream rounded them.
    pipeline::DevRequest d;
    d.stat = Stat::oadev;
    d.grid.kind = TauGrid::Kind::list;
    for (const StabilityPoint& p : got) d.grid.taus.push_back(p.tau);
    d.options.conservative_short = true;
    const auto want =
        pipeline::run_dev({"c"}, {std::span<const double>(whole.channels[c])}, whole.rate_hz, {}, d).channels[0].points;
    ASSERT_EQ(want.size(), got.size());
    for (std::size_t k = 0; k < got.size(); ++k) {
      ASSERT_EQ(got[k].m, want[k].m);
      if (str.channels[c].adev_strides[k] == 1) {
        expect_rel(got[k].dev, want[k].dev, 1e-9, "stride 1");
      } else {
        ++strided;
        EXPECT_LT(got[k].n, want[k].n);  // a stride leaves terms out
        EXPECT_GE(got[k].dev, want[k].interval.lo) << "AF " << got[k].m;
        EXPECT_LE(got[k].dev, want[k].interval.hi) << "AF " << got[k].m;
      }
    }
  }
  EXPECT_GT(strided, 40u);
}

TEST_F(AnalyzeStreamTest, TemperatureByLeastSquaresAndTheCompensatedCurves) {
  const std::string file = record();
  const io::SeriesOptions so = options(true);
  const pipeline::AnalyzeRequest req = request(true);
  const io::Series whole = io::read_series(file, so);
  const auto in = io::SampleStream::open(file, so);
  // Without a second pass there is no compensated curve: refused before reading.
  EXPECT_THROW(pipeline::run_analyze_stream(*in, req, 1 << 20), UsageError);
  const pipeline::AnalysisResult str =
      pipeline::run_analyze_stream(*in, req, 1 << 20, [&] { return io::SampleStream::open(file, so); });
  EXPECT_EQ(str.temp_name, "temp");
  for (std::size_t c = 0; c < 2; ++c) {
    ASSERT_TRUE(str.channels[c].temperature);
    const pipeline::TemperatureAnalysis& t = *str.channels[c].temperature;
    EXPECT_FALSE(t.joint);
    EXPECT_NE(t.joint_error.find("not streamed"), std::string::npos);
    const TemperatureFit ols = fit_temperature(whole.channels[c], whole.extra[0], 1);
    expect_rel(t.fit.coeff[1], ols.coeff[1], 1e-8, "coefficient");
    expect_rel(t.fit.coeff_sigma[1], ols.coeff_sigma[1], 0.05, "coefficient sigma");
    const std::vector<double> comp = compensate_temperature(whole.channels[c], whole.extra[0], t.fit);
    pipeline::DevRequest d;
    d.stat = Stat::oadev;
    d.grid = req.grid;
    d.options.conservative_short = true;
    const pipeline::DevResult want = pipeline::run_dev({"c"}, {std::span<const double>(comp)}, whole.rate_hz, {}, d);
    expect_same_curve(t.compensated.adev, want.channels[0].points, "compensated");
  }
  // gy is driven by the temperature at 0.01 deg/s per degC.
  EXPECT_NEAR(str.channels[1].temperature->fit.coeff[1], 0.01, 3.0 * str.channels[1].temperature->fit.coeff_sigma[1]);
}

TEST_F(AnalyzeStreamTest, CommandLine) {
  const std::string file = record();
  const auto r =
      test::run_cubecal("analyze " + file + " --columns gx,gy --unit deg/s --stream --window 256 --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("streamed (window bound 256 samples): Allan terms from AF"), std::string::npos) << r.out;
  // A pipe cannot be read twice: a temperature is refused before any reading.
  const auto t =
      test::run_cubecal_piped("cat " + file, "analyze - --columns gx,gy --unit deg/s --temp-col temp --stream");
  EXPECT_TRUE(test::one_error_line(t)) << t.err;
  EXPECT_NE(t.err.find("give the record as a file"), std::string::npos) << t.err;
  // analysis.json says the stream and its strides, and reads back.
  const auto rep = test::run_cubecal("report " + path("out"));
  EXPECT_EQ(rep.code, 0) << rep.err;
}

// issue 33, item 11: a drift window outside the record gave no drift points
// without a word (and window_s 9.2e16 in the JSON, llround's overflow):
// refused in memory and streamed, with the record's length or the sample
// period; the default window beyond a short record is said in the table and
// the JSON.
class DriftWindowTest : public TempDirTest {
 protected:
  std::string short_record() {  // 100 Hz, 20 s, a gap-free gyro record
    std::string t = "t,gx\n";
    for (std::size_t i = 0; i < 2000; ++i)
      t += std::to_string(static_cast<double>(i) / 100.0) + "," +
           std::to_string(0.01 * std::sin(0.1 * static_cast<double>(i))) + "\n";
    return write("short.csv", t);
  }
};

TEST_F(DriftWindowTest, OutsideTheRecordIsRefusedWithItsLength) {
  const std::string file = short_record();
  for (const std::string mode : {"", " --stream"}) {
    SCOPED_TRACE(mode);
    const std::string cmd = "analyze " + file + " --columns gx --unit deg/s --format json" + mode + " --drift-window ";
    test::CliRun r = test::run_cubecal(cmd + "1e30");
    EXPECT_TRUE(test::one_error_line(r)) << r.code << ' ' << r.err;
    EXPECT_NE(r.err.find("error: --drift-window 1e+30 s is longer than the record (20 s, 2000 samples)"),
              std::string::npos)
        << r.err;
    r = test::run_cubecal(cmd + "20.5");
    EXPECT_TRUE(test::one_error_line(r)) << r.code << ' ' << r.err;
    EXPECT_NE(r.err.find("give at most 20 s"), std::string::npos) << r.err;
    r = test::run_cubecal(cmd + "0.004");
    EXPECT_TRUE(test::one_error_line(r)) << r.code << ' ' << r.err;
    EXPECT_NE(r.err.find("error: --drift-window 0.004 s is shorter than one sample (the sample period is 0.01 s)"),
              std::string::npos)
        << r.err;
    r = test::run_cubecal(cmd + "20");  // the whole record: one point
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["channels"][0]["drift"]["points"], 1);
    EXPECT_DOUBLE_EQ(j["channels"][0]["drift"]["window_s"].get<double>(), 20.0);
    EXPECT_FALSE(j.contains("drift_skipped"));
  }
}

TEST_F(DriftWindowTest, DefaultWindowBeyondTheRecordIsSaid) {
  const std::string file = short_record();
  test::CliRun r = test::run_cubecal("analyze " + file + " --columns gx --unit deg/s");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("no bias drift: the default drift window (300 s for rate sensors) is longer than the record "
                       "(20 s, 2000 samples): give a shorter one (--drift-window)"),
            std::string::npos)
      << r.out;
  r = test::run_cubecal("analyze " + file + " --columns gx --unit deg/s --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NE(j.value("drift_skipped", std::string()).find("300 s"), std::string::npos) << r.out;
}

// A sample period beyond the default window (a rate of 1e-9 Hz): no drift,
// and said, rather than a refusal of a window nobody gave.
TEST(DriftWindow, DefaultWindowBelowOneSampleIsSaid) {
  io::Series s;
  s.rate_hz = 1e-3;
  s.tau0 = 1e3;
  s.names = {"g"};
  s.channels = {std::vector<double>(100)};
  for (std::size_t i = 0; i < 100; ++i) s.channels[0][i] = 0.001 * static_cast<double>(i % 7);
  s.segments = {IndexRange{0, 100}};
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s")};
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, req);
  EXPECT_TRUE(r.channels[0].drift.t.empty());
  EXPECT_NE(r.drift_skipped.find("300 s) is shorter than one sample (the sample period is 1000 s)"), std::string::npos)
      << r.drift_skipped;
}

TEST(DriftWindow, GapsLimitTheWindowToTheLongestSegment) {
  io::Series s;
  s.rate_hz = 10.0;
  s.tau0 = 0.1;
  s.names = {"g"};
  s.channels = {std::vector<double>(1000, 1.0)};
  for (std::size_t i = 0; i < 1000; ++i) s.channels[0][i] += 0.001 * static_cast<double>(i % 7);
  s.segments = {IndexRange{0, 400}, IndexRange{400, 1000}};  // 40 s and 60 s
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s")};
  req.drift_window_s = 61.0;
  try {
    (void)pipeline::run_analyze(s, req);
    ADD_FAILURE() << "a window longer than every segment was accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("longer than the longest gap-free part of the record (60 s of 100 s)"),
              std::string::npos)
        << e.what();
  }
  req.drift_window_s = 60.0;
  EXPECT_EQ(pipeline::run_analyze(s, req).channels[0].drift.t.size(), 1u);
}

}  // namespace
}  // namespace cubecal
