// A recording directory of `cubecal record` read as a record
// (io/recording.hpp): directories written here by hand (manifest.json and
// chunk files), then read through io::read_series and the commands.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal {
namespace {

namespace fs = std::filesystem;
using test::TempDirTest;

// Command-line words joined with spaces.
std::string words(std::initializer_list<std::string> parts) {
  std::string s;
  for (const auto& p : parts) {
    if (!s.empty()) s += ' ';
    s += p;
  }
  return s;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// One sample as the recorder writes it: receive stamps, then the columns.
struct Row {
  double host_mono = 0.0;
  double host_utc = 0.0;
  std::vector<double> values;
};

class RecordingTest : public TempDirTest {
 protected:
  io::RecordingManifest m;

  void SetUp() override {
    TempDirTest::SetUp();
    m.columns = {"t", "gx", "gy"};
    m.time_column = "t";
    m.source = "test";
  }

  std::string dir() const { return (dir_ / "rec").string(); }

  // Starts segment `index` (1-based) at UTC `utc` and monotonic `mono`.
  io::RecordingSegment& segment(int index, const std::string& utc, double mono) {
    io::RecordingSegment s;
    s.index = index;
    s.dir = std::string("seg-00") += std::to_string(index);
    s.start_utc = utc;
    s.start_mono_s = mono;
    s.end = io::SegmentEnd::clean;
    fs::create_directories(fs::path(dir()) / s.dir);
    m.segments.push_back(s);
    return m.segments.back();
  }

  static std::string text_of(const std::vector<std::string>& columns, const std::vector<Row>& rows) {
    std::string s = "host_mono_s,host_utc_s";
    for (const auto& c : columns) (s += ',') += c;
    s += "\n";
    for (const auto& r : rows) {
      ((s += fixed(r.host_mono, 9)) += ',') += fixed(r.host_utc, 9);
      for (double v : r.values) {
        std::ostringstream o;
        o.precision(17);
        o << v;
        s += ',';
        s += o.str();
      }
      s += "\n";
    }
    return s;
  }

  // Writes chunk `number` of `seg` holding `rows` (plus `tail` bytes after
  // them); closed chunks get their size and CRC-32 in the manifest.
  std::string chunk(io::RecordingSegment& seg, int number, const std::vector<Row>& rows, bool open = false,
                    const std::string& tail = "") {
    char name[32];
    std::snprintf(name, sizeof name, "chunk-%06d.csv", number);
    const std::string text = text_of(m.columns, rows);
    const fs::path p = fs::path(dir()) / seg.dir / name;
    std::ofstream(p, std::ios::binary) << text << tail;
    io::RecordingChunk c;
    c.file = name;
    c.samples = rows.size();
    c.bytes = text.size();
    c.open = open;
    if (!open)
      c.crc32 = static_cast<std::uint32_t>(
          ::crc32(::crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(text.data()), static_cast<uInt>(text.size())));
    if (!rows.empty()) {
      c.first_host_utc_s = rows.front().host_utc;
      c.last_host_utc_s = rows.back().host_utc;
    }
    seg.chunks.push_back(c);
    seg.samples += rows.size();
    if (open) seg.end = io::SegmentEnd::open;
    return p.string();
  }

  void finish() { io::write_manifest(dir(), m); }

  // The rows as one CSV file of the data columns (t, gx, gy).
  static std::string joined_text(const std::vector<Row>& all) {
    std::string joined = "t,gx,gy\n";
    for (const auto& r : all) {
      std::ostringstream o;
      o.precision(17);
      o << r.values[0] << ',' << r.values[1] << ',' << r.values[2] << '\n';
      joined += o.str();
    }
    return joined;
  }

  // Changes one digit of a chunk, the digit after the last `from` (",1"),
  // to `to`, keeping its size; returns the new text.
  static std::string change_a_digit(const std::string& path, const std::string& from, char to) {
    std::string text;
    {
      std::ifstream in(path, std::ios::binary);
      std::stringstream ss;
      ss << in.rdbuf();
      text = ss.str();
    }
    const std::size_t at = text.rfind(from);
    if (at == std::string::npos) {
      ADD_FAILURE() << path << " holds no " << from;
      return text;
    }
    text[at + 1] = to;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    return text;
  }

  // n samples of (t, gx, gy) at `rate`: t = t0 + i / rate, gx = bias + noise,
  // gy = i; received at host_mono = mono0 + i / rate (UTC utc0 + i / rate),
  // `batch` samples per receive stamp.
  static std::vector<Row> rows(std::size_t n, double rate, double t0, double mono0, double utc0, double bias = 0.0,
                               std::size_t batch = 1, unsigned seed = 1, std::size_t first_index = 0) {
    std::mt19937_64 gen(seed);
    std::normal_distribution<double> noise(0.0, 0.1);
    std::vector<Row> out;
    for (std::size_t i = 0; i < n; ++i) {
      const double host = static_cast<double>((i / batch) * batch) / rate;
      out.push_back({mono0 + host,
                     utc0 + host,
                     {t0 + static_cast<double>(i) / rate, bias + noise(gen), static_cast<double>(first_index + i)}});
    }
    return out;
  }

  io::Series read(io::GapPolicy gaps = io::GapPolicy::error) const {
    io::SeriesOptions o;
    o.gaps = gaps;
    return io::read_series(dir(), o);
  }
};

constexpr double kUtc0 = 1795784400.0;  // 2026-11-27T13:00:00Z
const char* kStart0 = "2026-11-27T13:00:00.000000000Z";

TEST_F(RecordingTest, ChunksOfASegmentAreJoinedInOrder) {
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(250, 100.0, 0.0, 100.0, kUtc0);
  chunk(s, 1, {all.begin(), all.begin() + 100});
  chunk(s, 2, {all.begin() + 100, all.begin() + 200});
  chunk(s, 3, {all.begin() + 200, all.end()});
  finish();
  ASSERT_TRUE(io::looks_like_recording(dir()));
  const io::Series r = read();
  EXPECT_EQ(r.file, dir());
  ASSERT_EQ(r.samples(), 250u);
  EXPECT_DOUBLE_EQ(r.rate_hz, 100.0);
  EXPECT_EQ(r.time_name, "t");
  EXPECT_TRUE(r.default_columns);
  EXPECT_EQ(r.names, (std::vector<std::string>{"gx", "gy"}));
  EXPECT_EQ(r.segments.size(), 1u);
  for (std::size_t i = 0; i < 250; ++i) {
    ASSERT_EQ(r.channels[1][i], static_cast<double>(i)) << "row " << i;
    ASSERT_EQ(r.channels[0][i], all[i].values[1]) << "row " << i;
  }
}

TEST_F(RecordingTest, ChunkWhoseCrcDiffersIsRefusedByName) {
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(200, 100.0, 0.0, 100.0, kUtc0);
  chunk(s, 1, {all.begin(), all.begin() + 100});
  const std::string second = chunk(s, 2, {all.begin() + 100, all.end()});
  finish();
  ASSERT_EQ(read().samples(), 200u);
  // One digit changed, the size kept.
  const std::string text = change_a_digit(second, ",1", '2');
  try {
    read();
    FAIL() << "a changed chunk was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), second);
    EXPECT_NE(e.problem().find("CRC-32"), std::string::npos) << e.what();
    EXPECT_NE(e.hint().find("changed since it was recorded"), std::string::npos) << e.what();
  }
  // A chunk cut short: its size.
  std::ofstream(second, std::ios::binary | std::ios::trunc) << text.substr(0, text.size() - 10);
  try {
    read();
    FAIL() << "a truncated chunk was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), second);
    EXPECT_NE(e.problem().find("bytes where the manifest recorded"), std::string::npos) << e.what();
  }
  const auto cli = test::run_cubecal(words({"dev", dir(), "--stat oadev"}));
  EXPECT_TRUE(test::one_error_line(cli)) << cli.err;
  EXPECT_NE(cli.err.find("chunk-000002.csv"), std::string::npos) << cli.err;
}

TEST_F(RecordingTest, OpenChunkIsReadUpToItsLastCompleteLine) {
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(180, 100.0, 0.0, 100.0, kUtc0);
  chunk(s, 1, {all.begin(), all.begin() + 100});
  // The recorder died in the middle of a line, after samples the manifest
  // has not counted yet: those complete lines are read, the partial one not.
  chunk(s, 2, {all.begin() + 100, all.end()}, true, "101.8,1795784401.8,1.8,0.0");
  s.chunks.back().samples = 50;  // the counts of its last flush
  s.chunks.back().bytes = 100;
  finish();
  const io::Series r = read();
  ASSERT_EQ(r.samples(), 180u);
  EXPECT_EQ(r.channels[1].back(), 179.0);
  EXPECT_DOUBLE_EQ(r.time.back(), 1.79);
}

TEST_F(RecordingTest, SegmentsAreJoinedByTheGapsPolicy) {
  // Segment 1: t 0 .. 0.99 s; segment 2: the sensor power-cycled, its clock
  // starts at 0 again.
  auto& s1 = segment(1, kStart0, 100.0);
  chunk(s1, 1, rows(100, 100.0, 0.0, 100.0, kUtc0, 1.0));
  // Segment 2 started 5 s after the first (another boot: another monotonic
  // clock); its first sample came 0.99 s after its start, i.e. 5.00 s after
  // segment 1's last (at 0.99 s).
  auto& s2 = segment(2, "2026-11-27T13:00:05.000000000Z", 5000.0);
  chunk(s2, 1, rows(100, 100.0, 0.0, 5000.99, kUtc0 + 5.99, 2.0, 1, 2));
  finish();
  const std::string second = (fs::path(dir()) / "seg-002" / "chunk-000001.csv").string();
  try {
    read(io::GapPolicy::error);
    FAIL() << "the break between the segments was not seen";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), second);
    EXPECT_EQ(e.line(), 2u) << "its first sample";
    EXPECT_NE(e.problem().find("gap of 5.000 s (500 periods"), std::string::npos) << e.what();
  }
  const io::Series split = read(io::GapPolicy::split);
  ASSERT_EQ(split.samples(), 200u);
  ASSERT_EQ(split.segments.size(), 2u);
  EXPECT_EQ(split.segments[0].size(), 100u);
  EXPECT_EQ(split.segments[1].size(), 100u);
  EXPECT_EQ(split.irregular_intervals, 1u);
  EXPECT_NEAR(split.time[100] - split.time[99], 5.0, 1e-9);
  const io::Series skip = read(io::GapPolicy::skip);
  ASSERT_EQ(skip.samples(), 699u) << "499 missing samples between";
  EXPECT_EQ(skip.segments.size(), 1u);
  std::size_t missing = 0;
  for (double v : skip.channels[0]) missing += std::isnan(v) ? 1 : 0;
  EXPECT_EQ(missing, 499u);
  EXPECT_EQ(skip.channels[1][599], 0.0) << "segment 2's first sample after the 499 missing";

  // turnon: one run per segment, each with its own bias.
  const auto runs = io::read_recording_segments(dir(), io::SeriesOptions{});
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[1].file, dir() + "/seg-002");
  const auto cli = test::run_cubecal(words({"turnon", dir(), "--columns gx --unit deg/s --format json"}));
  ASSERT_EQ(cli.code, 0) << cli.err;
  const auto j = nlohmann::json::parse(cli.out);
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_NEAR(j["runs"][0]["channels"][0]["mean"].get<double>(), 1.0, 0.05);
  EXPECT_NEAR(j["runs"][1]["channels"][0]["mean"].get<double>(), 2.0, 0.05);
  EXPECT_EQ(j["runs"][1]["file"], dir() + "/seg-002");
}

TEST_F(RecordingTest, TimeIsTheDeviceColumnNotTheReceiveStamps) {
  // 50 Hz from the device, received 5 samples per read (one stamp each):
  // the receive stamps alone could not time the samples.
  auto& s1 = segment(1, kStart0, 100.0);
  chunk(s1, 1, rows(100, 50.0, 10.0, 100.0, kUtc0, 0.0, 5));
  // The recorder restarted while the sensor ran on: the device clock
  // continues (the next sample at 12.00 s), which is kept: the host's
  // batched stamps put the break 0.12 s long, within their 1 s slack.
  auto& s2 = segment(2, "2026-11-27T13:00:02.000000000Z", 400.0);
  chunk(s2, 1, rows(100, 50.0, 12.0, 400.02, kUtc0 + 2.02, 0.0, 5, 3, 100));
  finish();
  const io::Series r = read();
  ASSERT_EQ(r.samples(), 200u);
  EXPECT_DOUBLE_EQ(r.rate_hz, 50.0);
  EXPECT_EQ(r.time_name, "t");
  EXPECT_EQ(r.segments.size(), 1u);
  EXPECT_DOUBLE_EQ(r.time[0], 10.0);
  EXPECT_DOUBLE_EQ(r.time[100], 12.0);
  for (std::size_t i = 0; i < 200; ++i) ASSERT_EQ(r.channels[1][i], static_cast<double>(i));

  // Without the device column (and no rate) the receive stamps decide, and
  // several samples per stamp cannot be timed: refused at the place.
  io::SeriesOptions o;
  o.time_col = "host_mono_s";
  try {
    io::read_series(dir(), o);
    FAIL() << "batched receive stamps were taken as sample times";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (fs::path(dir()) / "seg-001" / "chunk-000001.csv").string());
    EXPECT_EQ(e.line(), 3u);
  }
  // A rate spaces the samples of each segment from its first receive stamp.
  o.time_col.clear();
  o.rate_hz = 50.0;
  o.gaps = io::GapPolicy::split;
  const io::Series spaced = io::read_series(dir(), o);
  EXPECT_EQ(spaced.samples(), 200u);
  EXPECT_EQ(spaced.left_out, (std::vector<std::string>{"t"})) << "a time column is never a channel";
  ASSERT_EQ(spaced.time.size(), 200u);
  EXPECT_NEAR(spaced.time[100] - spaced.time[99], 0.04, 1e-9) << "2.02 s - 1.98 s on the host clock";
}

TEST_F(RecordingTest, DeviceClockResetInsideASegmentIsABreak) {
  // The sensor restarted while the recorder ran on: its clock starts at 0
  // again at row 100 (line 102), received 3 s after the sample before it.
  auto& s = segment(1, kStart0, 100.0);
  auto all = rows(100, 100.0, 0.0, 100.0, kUtc0, 1.0);
  const auto after = rows(100, 100.0, 0.0, 103.99, kUtc0 + 3.99, 2.0, 1, 2, 100);
  all.insert(all.end(), after.begin(), after.end());
  const std::string path = chunk(s, 1, all);
  finish();
  try {
    read();
    FAIL() << "the reset was not seen";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 102u);
    EXPECT_NE(e.problem().find("gap of 3.000 s (300 periods"), std::string::npos) << e.what();
  }
  const io::Series split = read(io::GapPolicy::split);
  ASSERT_EQ(split.segments.size(), 2u);
  EXPECT_EQ(split.segments[1].begin, 100u);
  const io::Series skip = read(io::GapPolicy::skip);
  EXPECT_EQ(skip.samples(), 499u) << "299 missing samples between";
  EXPECT_DOUBLE_EQ(skip.time.back(), 3.99 + 0.99);
}

TEST_F(RecordingTest, ReconnectRestartsTheSpacingOfARateTimedRecording) {
  // No device time: the samples are spaced at the rate from the receive
  // stamps. The source was away for 5 s before sample 100 (its reconnect
  // event): the samples after it start from their own receive stamp, and
  // the break is judged by the gap policy, as one between segments.
  m.columns = {"gx", "gy"};
  m.time_column.reset();
  m.rate_hz = 10.0;
  auto& s = segment(1, kStart0, 100.0);
  std::vector<Row> all;
  for (std::size_t i = 0; i < 200; ++i) {
    const double host = static_cast<double>(i) / 10.0 + (i >= 100 ? 5.0 : 0.0);
    all.push_back({100.0 + host, kUtc0 + host, {0.01 * static_cast<double>(i % 7), static_cast<double>(i)}});
  }
  chunk(s, 1, {all.begin(), all.begin() + 150});
  chunk(s, 2, {all.begin() + 150, all.end()});
  io::RecordingEvent e;
  e.kind = io::RecordingEvent::Kind::reconnect;
  e.sample = 100;
  e.host_utc_s = kUtc0 + 15.0;
  s.events.push_back(e);
  finish();
  EXPECT_THROW(read(), InputError);  // a gap of 5.1 s, refused by default
  const io::Series split = read(io::GapPolicy::split);
  ASSERT_EQ(split.samples(), 200u);
  ASSERT_EQ(split.segments.size(), 2u);
  EXPECT_EQ(split.segments[1].begin, 100u);
  const io::Series skip = read(io::GapPolicy::skip);  // 51 periods: 50 missing samples between
  ASSERT_EQ(skip.samples(), 250u);
  EXPECT_EQ(skip.channels[1][99], 99.0);
  EXPECT_TRUE(std::isnan(skip.channels[1][100]));
  EXPECT_EQ(skip.channels[1][150], 100.0);
}

TEST_F(RecordingTest, ARecordingBeyondTheMemoryBudgetIsReadWholeWithAWarning) {
  // About 1.4 MB of chunks against a 1 MB budget: the size counted from the
  // manifest, and no switch to the streamed path (which takes no recording).
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(24000, 100.0, 0.0, 100.0, kUtc0, 0.5);
  chunk(s, 1, {all.begin(), all.begin() + 12000});
  chunk(s, 2, {all.begin() + 12000, all.end()});
  finish();
  ASSERT_GT(s.chunks[0].bytes + s.chunks[1].bytes, std::size_t{1} << 20);
  for (const std::string name : {"dev", "analyze"}) {
    const std::string unit = name == "analyze" ? " --unit deg/s" : "";
    const auto small = test::run_cubecal(words({name, dir(), "--columns gx --memory 1M" + unit}));
    ASSERT_EQ(small.code, 0) << name << ": " << small.err;
    EXPECT_NE(small.err.find("a recording directory is read whole"), std::string::npos) << name << ": " << small.err;
    const auto plain = test::run_cubecal(words({name, dir(), "--columns gx" + unit}));
    ASSERT_EQ(plain.code, 0) << plain.err;
    EXPECT_EQ(plain.err.find("read whole"), std::string::npos) << plain.err;
    EXPECT_EQ(small.out, plain.out) << name;
  }
}

TEST_F(RecordingTest, OneClosedSegmentIsStreamedAsOneText) {
  // --stream reads the chunks in turn as one text: the same result as the
  // chunks joined into one file and streamed, each chunk still checked
  // against its CRC-32; several segments are read whole, not streamed.
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(3000, 100.0, 0.0, 100.0, kUtc0, 0.5);
  chunk(s, 1, {all.begin(), all.begin() + 1000});
  chunk(s, 2, {all.begin() + 1000, all.begin() + 2000});
  const std::string third = chunk(s, 3, {all.begin() + 2000, all.end()});
  finish();
  const std::string file = write("joined.csv", joined_text(all));
  // Small pieces, so that pieces end inside chunks and chunks inside pieces.
  const std::string opts = "--columns gx --format csv --stream --memory 1M";
  const auto a = test::run_cubecal(words({"dev", dir(), opts}));
  const auto b = test::run_cubecal(words({"dev", file, opts}));
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  const auto in_memory = test::run_cubecal(words({"dev", dir(), "--columns gx --format csv"}));
  ASSERT_EQ(in_memory.code, 0) << in_memory.err;
  // A changed chunk: refused by name while streaming.
  change_a_digit(third, ",2", '3');
  const auto changed = test::run_cubecal(words({"dev", dir(), opts}));
  EXPECT_EQ(changed.code, 2);
  EXPECT_NE(changed.err.find(third), std::string::npos) << changed.err;
  EXPECT_NE(changed.err.find("changed since it was recorded"), std::string::npos) << changed.err;
  EXPECT_EQ(changed.out, "") << "nothing is written before the record is known whole";
  // Two segments: read whole, not streamed.
  auto& s2 = segment(2, "2026-11-27T13:01:00.000000000Z", 160.0);
  chunk(s2, 1, rows(100, 100.0, 60.0, 160.0, kUtc0 + 60.0));
  finish();
  const auto two = test::run_cubecal(words({"dev", dir(), opts}));
  EXPECT_EQ(two.code, 2);
  EXPECT_NE(two.err.find("leave out --stream"), std::string::npos) << two.err;
  EXPECT_EQ(std::count(two.err.begin(), two.err.end(), '\n'), 1) << two.err;
}

TEST_F(RecordingTest, AStreamedRecordingsBadLineIsNamedInItsChunk) {
  // The chunks are read as one text; a fault in the second chunk is named by
  // that chunk's path and its own line (its header is line 1), as reading the
  // directory whole names it, not by the directory and a line counted
  // through the joined text.
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(3000, 100.0, 0.0, 100.0, kUtc0, 0.5);
  chunk(s, 1, {all.begin(), all.begin() + 1000});
  const std::string second = chunk(s, 2, {all.begin() + 1000, all.begin() + 2000});
  chunk(s, 3, {all.begin() + 2000, all.end()});
  // Row 700 of the second chunk (line 702) gets a word for its gx; the
  // manifest's size and CRC-32 follow, as if it had been recorded so.
  std::string text;
  {
    std::ifstream in(second, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  std::size_t at = 0;
  for (int line = 1; line < 702; ++line) at = text.find('\n', at) + 1;
  at = text.find(',', text.find(',', text.find(',', at) + 1) + 1) + 1;  // gx: after host_mono, host_utc, t
  text.replace(at, text.find(',', at) - at, "oops");
  std::ofstream(second, std::ios::binary | std::ios::trunc) << text;
  io::RecordingChunk& c = m.segments.back().chunks[1];
  c.bytes = text.size();
  c.crc32 = static_cast<std::uint32_t>(
      ::crc32(::crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(text.data()), static_cast<uInt>(text.size())));
  finish();
  for (const char* stream : {"--stream --memory 1M", ""}) {
    const auto cli = test::run_cubecal(words({"dev", dir(), "--columns gx --format csv", stream}));
    EXPECT_EQ(cli.code, 2) << stream;
    EXPECT_TRUE(test::one_error_line(cli)) << stream << ": " << cli.err;
    EXPECT_NE(cli.err.find(second + ":702:"), std::string::npos) << stream << ": " << cli.err;
    EXPECT_NE(cli.err.find("'oops'"), std::string::npos) << stream << ": " << cli.err;
  }
}

TEST_F(RecordingTest, ManifestOfAnotherFormatIsNamed) {
  fs::create_directories(dir());
  std::ofstream(fs::path(dir()) / "manifest.json") << R"({"format": "something/2"})";
  const auto cli = test::run_cubecal(words({"analyze", dir()}));
  EXPECT_TRUE(test::one_error_line(cli)) << cli.err;
  EXPECT_NE(cli.err.find("manifest.json"), std::string::npos) << cli.err;
  EXPECT_NE(cli.err.find("cubecal-record/1"), std::string::npos) << cli.err;
}

TEST_F(RecordingTest, CommandsReadTheDirectory) {
  auto& s = segment(1, kStart0, 100.0);
  const auto all = rows(2000, 100.0, 0.0, 100.0, kUtc0, 0.5);
  chunk(s, 1, {all.begin(), all.begin() + 1000});
  chunk(s, 2, {all.begin() + 1000, all.end()});
  finish();
  const std::string d = dir();
  const std::vector<std::string> commands{"dev", "analyze", "psd", "davar", "compare"};
  for (const std::string& name : commands) {
    std::string cmd = name;
    cmd += ' ';
    cmd += d;
    if (name == "compare") (cmd += ' ') += d;
    cmd += " --columns gx";
    if (name != "dev" && name != "davar") cmd += " --unit deg/s";
    const auto r = test::run_cubecal(cmd);
    EXPECT_EQ(r.code, 0) << cmd << ": " << r.err;
    EXPECT_FALSE(r.out.empty()) << cmd;
  }
  // The same numbers as the chunks concatenated into one file.
  const std::string file = write("joined.csv", joined_text(all));
  const auto a = test::run_cubecal(words({"dev", dir(), "--columns gx --format csv"}));
  const auto b = test::run_cubecal(words({"dev", file, "--columns gx --format csv"}));
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
}

}  // namespace
}  // namespace cubecal
