// The dev pipeline: segment pooling and error paths.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cubecal/error.hpp"
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
      EXPECT_LT(q.hi - q.lo, p.hi - p.lo);  // more data, narrower interval
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
      EXPECT_EQ(r1.channels[c].points[k].lo, r2.channels[c].points[k].lo);
    }
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

}  // namespace
}  // namespace cubecal::pipeline
