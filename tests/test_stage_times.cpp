// Where the time goes (stage_times.hpp): the deviations' stages are timed
// only when asked, the timing changes no result, a stage that does not run
// takes no time, and `--timings` prints every stage that ran with the wall
// clock after the result (and nothing without it).
#include <gtest/gtest.h>

#include <random>
#include <regex>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/stage_times.hpp"

namespace cubecal {
namespace {

std::vector<std::vector<double>> white_channels(std::size_t channels, std::size_t n) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> y(channels, std::vector<double>(n));
  for (auto& c : y)
    for (double& v : c) v = g(rng);
  return y;
}

bool same_points(const pipeline::DevResult& a, const pipeline::DevResult& b) {
  if (a.channels.size() != b.channels.size()) return false;
  for (std::size_t c = 0; c < a.channels.size(); ++c) {
    const auto& p = a.channels[c].points;
    const auto& q = b.channels[c].points;
    if (p.size() != q.size()) return false;
    for (std::size_t j = 0; j < p.size(); ++j)
      if (p[j].dev != q[j].dev || p[j].interval.lo != q[j].interval.lo || p[j].interval.hi != q[j].interval.hi ||
          p[j].alpha != q[j].alpha || p[j].edf != q[j].edf || p[j].n != q[j].n)
        return false;
  }
  return true;
}

TEST(StageTimes, DevStagesAreTimedWithoutChangingTheResult) {
  const auto y = white_channels(3, 200'000);
  pipeline::DevRequest req;
  req.grid = parse_tau_grid("log:20");
  const pipeline::DevResult plain = pipeline::run_dev({"a", "b", "c"}, y, 100.0, req);

  StageTimes times;
  req.times = &times;
  const pipeline::DevResult timed = pipeline::run_dev({"a", "b", "c"}, y, 100.0, req);
  EXPECT_TRUE(same_points(plain, timed));
  EXPECT_GT(times.seconds(Stage::phase), 0.0);
  EXPECT_GT(times.seconds(Stage::kernels), 0.0);
  EXPECT_GT(times.seconds(Stage::noise_id), 0.0);
  EXPECT_GT(times.seconds(Stage::intervals), 0.0);
  // Not the deviations' stages: nothing.
  for (const Stage s : {Stage::read, Stage::fits, Stage::drift, Stage::covariance, Stage::temperature, Stage::output})
    EXPECT_EQ(times.seconds(s), 0.0) << to_string(s);

  // Deviations only: no noise identification.
  StageTimes bare;
  req.times = &bare;
  req.options.intervals = false;
  (void)pipeline::run_dev({"a", "b", "c"}, y, 100.0, req);
  EXPECT_GT(bare.seconds(Stage::kernels), 0.0);
  EXPECT_EQ(bare.seconds(Stage::noise_id), 0.0);
}

TEST(StageTimes, TimersAddAcrossThreadsAndStopOnce) {
  StageTimes t;
  {
    StageTimer a(&t, Stage::fits);
    a.stop();
    const double once = t.seconds(Stage::fits);
    EXPECT_GE(once, 0.0);
    a.stop();  // a second stop adds nothing
    EXPECT_EQ(t.seconds(Stage::fits), once);
  }
  t.add(Stage::drift, 0.25);
  t.add(Stage::drift, 0.5);
  EXPECT_DOUBLE_EQ(t.seconds(Stage::drift), 0.75);
  StageTimer none(nullptr, Stage::drift);  // no sink: nothing to time
  none.stop();
  EXPECT_DOUBLE_EQ(t.seconds(Stage::drift), 0.75);
}

class TimingsCli : public test::TempDirTest {};

TEST_F(TimingsCli, TimingsListTheStagesAfterTheResultAndOnlyWhenAsked) {
  std::string csv = "t,gx,gy\n";
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 0.01);
  for (int i = 0; i < 20000; ++i)
    csv += std::to_string(i * 0.01) + "," + std::to_string(g(rng)) + "," + std::to_string(g(rng)) + "\n";
  const std::string file = write("g.csv", csv);

  const test::CliRun quiet = test::run_cubecal("dev " + file + " --taus octave --format csv");
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("timing"), std::string::npos);

  const test::CliRun dev = test::run_cubecal("dev " + file + " --taus octave --format csv --timings");
  ASSERT_EQ(dev.code, 0) << dev.err;
  EXPECT_EQ(dev.out, quiet.out);  // the result is the same
  for (const char* stage : {"read", "phase", "kernels", "noise id", "intervals", "output", "total"})
    EXPECT_TRUE(std::regex_search(dev.err, std::regex(std::string("cubecal: timing: ") + stage + " +[0-9.]+ s")))
        << stage << "\n"
        << dev.err;
  EXPECT_EQ(dev.err.find("timing: temperature"), std::string::npos);

  const test::CliRun an = test::run_cubecal("analyze " + file + " --unit deg/s --timings");
  ASSERT_EQ(an.code, 0) << an.err;
  for (const char* stage : {"read", "kernels", "fits", "drift", "covariance", "output", "total"})
    EXPECT_TRUE(std::regex_search(an.err, std::regex(std::string("cubecal: timing: ") + stage + " +[0-9.]+ s")))
        << stage << "\n"
        << an.err;
}

}  // namespace
}  // namespace cubecal
