// record --target and cubecal status (issue 35, deliverable 3): the live
// status of a recording against `analyze` of the same recording, its
// precision and targets, --stop-when-met, bad targets, the status command.
// kill -9 during a run and analyze while it runs: tests/record/test_record_status.py.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/record_status.hpp"

namespace {

namespace fs = std::filesystem;
using cubecal::PlanTarget;
using cubecal::PlanTerm;
using cubecal::pipeline::LiveNoiseStatus;
using cubecal::pipeline::LiveStatus;
using cubecal::pipeline::LiveStatusOptions;
using cubecal::pipeline::LiveTerm;
using cubecal::test::CliRun;
using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;
using cubecal::test::run_cubecal_piped;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

cubecal::Unit counts() { return *cubecal::parse_unit("counts"); }

const LiveTerm& term_of(const LiveStatus& s, std::size_t channel, PlanTerm t) {
  for (const auto& x : s.channels.at(channel).terms)
    if (x.term == t) return x;
  throw std::runtime_error("no such term");
}

// White noise of N = sigma sqrt(dt) plus a random walk of K = q / sqrt(dt) per
// step, seeded: the IEEE 952 terms of the record are N and K.
std::vector<double> white_plus_walk(std::size_t n, double dt, double N, double K, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<double> y(n);
  double walk = 0.0;
  for (auto& v : y) {
    walk += K * std::sqrt(dt) * g(rng);
    v = N / std::sqrt(dt) * g(rng) + walk;
  }
  return y;
}

// The channels analyze takes by default: not the time column, not a
// temperature; the period from the time column's first intervals, its rate
// to nine significant digits, as the record's reader gives it.
TEST(LiveNoiseStatus, ChannelsAndPeriodAsTheRecordingReaderTakesThem) {
  LiveNoiseStatus live({"t", "gx", "temp", "gy"}, std::string("t"), std::nullopt, counts(), {});
  EXPECT_EQ(live.channel_names(), (std::vector<std::string>{"gx", "gy"}));
  for (int k = 0; k < 31; ++k) {
    const double row[] = {0.01 * k + 1e-12 * (k % 3), 1.0, 20.0, 2.0};
    live.push(row);
  }
  EXPECT_EQ(live.period(), 0.0);  // 30 intervals: not yet
  const LiveStatus early = live.evaluate();
  EXPECT_NE(early.why.find("sample period"), std::string::npos) << early.why;
  const double row[] = {0.31, 1.0, 20.0, 2.0};
  live.push(row);
  EXPECT_DOUBLE_EQ(live.period(), 0.01);
  EXPECT_DOUBLE_EQ(live.record_seconds(), 0.32);

  LiveNoiseStatus rated({"a"}, std::nullopt, 50.0, counts(), {});
  EXPECT_DOUBLE_EQ(rated.period(), 0.02);
  LiveNoiseStatus none({"a"}, std::nullopt, std::nullopt, counts(), {});
  const double one[] = {1.0};
  none.push(one);
  EXPECT_NE(none.evaluate().why.find("no sample period"), std::string::npos);
}

TEST(LiveNoiseStatus, ConfidenceOutsideZeroOneIsAUsageError) {
  LiveStatusOptions o;
  o.ci = 1.0;
  EXPECT_THROW(LiveNoiseStatus({"a"}, std::nullopt, 10.0, counts(), o), cubecal::UsageError);
  EXPECT_NEAR(cubecal::pipeline::normal_half_width(0.95), 1.959963984540054, 1e-12);
  EXPECT_NEAR(cubecal::pipeline::normal_half_width(0.6826894921370859), 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(cubecal::pipeline::normal_half_width(0.0)));
}

// White noise and a random walk: N and K resolved near their truth, each
// precision z(ci) sigma / value, a target met exactly when the precision is
// within it, and the time still needed the plan's length less the record.
TEST(LiveNoiseStatus, PrecisionIsTheHalfWidthAtTheConfidenceAndTargetsAreJudgedByIt) {
  const double dt = 0.01, N = 0.01, K = 0.002;
  const std::vector<double> y = white_plus_walk(400000, dt, N, K, 7);
  LiveStatusOptions o;
  o.ci = 0.95;
  o.targets = {{PlanTerm::N, 0.05}, {PlanTerm::K, 0.01}, {PlanTerm::B, 0.2}};
  LiveNoiseStatus live({"gx"}, std::nullopt, 1.0 / dt, counts(), o);
  for (double v : y) live.push(std::span<const double>(&v, 1));
  const LiveStatus s = live.evaluate();
  ASSERT_TRUE(s.why.empty()) << s.why;
  EXPECT_EQ(s.samples, y.size());
  EXPECT_DOUBLE_EQ(s.record_s, 4000.0);
  const double z = 1.959963984540054;
  const LiveTerm& n = term_of(s, 0, PlanTerm::N);
  ASSERT_TRUE(n.resolved) << n.why;
  EXPECT_NEAR(n.value, N, 3 * n.sigma);
  EXPECT_DOUBLE_EQ(n.precision, z * n.sigma / n.value);
  EXPECT_NEAR(n.hi - n.lo, 2 * z * n.sigma, 1e-12 * n.value);
  ASSERT_TRUE(n.target.has_value());
  EXPECT_EQ(n.met, n.precision <= 0.05);
  EXPECT_TRUE(n.met) << n.precision;  // 400000 samples: N to well under 5 %
  EXPECT_EQ(n.remaining_s, 0.0);
  const LiveTerm& k = term_of(s, 0, PlanTerm::K);
  ASSERT_TRUE(k.resolved) << k.why;
  EXPECT_NEAR(k.value, K, 3 * k.sigma);
  EXPECT_FALSE(k.met);  // 1 % of K needs far more than 4000 s
  ASSERT_TRUE(std::isfinite(k.needed_s)) << k.why;
  EXPECT_GT(k.needed_s, 10 * s.record_s);
  EXPECT_DOUBLE_EQ(k.remaining_s, k.needed_s - s.record_s);
  EXPECT_TRUE(std::isnan(n.needed_s));  // met: no plan is made
  EXPECT_FALSE(s.all_met);
  // Terms that are not targets carry no target, no verdict, no time.
  const LiveTerm& t = term_of(s, 0, PlanTerm::T);
  EXPECT_FALSE(t.target.has_value());
  EXPECT_TRUE(std::isnan(t.remaining_s));
}

// White noise alone: no minimum, no random walk: B, T and K unresolved
// with the reason, and their targets never met.
TEST(LiveNoiseStatus, WhiteNoiseLeavesBAndKUnresolvedWithTheReason) {
  const double dt = 0.01;
  const std::vector<double> y = white_plus_walk(100000, dt, 0.01, 0.0, 3);
  LiveStatusOptions o;
  o.targets = {{PlanTerm::B, 0.1}, {PlanTerm::K, 0.2}};
  LiveNoiseStatus live({"t", "gx"}, std::string("t"), std::nullopt, counts(), o);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double row[] = {static_cast<double>(i) * dt, y[i]};
    live.push(row);
  }
  const LiveStatus s = live.evaluate();
  const LiveTerm& b = term_of(s, 0, PlanTerm::B);
  EXPECT_FALSE(b.resolved);
  EXPECT_TRUE(b.bound);
  EXPECT_NE(b.why.find("no minimum yet: B not resolved"), std::string::npos) << b.why;
  EXPECT_FALSE(b.met);
  EXPECT_TRUE(std::isnan(b.remaining_s));
  const LiveTerm& k = term_of(s, 0, PlanTerm::K);
  EXPECT_FALSE(k.resolved);
  EXPECT_NE(k.why.find("K not resolved yet"), std::string::npos) << k.why;
  EXPECT_FALSE(term_of(s, 0, PlanTerm::T).resolved);
  EXPECT_FALSE(s.all_met);
  // The JSON says the same, with nulls where nothing is known.
  const nlohmann::json j = cubecal::pipeline::to_json(s);
  EXPECT_EQ(j["format"], "cubecal-record-status/1");
  EXPECT_TRUE(j["channels"][0]["terms"][2]["precision"].is_null());
  EXPECT_EQ(j["channels"][0]["terms"][2]["term"], "B");
  EXPECT_EQ(j["channels"][0]["terms"][2]["met"], false);
}

TEST(LiveNoiseStatus, ANonFiniteValueStopsThatChannelOnly) {
  LiveNoiseStatus live({"a", "b"}, std::nullopt, 100.0, counts(), {});
  const std::vector<double> y = white_plus_walk(20000, 0.01, 0.01, 0.0, 5);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double row[] = {i == 500 ? std::numeric_limits<double>::quiet_NaN() : y[i], y[i]};
    live.push(row);
  }
  const LiveStatus s = live.evaluate();
  EXPECT_NE(s.channels[0].why.find("the curve stopped"), std::string::npos) << s.channels[0].why;
  EXPECT_TRUE(s.channels[1].why.empty()) << s.channels[1].why;
  EXPECT_TRUE(term_of(s, 1, PlanTerm::N).resolved);
}

class RecordStatusCli : public cubecal::test::TempDirTest {
 protected:
  static std::string simulate(const std::string& args) {
    return std::string(CUBECAL_BINARY) + " simulate " + args + " --out - 2>/dev/null";
  }
  static nlohmann::json json_of(const std::string& text) { return nlohmann::json::parse(text); }
  // Term `t` of channel `c` of a status.
  static const nlohmann::json& status_term(const nlohmann::json& s, std::size_t c, const std::string& t) {
    for (const auto& x : s["channels"][c]["terms"])
      if (x["term"] == t) return x;
    throw std::runtime_error("no term " + t);
  }
};

// (a) The live status against `analyze` of the same recording. The status
// streams each channel's OADEV through the pyramid with a window bound of
// 65536: `analyze --stream --window 65536` computes the same curve and so
// the same numbers (values to 1e-9; sigmas to 1e-6: B's and T's come from
// the minimum's spread, fixed-seed curves on the fit's shape, which carries
// the rounding further). The in-memory `analyze` has every factor at stride
// 1, the status the factors over 32768 samples (327 s) at a stride: the
// values read at short taus (N, B and T at the minimum, 6-40 s here) are the
// same, K (the fit of the whole curve) differs by under 1 % of its sigma,
// and B's and T's sigmas, which take the fit's shape at the bottom, by up to
// 10 %: what a streamed curve changes in what analyze states.
TEST_F(RecordStatusCli, TheLiveStatusAgreesWithAnalyzeOfTheSameRecording) {
  const std::string d = path("rec");
  const CliRun r =
      run_cubecal_piped(simulate("--preset sport-gyro --rate 100 --duration 2h --seed 3"),
                        "record - --out " + d + " --unit deg/s --quiet --target B:10%,K:20%,T:50% --status-every 600s");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json st = json_of(slurp(fs::path(d) / "status.json"));
  EXPECT_EQ(st["final"], true);
  EXPECT_EQ(st["samples"], 720000);
  EXPECT_DOUBLE_EQ(st["record_s"].get<double>(), 7200.0);
  EXPECT_DOUBLE_EQ(st["rate_hz"].get<double>(), 100.0);
  EXPECT_EQ(st["window_bound"], 65536);
  const CliRun streamed = run_cubecal("analyze " + d + " --stream --window 65536 --format json");
  ASSERT_EQ(streamed.code, 0) << streamed.err;
  const CliRun whole = run_cubecal("analyze " + d + " --format json");
  ASSERT_EQ(whole.code, 0) << whole.err;
  const std::map<std::string, std::string> keys = {
      {"N", "white_noise"}, {"K", "rate_random_walk"}, {"B", "bias_instability"}};
  for (const auto* run : {&streamed, &whole}) {
    const nlohmann::json a = json_of(run->out);
    ASSERT_EQ(a["channels"].size(), st["channels"].size());
    for (std::size_t c = 0; c < a["channels"].size(); ++c) {
      const nlohmann::json& ch = a["channels"][c];
      EXPECT_EQ(ch["name"], st["channels"][c]["name"]);
      for (const auto& [t, key] : keys) {
        const nlohmann::json& want = ch["noise"]["reported"][key];
        const nlohmann::json& got = status_term(st, c, t);
        ASSERT_EQ(got["resolved"], true) << t << " " << got["why"];
        EXPECT_EQ(got["source"], want["source"]) << t;
        EXPECT_EQ(got["display"]["unit"], want["unit"]) << t;
        const double v = got["display"]["value"], s = got["display"]["sigma"];
        const bool batch = run == &whole;
        EXPECT_NEAR(want["value"].get<double>(), v, batch && t == "K" ? 0.01 * s : 1e-9 * v) << ch["name"] << t;
        const double sigma_tol = !batch ? 1e-6 : t == "N" ? 1e-9 : t == "K" ? 0.01 : 0.1;
        EXPECT_NEAR(want["sigma"].get<double>(), s, sigma_tol * s) << ch["name"] << " " << t;
      }
      const nlohmann::json& T = status_term(st, c, "T");
      const double t_rel = T["sigma"].get<double>() / T["value"].get<double>();
      EXPECT_NEAR(ch["noise"]["time_constant_s"].get<double>(), T["value"].get<double>(), 1e-3);
      EXPECT_NEAR(ch["noise"]["time_constant_rel_sigma"].get<double>(), t_rel, (run == &whole ? 0.1 : 1e-6) * t_rel);
      for (int e = 0; e < 2; ++e)
        EXPECT_NEAR(ch["noise"]["time_constant_range_s"][e].get<double>(), T["tau_range_s"][e].get<double>(), 0.01);
    }
  }
}

// `analyze DIR --stream` on a recording whose chunk is open (a running or
// crashed recorder): the chunk read up to its last complete line, as the
// in-memory read takes it: the same samples, the same white noise.
TEST_F(RecordStatusCli, AStreamedAnalysisReadsTheOpenChunkUpToItsLastCompleteLine) {
  const std::string d = path("rec");
  const CliRun r = run_cubecal_piped(simulate("--preset sport-gyro --rate 100 --duration 20m --seed 6"),
                                     "record - --out " + d + " --unit deg/s --chunk-bytes 200000");
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json m = json_of(slurp(fs::path(d) / "manifest.json"));
  nlohmann::json& chunks = m["segments"][0]["chunks"];
  ASSERT_GE(chunks.size(), 3u);
  // The last chunk as the manifest of a running recorder has it: open, no
  // CRC, the counts of an earlier sync; a partial line after its last one.
  nlohmann::json& last = chunks.back();
  last["open"] = true;
  last.erase("crc32");
  last["bytes"] = 100;
  last["samples"] = 1;
  m["segments"][0]["end"] = "open";
  std::ofstream(fs::path(d) / "manifest.json") << m.dump(2);
  std::ofstream(fs::path(d) / "seg-001" / last["file"].get<std::string>(), std::ios::app) << "12.3,4";
  const std::string cols = " --columns gx,gy,gz --unit deg/s --format json";
  const CliRun streamed = run_cubecal("analyze " + d + " --stream" + cols);
  ASSERT_EQ(streamed.code, 0) << streamed.err;
  const CliRun whole = run_cubecal("analyze " + d + cols);
  ASSERT_EQ(whole.code, 0) << whole.err;
  const nlohmann::json a = json_of(streamed.out), b = json_of(whole.out);
  EXPECT_EQ(a["input"]["samples"], 120000) << a["input"].dump();
  EXPECT_EQ(a["input"]["samples"], b["input"]["samples"]);
  for (std::size_t c = 0; c < 3; ++c) {
    const double na = a["channels"][c]["noise"]["reported"]["white_noise"]["value"];
    const double nb = b["channels"][c]["noise"]["reported"]["white_noise"]["value"];
    EXPECT_NEAR(na, nb, 1e-12 * nb);
  }
}

// (c) --stop-when-met: the run ends at the first status where every target
// holds, cleanly (chunk closed, segment clean), saying so. A sensor paced
// in real time (1 kHz for 60 s): the status is computed beside the
// recording, which takes the samples that arrive meanwhile.
TEST_F(RecordStatusCli, StopWhenMetEndsTheRunCleanlyAtTheFirstStatusThatMeetsEveryTarget) {
  const std::string d = path("rec");
  const CliRun r =
      run_cubecal_piped(simulate("--preset sport-gyro --rate 1000 --duration 60s --seed 4 --realtime"),
                        "record - --out " + d + " --quiet --target N:3% --status-every 1s --stop-when-met");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json st = json_of(slurp(fs::path(d) / "status.json"));
  ASSERT_TRUE(st["met_at_samples"].is_number()) << st.dump();
  const std::size_t met_at = st["met_at_samples"];
  EXPECT_EQ(met_at % 1000, 0u);  // at a status: every 1 s of 1 kHz samples
  EXPECT_NE(r.err.find("cubecal: record: targets met at " + std::to_string(met_at) + " samples"), std::string::npos)
      << r.err;
  const nlohmann::json m = json_of(slurp(fs::path(d) / "manifest.json"));
  EXPECT_EQ(m["segments"][0]["end"], "clean");
  EXPECT_FALSE(m["segments"][0]["chunks"][0]["open"].get<bool>());
  const std::size_t samples = m["segments"][0]["samples"];
  EXPECT_GE(samples, met_at);
  EXPECT_LT(samples, met_at + 2000);  // those that arrived while the status was computed, not the source's 60000
  EXPECT_EQ(st["final"], true);
  EXPECT_EQ(st["samples"], samples);
  EXPECT_EQ(run_cubecal("analyze " + d + " --unit deg/s").code, 0);
}

// (d) Bad targets and target options: one line naming the flag, exit 2,
// nothing recorded.
TEST_F(RecordStatusCli, BadTargetsExitTwoWithOneLineBeforeAnythingIsRecorded) {
  const std::string feed = "printf 't,gx\\n0,1\\n0.01,2\\n'";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--target B:10", "--target"},
      {"--target X:10%", "--target"},
      {"--target B:0%", "--target"},
      {"--target B:10%,", "--target"},
      {"--target B:10% --ci 1.5", "--ci"},
      {"--target B:10% --status-every 0s", "--status-every"},
      {"--target B:10% --status-every soon", "--status-every"},
      {"--stop-when-met", "--stop-when-met"},
  };
  for (const auto& [args, flag] : cases) {
    const std::string d = path("bad");
    const CliRun r = run_cubecal_piped(feed, "record - --out " + d + " " + args);
    EXPECT_TRUE(one_error_line(r)) << args << ": " << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(d)) << args;
  }
}

// Without --target nothing changes: no status file.
TEST_F(RecordStatusCli, WithoutTargetsThereIsNoStatusFile) {
  const std::string d = path("rec");
  const CliRun r = run_cubecal_piped(simulate("--preset sport-gyro --rate 100 --duration 10m"), "record - --out " + d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(fs::path(d) / "status.json"));
  const CliRun s = run_cubecal("status " + d);
  EXPECT_TRUE(one_error_line(s)) << s.err;
  EXPECT_NE(s.err.find("has no status.json yet"), std::string::npos) << s.err;
}

// cubecal status: the table, --format json as the file holds it, and
// one-line errors for a directory that is not a recording.
TEST_F(RecordStatusCli, StatusPrintsTheTableOrTheFileAndRefusesWhatIsNotARecording) {
  const std::string d = path("rec");
  const CliRun r = run_cubecal_piped(simulate("--preset sport-gyro --rate 100 --duration 30m --seed 5"),
                                     "record - --out " + d + " --unit deg/s --target B:10%,K:20% --status-every 5m");
  ASSERT_EQ(r.code, 0) << r.err;
  const CliRun j = run_cubecal("status " + d + " --format json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(j.out, slurp(fs::path(d) / "status.json"));
  const CliRun t = run_cubecal("status " + d);
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("(the run's last); segment 1, 180000 samples at 100 Hz (0:30:00 recorded); recorder ended "
                       "cleanly"),
            std::string::npos)
      << t.out;
  EXPECT_NE(t.out.find("targets B:10%,K:20% at 68.3% confidence"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("channel  term  value"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("deg/h"), std::string::npos) << t.out;
  // One line per channel and term: 3 channels x N, K, B, T.
  std::size_t rows = 0;
  for (const std::string ch : {"gx", "gy", "gz"})
    for (const std::string term : {"N", "K", "B", "T"})
      rows += t.out.find("\n" + ch + std::string(9 - ch.size(), ' ') + term + "  ") != std::string::npos ? 1 : 0;
  EXPECT_EQ(rows, 12u) << t.out;

  const CliRun not_rec = run_cubecal("status " + path("nothing"));
  EXPECT_TRUE(one_error_line(not_rec)) << not_rec.err;
  EXPECT_NE(not_rec.err.find("is not a recording directory"), std::string::npos) << not_rec.err;
  std::ofstream(fs::path(d) / "status.json") << "{\"format\": \"cubecal-record-status/1\", \"chan";
  const CliRun broken = run_cubecal("status " + d);
  EXPECT_TRUE(one_error_line(broken)) << broken.err;
  EXPECT_NE(broken.err.find("not a readable status"), std::string::npos) << broken.err;
}

}  // namespace
