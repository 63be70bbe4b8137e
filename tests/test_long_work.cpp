// Long work is never silent (issue 10 item 5): `dev` estimates its work and
// warns before a long run, reports progress through the pipeline's callback,
// and `simulate` refuses a record of gigabytes unless --force.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/io/csv_writer.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/simulate_size.hpp"
#include "cubecal/sim/presets.hpp"

namespace cubecal {
namespace {

using test::run_cubecal;

// Sets an environment variable for the scope (the binary inherits it).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~ScopedEnv() { ::unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

// A file-size limit for the scope: a regression that starts writing a huge
// record fails with "file too large" instead of filling the disk.
class ScopedFileSizeLimit {
 public:
  explicit ScopedFileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &old_);
    rlimit r = old_;
    r.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &r);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
  }
  ~ScopedFileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  ScopedFileSizeLimit(const ScopedFileSizeLimit&) = delete;
  ScopedFileSizeLimit& operator=(const ScopedFileSizeLimit&) = delete;

 private:
  rlimit old_{};
  void (*old_handler_)(int) = nullptr;
};

class LongWork : public test::TempDirTest {
 protected:
  std::string white_noise(std::size_t n) {
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g(0.0, 1.0);
    std::ostringstream s;
    s << "t,g\n";
    for (std::size_t i = 0; i < n; ++i) s << static_cast<double>(i) * 0.1 << ',' << g(rng) << '\n';
    return write("white.csv", s.str());
  }
};

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t k = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++k;
  return k;
}

// With the threshold lowered to 0 s (instead of running a 30 s job) the
// all-tau run is "long": a warning with the estimate and the cheaper grid
// before the work, progress lines with the percentage into the log, and
// the same standard output as a quiet run.
TEST_F(LongWork, DevWarnsAndReportsProgressForLongWorkOnly) {
  const std::string file = white_noise(4000);
  const std::string args = "dev " + file + " --columns g --taus all --format csv";
  const test::CliRun quiet = run_cubecal(args);
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("warning"), std::string::npos) << quiet.err;
  EXPECT_EQ(quiet.err.find('%'), std::string::npos) << quiet.err;

  ScopedEnv env("CUBECAL_LONG_WORK_SECONDS", "0");
  const test::CliRun loud = run_cubecal(args);
  ASSERT_EQ(loud.code, 0) << loud.err;
  EXPECT_EQ(loud.out, quiet.out);  // stdout is never garbled
  const auto warn = loud.err.find("cubecal: warning: oadev at 1000 taus");
  ASSERT_NE(warn, std::string::npos) << loud.err;
  EXPECT_NE(loud.err.find("estimated", warn), std::string::npos) << loud.err;
  EXPECT_NE(loud.err.find("--taus log:20", warn), std::string::npos) << loud.err;
  EXPECT_GE(count(loud.err, " %"), 1u) << loud.err;
  EXPECT_NE(loud.err.find("100 %"), std::string::npos) << loud.err;
  EXPECT_EQ(loud.err.find('\r'), std::string::npos);  // a log gets lines, not a terminal's line
}

TEST_F(LongWork, EstimateCountsTheTermsOfTheGrid) {
  io::Series s;
  s.rate_hz = 10.0;
  s.names = {"a", "b"};
  s.channels.assign(2, std::vector<double>(5000));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g;
  for (auto& c : s.channels)
    for (double& v : c) v = g(rng);
  s.segments = {IndexRange{0, 5000}};
  pipeline::DevRequest req;
  req.options.intervals = false;
  req.grid = parse_tau_grid("all");
  const auto all = pipeline::estimate_dev(s, req);
  // OADEV on N = 5001 phase points: m = 1..1250, N - 2m terms each (plus a
  // fixed 64 per factor), two channels.
  double want = 0.0;
  for (std::size_t m = 1; m <= 1250; ++m) want += 5001.0 - 2.0 * static_cast<double>(m) + 64.0;
  EXPECT_EQ(all.taus, 1250u);
  EXPECT_DOUBLE_EQ(all.terms, 2.0 * want);
  EXPECT_GT(all.terms_per_second, 0.0);
  EXPECT_GT(all.seconds, 0.0);
  req.grid = parse_tau_grid("log:20");
  const auto sparse = pipeline::estimate_dev(s, req);
  EXPECT_LT(sparse.terms * 10.0, all.terms);
}

// The callback sees the fraction done rise to 1, from the calling thread.
TEST(LongWorkPipeline, RunDevReportsProgress) {
  std::vector<double> y(20000);
  std::mt19937_64 rng(2);
  std::normal_distribution<double> g;
  for (double& v : y) v = g(rng);
  pipeline::DevRequest req;
  req.grid = parse_tau_grid("all");
  req.threads = 2;
  std::vector<double> seen;
  req.progress = [&](double f) { seen.push_back(f); };
  pipeline::run_dev({"y"}, {y}, 10.0, req);
  ASSERT_GE(seen.size(), 2u);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
  EXPECT_GT(seen.front(), 0.0);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
}

// issue 33, item 13: model --bootstrap reports its progress as dev does:
// nothing for short work, and with the long-work threshold at 0 s the stage
// with the estimate and lines per tenth into the log, stdout unchanged.
TEST_F(LongWork, ModelBootstrapReportsProgressForLongWorkOnly) {
  const std::string file = white_noise(4000);
  const std::string args = "model " + file + " --columns g --model WN+RW --bootstrap 40 --format json";
  const test::CliRun quiet = run_cubecal(args);
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find('%'), std::string::npos) << quiet.err;

  ScopedEnv env("CUBECAL_LONG_WORK_SECONDS", "0");
  const test::CliRun loud = run_cubecal(args);
  ASSERT_EQ(loud.code, 0) << loud.err;
  EXPECT_EQ(loud.out, quiet.out);  // stdout is never garbled
  const auto stage = loud.err.find("cubecal: bootstrap: 40 replicates on 1 channel(s), estimated ");
  ASSERT_NE(stage, std::string::npos) << loud.err;
  EXPECT_GE(count(loud.err, " %"), 2u) << loud.err;
  EXPECT_NE(loud.err.find("bootstrap: 40 replicates on 1 channel(s), estimated", stage + 1), std::string::npos);
  EXPECT_NE(loud.err.find("100 %"), std::string::npos) << loud.err;
  EXPECT_EQ(loud.err.find('\r'), std::string::npos);  // a log gets lines, not a terminal's line
}

// The bootstrap's callback: (0, total) first, counts that increase, (total,
// total) last, all from the calling thread.
TEST(LongWorkPipeline, RunModelReportsBootstrapProgress) {
  io::Series s;
  s.rate_hz = 10.0;
  s.names = {"a", "b"};
  s.channels.assign(2, std::vector<double>(4096));
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g;
  for (auto& c : s.channels)
    for (double& v : c) v = g(rng);
  s.segments = {IndexRange{0, 4096}};
  pipeline::ModelRequest req;
  req.model = "WN";
  req.bootstrap = 30;
  req.threads = 2;
  std::vector<std::pair<std::size_t, std::size_t>> seen;
  bool other_thread = false;
  const auto caller = std::this_thread::get_id();
  req.bootstrap_progress = [&](std::size_t done, std::size_t total) {
    seen.emplace_back(done, total);
    other_thread = other_thread || std::this_thread::get_id() != caller;
  };
  const pipeline::ModelResult r = pipeline::run_model(s, req);
  ASSERT_GE(seen.size(), 3u);
  EXPECT_EQ(seen.front(), std::make_pair(std::size_t{0}, std::size_t{60}));
  EXPECT_EQ(seen.back(), std::make_pair(std::size_t{60}, std::size_t{60}));
  for (std::size_t i = 1; i < seen.size(); ++i) {
    EXPECT_GT(seen[i].first, seen[i - 1].first);
    EXPECT_EQ(seen[i].second, 60u);
  }
  EXPECT_FALSE(other_thread);
  EXPECT_EQ(r.channels[0].replicates, 30u);
}

TEST_F(LongWork, SimulateRefusesARecordOfGigabytes) {
  ScopedFileSizeLimit limit(50'000'000);
  const std::string out = path("big.csv");
  const test::CliRun r = run_cubecal("simulate --preset sport-gyro --rate 1000 --duration 72d --out " + out);
  EXPECT_TRUE(test::one_error_line(r)) << r.code << ' ' << r.err;
  EXPECT_NE(r.err.find("373 GB"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--duration"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".partial"));
}

// Past any disk even with --force: the sample count would overflow (it
// started writing 9.2e18 samples before).
TEST_F(LongWork, SimulateRefusesAnImpossibleDurationEvenWithForce) {
  ScopedFileSizeLimit limit(50'000'000);
  const std::string out = path("huge.csv");
  const test::CliRun r = run_cubecal("simulate --preset sport-gyro --duration 1e300d --force --out " + out);
  EXPECT_TRUE(test::one_error_line(r)) << r.code << ' ' << r.err;
  EXPECT_NE(r.err.find("--duration: duration x rate = 8.64e+305 samples"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out + ".partial"));
}

// The limit lowered to 1 kB: a 10 s record is refused, and --force writes it.
TEST_F(LongWork, SimulateForceLiftsTheSizeLimit) {
  ScopedEnv env("CUBECAL_SIMULATE_MAX_BYTES", "1000");
  const std::string out = path("small.csv");
  const std::string args = "simulate --preset sport-gyro --duration 10s --out " + out;
  const test::CliRun refused = run_cubecal(args);
  EXPECT_TRUE(test::one_error_line(refused)) << refused.code << ' ' << refused.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  const test::CliRun forced = run_cubecal(args + " --force");
  EXPECT_EQ(forced.code, 0) << forced.err;
  EXPECT_TRUE(std::filesystem::exists(out));
}

// The estimate is close to (and not below) the bytes write_simulation writes.
TEST_F(LongWork, TextSizeEstimateMatchesTheWrittenFile) {
  pipeline::SimulateRequest req;
  req.triads = {preset("sport-gyro"), preset("sport-mag")};
  req.rate_hz = 10.0;
  req.duration_s = 3600.0;
  const std::string out = path("sim.csv");
  {
    io::CsvWriter w(out, false);
    pipeline::write_simulation(req, w);
    w.commit();
  }
  const double actual = static_cast<double>(std::filesystem::file_size(out));
  const double est = pipeline::estimated_text_bytes(req);
  EXPECT_GE(est, actual);
  EXPECT_LE(est, 1.3 * actual);

  req.rate_hz = 1000.0;
  req.duration_s = 72.0 * 86400.0;
  EXPECT_GT(pipeline::estimated_text_bytes(req), 2e9);
  req.duration_s = 1e300;
  EXPECT_TRUE(std::isfinite(pipeline::estimated_text_bytes(req)));
  req.duration_s = 1e-6;
  EXPECT_EQ(pipeline::estimated_text_bytes(req), 0.0);
}

}  // namespace
}  // namespace cubecal
