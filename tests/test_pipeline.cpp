// The dev pipeline: segment pooling and error paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <cstdio>
#include <string>
#include <random>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"

namespace cubecal::pipeline {
namespace {

std::vector<double> white(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = g(rng);
  return v;
}

TEST(DevPipeline, SegmentsPoolTheirDifferences) {
  // Two identical segments: the pooled deviation equals one segment's, with
  // twice the terms and twice the degrees of freedom.
  const auto a = white(4000, 5);
  io::Series one;
  one.names = {"g"};
  one.channels = {a};
  one.rate_hz = 10;
  one.tau0 = 0.1;
  one.segments = {{0, a.size()}};
  io::Series two = one;
  two.channels[0].insert(two.channels[0].end(), a.begin(), a.end());
  two.segments = {{0, a.size()}, {a.size(), 2 * a.size()}};
  DevRequest req;
  req.grid = parse_tau_grid("octave");
  for (Stat st : {Stat::oadev, Stat::tdev, Stat::hdev}) {
    req.stat = st;
    const auto r1 = run_dev(one, req);
    const auto r2 = run_dev(two, req);
    ASSERT_EQ(r1.channels[0].points.size(), r2.channels[0].points.size());
    EXPECT_EQ(r2.segments, 2u);
    for (std::size_t k = 0; k < r1.channels[0].points.size(); ++k) {
      const auto& p = r1.channels[0].points[k];
      const auto& q = r2.channels[0].points[k];
      EXPECT_NEAR(q.dev / p.dev, 1.0, 1e-12) << to_string(st) << " m " << p.m;
      EXPECT_EQ(q.n, 2 * p.n);
      EXPECT_NEAR(q.edf / p.edf, 2.0, 1e-9);
      EXPECT_LT(q.interval.hi - q.interval.lo, p.interval.hi - p.interval.lo);  // more data, narrower interval
    }
  }
}

TEST(DevPipeline, ThreadCountDoesNotChangeResults) {
  const std::vector<std::string> names{"a", "b", "c"};
  const std::vector<std::vector<double>> ch{white(3000, 1), white(3000, 2), white(3000, 3)};
  DevRequest req;
  req.grid = parse_tau_grid("log:10");
  req.threads = 1;
  const auto r1 = run_dev(names, ch, 1.0, req);
  req.threads = 2;
  const auto r2 = run_dev(names, ch, 1.0, req);
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t k = 0; k < r1.channels[c].points.size(); ++k) {
      EXPECT_EQ(r1.channels[c].points[k].dev, r2.channels[c].points[k].dev);
      EXPECT_EQ(r1.channels[c].points[k].interval.lo, r2.channels[c].points[k].interval.lo);
    }
}

// The channels are evaluated a batch at a time (one channel when its taus
// keep the threads busy, one per thread otherwise): every channel's points
// are those of the channel analysed alone, whatever the grid, the threads
// and the segments; the progress reaches 1 without going back.
TEST(DevPipeline, ChannelsInBatchesEqualEachChannelAlone) {
  const std::size_t n = 6000;
  io::Series s;
  s.names = {"a", "b", "c", "d", "e"};
  for (std::uint64_t k = 0; k < 5; ++k) s.channels.push_back(white(n, 10 + k));
  s.rate_hz = 10;
  s.tau0 = 0.1;
  s.segments = {{0, 2500}, {2500, n}};
  for (const char* grid : {"log:20", "1,2", "all"}) {
    for (unsigned threads : {1u, 2u, 3u}) {
      DevRequest req;
      req.grid = parse_tau_grid(grid);
      req.threads = threads;
      std::vector<double> progress;
      req.progress = [&](double f) { progress.push_back(f); };
      const DevResult all = run_dev(s, req);
      req.progress = nullptr;
      ASSERT_FALSE(progress.empty());
      EXPECT_EQ(progress.back(), 1.0);
      EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end())) << grid << " " << threads;
      for (std::size_t c = 0; c < s.channels.size(); ++c) {
        const DevResult one =
            run_dev({s.names[c]}, {std::span<const double>(s.channels[c])}, s.rate_hz, s.segments, req);
        const auto& p = all.channels[c].points;
        const auto& q = one.channels[0].points;
        ASSERT_EQ(p.size(), q.size()) << grid;
        for (std::size_t k = 0; k < p.size(); ++k) {
          EXPECT_EQ(p[k].dev, q[k].dev) << grid << " " << threads << " " << c << " m " << p[k].m;
          EXPECT_EQ(p[k].interval.lo, q[k].interval.lo);
          EXPECT_EQ(p[k].alpha, q[k].alpha);
        }
      }
    }
  }
}

TEST(DevPipeline, SpanOverloadChecksItsArguments) {
  const auto a = white(100, 1);
  const auto b = white(90, 2);
  DevRequest req;
  EXPECT_THROW(run_dev({"a"}, {std::span<const double>(a), std::span<const double>(a)}, 1.0, {}, req),
               std::invalid_argument);
  EXPECT_THROW(run_dev({"a", "b"}, {std::span<const double>(a), std::span<const double>(b)}, 1.0, {}, req),
               std::invalid_argument);
  EXPECT_THROW(run_dev({"a"}, {std::span<const double>(a)}, 1.0, {{0, 101}}, req), std::invalid_argument);
  EXPECT_EQ(run_dev({"a"}, {std::span<const double>(a)}, 1.0, {}, req).samples, 100u);
}

TEST(DevPipeline, NonFiniteSampleNamesTheColumn) {
  auto bad = white(100, 9);
  bad[10] = std::nan("");
  DevRequest req;
  try {
    (void)run_dev({"ok", "gy"}, {white(100, 8), bad}, 1.0, req);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("gy"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("10"), std::string::npos) << e.what();
  }
}

TEST(DevPipeline, TooShortIsAUsageError) {
  DevRequest req;
  req.stat = Stat::hdev;
  EXPECT_THROW((void)run_dev({"g"}, {{1.0, 2.0, 3.0}}, 1.0, req), UsageError);
}

std::vector<double> taus_of(const DevResult& r) {
  std::vector<double> t;
  for (const auto& p : r.channels.at(0).points) t.push_back(p.tau);
  return t;
}

std::string tau_list_text(const std::vector<double>& taus) {
  std::string s;
  for (double t : taus) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", t);
    if (!s.empty()) s += ',';
    s += b;
  }
  return s;
}

// Each statistic's own limit (Stable32's largest averaging factor): on 1000
// frequency samples ADEV and HDEV reach m = 200, the overlapping and
// modified statistics m = 250, TOTDEV m = 500. Listed taus up to the limit
// are evaluated; the ones beyond it are reported with the statistic, m, the
// samples it needs and the samples the record has, never dropped silently.
TEST(DevPipeline, ListedTausBeyondTheStatisticsLimitAreReported) {
  const std::vector<double> y = white(1000, 11);
  const double tau0 = 0.1;
  const struct {
    Stat stat;
    std::size_t max_m, per;
  } cases[] = {{Stat::adev, 200, 5}, {Stat::oadev, 250, 4}, {Stat::mdev, 250, 4},  {Stat::tdev, 250, 4},
               {Stat::hdev, 200, 5}, {Stat::ohdev, 250, 4}, {Stat::totdev, 500, 2}};
  for (const auto& c : cases) {
    SCOPED_TRACE(std::string(to_string(c.stat)));
    const double last = static_cast<double>(c.max_m) * tau0;
    const double beyond = static_cast<double>(c.max_m + 1) * tau0;
    DevRequest req;
    req.stat = c.stat;
    req.grid = parse_tau_grid(tau_list_text({0.1, 1.0, last, beyond, 1e6}));
    const DevResult r = run_dev({"g"}, {y}, 1.0 / tau0, req);
    ASSERT_EQ(taus_of(r).size(), 3u);
    EXPECT_DOUBLE_EQ(taus_of(r)[2], last);
    ASSERT_EQ(r.tau_list.excluded.size(), 2u);
    const ExcludedTau& e = r.tau_list.excluded[0];
    EXPECT_EQ(e.tau, beyond);
    EXPECT_EQ(e.m, static_cast<double>(c.max_m + 1));
    EXPECT_EQ(e.needs, static_cast<double>(c.per * (c.max_m + 1)));
    EXPECT_EQ(e.has, 1000u);
    const std::string want = std::string(to_string(c.stat)) + " needs at least " + std::to_string(c.per) +
                             "m = " + std::to_string(c.per * (c.max_m + 1)) +
                             " samples for m = " + std::to_string(c.max_m + 1) + ", the record has 1000";
    EXPECT_EQ(e.reason, want);
    EXPECT_EQ(r.tau_list.excluded[1].tau, 1e6);
    EXPECT_EQ(r.tau_list.excluded[1].m, 1e7);
    EXPECT_TRUE(r.tau_list.merged.empty());
  }
}

TEST(DevPipeline, ListedTausOfPhaseDataCountPhasePoints) {
  // 1001 phase points are the same record as 1000 frequency samples: OADEV
  // reaches m = 250 and needs 4m+1 phase points for m.
  std::vector<double> x(1001, 0.0);
  const std::vector<double> y = white(1000, 12);
  for (std::size_t i = 0; i < y.size(); ++i) x[i + 1] = x[i] + y[i];
  DevRequest req;
  req.type = DataType::phase;
  req.grid = parse_tau_grid("25,25.1");
  const DevResult r = run_dev({"x"}, {x}, 10.0, req);
  EXPECT_EQ(taus_of(r), std::vector<double>{25.0});
  ASSERT_EQ(r.tau_list.excluded.size(), 1u);
  EXPECT_EQ(r.tau_list.excluded[0].reason,
            "oadev needs at least 4m+1 = 1005 phase samples for m = 251, the record has 1001");
}

// Two listed taus on one averaging factor are one point, evaluated once;
// the later one is reported as merged with the first.
TEST(DevPipeline, ListedTausOnOneFactorAreMerged) {
  DevRequest req;
  req.grid = parse_tau_grid("1,1.04,10,0.96,1");
  const DevResult r = run_dev({"g"}, {white(1000, 13)}, 10.0, req);
  EXPECT_EQ(taus_of(r), (std::vector<double>{1.0, 10.0}));
  ASSERT_EQ(r.tau_list.merged.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.tau_list.merged[i].kept_tau, 1.0);
    EXPECT_EQ(r.tau_list.merged[i].m, 10u);
  }
  EXPECT_EQ(r.tau_list.merged[0].tau, 1.04);
  EXPECT_EQ(r.tau_list.merged[1].tau, 0.96);
  EXPECT_EQ(r.tau_list.merged[2].tau, 1.0);
  EXPECT_TRUE(r.tau_list.excluded.empty());
}

// A generated grid ends at the statistic's limit by construction: nothing
// was asked for that is not evaluated.
TEST(DevPipeline, GeneratedGridsReportNothing) {
  for (const char* g : {"octave", "decade", "all", "log:10"}) {
    DevRequest req;
    req.grid = parse_tau_grid(g);
    req.options.intervals = false;
    const DevResult r = run_dev({"g"}, {white(1000, 14)}, 10.0, req);
    EXPECT_TRUE(r.tau_list.empty()) << g;
  }
}

TEST(DevPipeline, ListedTausBeyondTheLongestSegmentSaySo) {
  io::Series s;
  s.names = {"g"};
  s.channels = {white(1500, 15)};
  s.rate_hz = 10;
  s.tau0 = 0.1;
  s.segments = {{0, 1000}, {1000, 1500}};
  DevRequest req;
  req.grid = parse_tau_grid("1,30");
  const DevResult r = run_dev(s, req);
  ASSERT_EQ(r.tau_list.excluded.size(), 1u);
  EXPECT_EQ(r.tau_list.excluded[0].reason,
            "oadev needs at least 4m = 1200 samples for m = 300, the longest segment has 1000");
}

TEST(DevPipeline, NoListedTauFitsIsAUsageErrorWithTheReason) {
  DevRequest req;
  req.grid = parse_tau_grid("1e6");
  try {
    (void)run_dev({"g"}, {white(100, 16)}, 10.0, req);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("oadev needs at least 4m = 40000000 samples for m = 10000000, "
                                         "the record has 100"),
              std::string::npos)
        << e.what();
  }
}

// analyze: the Allan curve's exclusions, and the listed taus on the curve but
// beyond the --max-samples part the model is fitted on.
TEST(Analyze, ListedTausLeftOutAreReported) {
  io::Series s;
  s.names = {"gx"};
  s.channels = {white(4000, 17)};
  s.rate_hz = 10;
  s.tau0 = 0.1;
  s.segments = {{0, 4000}};
  AnalyzeRequest req;
  req.grid = parse_tau_grid("0.1,1,10,50,100,1000");
  req.max_samples = 1000;
  const AnalysisResult r = run_analyze(s, req);
  ASSERT_EQ(r.tau_list.excluded.size(), 1u);  // 4000 samples: m <= 1000, tau <= 100 s
  EXPECT_EQ(r.tau_list.excluded[0].tau, 1000.0);
  ASSERT_EQ(r.model_excluded_taus.size(), 2u);  // the first 1000: m <= 250, tau <= 25 s
  EXPECT_EQ(r.model_excluded_taus[0].tau, 50.0);
  EXPECT_EQ(r.model_excluded_taus[0].reason,
            "oadev needs at least 4m = 2000 samples for m = 500, the part the model is fitted on has 1000");
  EXPECT_EQ(r.model_excluded_taus[1].tau, 100.0);
  EXPECT_EQ(r.channels[0].noise.adev.size(), 5u);
  EXPECT_EQ(r.channels[0].model.adev.size(), 3u);
}

}  // namespace
}  // namespace cubecal::pipeline
