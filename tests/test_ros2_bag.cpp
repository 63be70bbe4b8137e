// ROS 2 bags (issue 12, item 1): the real Phidgets recording as MCAP (zstd
// chunks) and as a rosbag2 SQLite directory, checked against the same
// recording's ROS 1 bag, against the test's own MCAP walker and CDR decoder
// (ros2_bag_writer.hpp, which shares no code with the readers), and
// rewritten here to reach the uncompressed and LZ4 chunk paths, big-endian
// CDR, a Temperature topic, killed recordings and corrupt bytes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/io/mcap.hpp"
#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/ros2_bag.hpp"
#include "cubecal/io/series.hpp"
#include "ros2_bag_writer.hpp"

namespace {

using cubecal::InputError;
namespace io = cubecal::io;
namespace fs = std::filesystem;
using namespace cubecal::test::ros2;

const std::string kData = std::string(CUBECAL_SHARED_DATA) + "/rosbag/";
const std::string kMcap = kData + "ros2-mcap/phidgets_imu_upside_down.mcap";
const std::string kDb3Dir = kData + "ros2-db3/phidgets_imu_upside_down";
const std::string kDb3 = kDb3Dir + "/phidgets_imu_upside_down_0.db3";
const std::string kRos1 = kData + "ros1/phidgets_imu_upside_down.bag";
constexpr std::size_t kMessages = 13964;

// A temporary directory of the test's own, removed after it.
class Ros2Bag : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cubecal_ros2_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string put(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
  }
  fs::path dir_;
};

io::SeriesOptions imu_options() {
  io::SeriesOptions o;
  o.gaps = io::GapPolicy::split;  // the Phidgets driver stamps with jitter
  o.topics = {"/imu/data_raw"};
  return o;
}

void expect_phidgets_topics(const io::MessageLog& log) {
  ASSERT_EQ(log.topics.size(), 2u);
  EXPECT_EQ(log.topics[0].name, "/imu/data_raw");
  EXPECT_EQ(log.topics[0].type, "sensor_msgs/msg/Imu");
  EXPECT_EQ(log.topics[1].name, "/imu/mag");
  EXPECT_EQ(log.topics[1].type, "sensor_msgs/msg/MagneticField");
  for (const auto& t : log.topics) {
    EXPECT_EQ(t.encoding, "cdr");
    EXPECT_EQ(t.messages, kMessages);
  }
  EXPECT_EQ(log.messages.size(), 2 * kMessages);
}

TEST_F(Ros2Bag, McapTopicsTypesAndCountsAgreeWithItsStatistics) {
  const io::MessageLog log = io::read_mcap(kMcap);
  expect_phidgets_topics(log);
  for (const auto& t : log.topics) EXPECT_EQ(t.counted, std::optional<std::size_t>(kMessages)) << t.name;
  // Every message is in a zstd chunk (the file's only compression).
  for (const auto& m : log.messages) ASSERT_EQ(m.place, io::MessagePlace::chunk);
}

TEST_F(Ros2Bag, Db3FileAndDirectoryTopicsTypesAndCounts) {
  const io::MessageLog file = io::read_db3(kDb3);
  expect_phidgets_topics(file);
  EXPECT_TRUE(file.parts.empty());
  const io::MessageLog dir = io::read_ros2_bag_directory(kDb3Dir);
  expect_phidgets_topics(dir);
  EXPECT_EQ(dir.parts, (std::vector<std::string>{"phidgets_imu_upside_down_0.db3"}));
  EXPECT_EQ(dir.payload, file.payload);
  EXPECT_EQ(dir.where(dir.messages[0]),
            "row " + std::to_string(dir.messages[0].offset) + " of phidgets_imu_upside_down_0.db3's messages table");
}

// The MCAP's messages, read by the test's own walker, are the db3's rows
// byte for byte, and decode by fixed offsets to what the reader gives.
TEST_F(Ros2Bag, McapAndDb3HoldTheSameBytesAndDecodeAsTheTestsOwnDecoder) {
  const std::vector<McapMessage> own = mcap_messages(slurp(kMcap));
  ASSERT_EQ(own.size(), 2 * kMessages);
  const io::MessageLog mcap = io::read_mcap(kMcap);
  const io::MessageLog db3 = io::read_db3(kDb3);
  ASSERT_EQ(mcap.messages.size(), own.size());
  for (std::size_t i = 0; i < own.size(); ++i) {
    const io::LogMessage& m = mcap.messages[i];
    ASSERT_EQ(mcap.data(m), own[i].data) << i;
    ASSERT_EQ(static_cast<std::uint64_t>(m.sec) * 1000000000u + m.nsec, own[i].log_time) << i;
    ASSERT_EQ(db3.data(db3.messages[i]), own[i].data) << i;
    ASSERT_EQ(db3.messages[i].sec, m.sec) << i;
    ASSERT_EQ(db3.messages[i].nsec, m.nsec) << i;
  }
  const io::Series s = io::read_series(kMcap, imu_options());
  std::size_t row = 0;
  for (const McapMessage& m : own) {
    if (m.channel != own[0].channel) continue;
    const ImuFields f = imu_fields(m.data);
    ASSERT_EQ(f.size, m.data.size()) << row;
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(s.channels[static_cast<std::size_t>(k)][row], f.g[k]) << row;
      ASSERT_EQ(s.channels[static_cast<std::size_t>(3 + k)][row], f.a[k]) << row;
    }
    ASSERT_EQ(s.time[row], static_cast<double>(f.sec) + 1e-9 * static_cast<double>(f.nsec)) << row;
    ++row;
  }
  EXPECT_EQ(row, kMessages);
}

// The ROS 2 files were converted from the ROS 1 bag: the same messages,
// values, header stamps and record (log) times.
TEST_F(Ros2Bag, SameSeriesAsTheRos1BagOfTheSameRecording) {
  io::SeriesOptions o = imu_options();
  const io::Series ros1 = io::read_series(kRos1, o);
  for (const std::string& path : {kMcap, kDb3Dir, kDb3}) {
    SCOPED_TRACE(path);
    const io::Series s = io::read_series(path, o);
    ASSERT_EQ(s.names, (std::vector<std::string>{"gx", "gy", "gz", "ax", "ay", "az"}));
    EXPECT_EQ(s.units, (std::vector<std::string>{"rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2", "m/s^2"}));
    ASSERT_EQ(s.samples(), kMessages);
    EXPECT_EQ(s.channels, ros1.channels);
    EXPECT_EQ(s.time, ros1.time);
    EXPECT_EQ(s.rate_hz, ros1.rate_hz);
    EXPECT_EQ(s.segments.size(), ros1.segments.size());
    EXPECT_EQ(s.topics, (std::vector<std::string>{"/imu/data_raw (sensor_msgs/msg/Imu, 13964 messages)"}));
    // First values as decoded by hand from the ROS 1 bag (test_ros1_bag.cpp).
    EXPECT_EQ(s.channels[1][0], 0.000351509311351658);
    EXPECT_EQ(s.channels[5][0], -9.869743322172164);
    EXPECT_EQ(s.time[0], 1360242236.0 + 1e-9 * 211312933.0);
    // read_series keeps nine significant digits of 1 / median interval.
    EXPECT_NEAR(s.rate_hz, 250.00321869225726, 5e-9 * 250.0);
  }
  o.time_col = "record";
  for (const std::string& path : {kMcap, kDb3}) {
    const io::Series s = io::read_series(path, o);
    EXPECT_EQ(s.time_name, "/imu/data_raw record time");
    EXPECT_NE(s.time, ros1.time) << path;  // the log time is not the header stamp
  }
}

// The log (record) times are the ROS 1 bag's, as the converter wrote them:
// through double seconds (one unit in the last place at 1.36e9 s is 238 ns)
// and double nanoseconds (256 ns apart), so within a few hundred ns.
TEST_F(Ros2Bag, LogTimesAreTheRos1RecordTimesRoundedThroughDoubles) {
  const io::MessageLog ros1 = io::message_log(io::read_ros1_bag(kRos1));
  const auto of_topic = [](const io::MessageLog& log, std::uint32_t t) {
    std::vector<const io::LogMessage*> v;
    for (const auto& m : log.messages)
      if (m.topic == t) v.push_back(&m);
    return v;
  };
  const auto ns = [](const io::LogMessage& m) { return static_cast<std::int64_t>(m.sec) * 1000000000 + m.nsec; };
  for (const std::string& path : {kMcap, kDb3}) {
    SCOPED_TRACE(path);
    const io::MessageLog log = path == kMcap ? io::read_mcap(kMcap) : io::read_db3(kDb3);
    ASSERT_EQ(log.messages.size(), ros1.messages.size());
    std::size_t exact = 0;
    for (std::uint32_t t = 0; t < 2; ++t) {
      ASSERT_EQ(log.topics[t].name, ros1.topics[t].name);
      const auto a = of_topic(ros1, t), b = of_topic(log, t);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        // header.stamp: after the 4-byte seq in ROS 1, the 4-byte
        // encapsulation header in CDR.
        ASSERT_EQ(log.data(*b[i]).substr(4, 8), ros1.data(*a[i]).substr(4, 8)) << i;
        ASSERT_LE(std::llabs(ns(*b[i]) - ns(*a[i])), 238 + 128) << i;
        exact += ns(*a[i]) == ns(*b[i]) ? 1 : 0;
      }
    }
    EXPECT_LT(exact, log.messages.size() / 10);  // so they are not simply the same numbers
  }
}

// MCAP's ros1 profile: the ROS 1 bag's messages, as they are, in an MCAP
// of message encoding "ros1" and ROS 1 type names read as the bag.
TEST_F(Ros2Bag, McapOfRos1MessagesReadsAsTheRos1Bag) {
  const io::MessageLog bag = io::message_log(io::read_ros1_bag(kRos1));
  std::string out = kMagic + record(0x01, str("ros1") + str("cubecal test"));
  std::string chunk;
  for (std::uint16_t t = 0; t < bag.topics.size(); ++t) {
    chunk += record(0x03, u16(t + 1) + str(bag.topics[t].type) + str("ros1msg") + str(""));
    chunk += channel_record(static_cast<std::uint16_t>(t + 1), static_cast<std::uint16_t>(t + 1), bag.topics[t].name,
                            "ros1");
  }
  for (std::size_t i = 0; i < bag.messages.size(); ++i) {
    const io::LogMessage& m = bag.messages[i];
    chunk += message_record(static_cast<std::uint16_t>(m.topic + 1), static_cast<std::uint32_t>(i),
                            static_cast<std::uint64_t>(m.sec) * 1000000000u + m.nsec, std::string(bag.data(m)));
    if (i % 5000 == 4999 || i + 1 == bag.messages.size()) {
      out += chunk_record(chunk, (i / 5000) % 2 == 0 ? "lz4" : "zstd");
      chunk.clear();
    }
  }
  const std::string path = put("ros1.mcap", out + footer());
  io::SeriesOptions o = imu_options();
  const io::Series s = io::read_series(path, o);
  const io::Series ros1 = io::read_series(kRos1, o);
  EXPECT_EQ(s.channels, ros1.channels);
  EXPECT_EQ(s.time, ros1.time);
  EXPECT_EQ(s.topics, ros1.topics);
  o.time_col = "record";
  EXPECT_EQ(io::read_series(path, o).time, io::read_series(kRos1, o).time);
}

TEST_F(Ros2Bag, NaNMagnetometerSamplesAreCountedAsInTheRos1Bag) {
  io::SeriesOptions o;
  o.rate_hz = 250;
  o.topics = {"/imu/mag"};
  for (const std::string& path : {kMcap, kDb3Dir}) {
    try {
      io::read_series(path, o);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("message 2 of /imu/mag ("), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("NaN, in 6990 of 13964 messages"), std::string::npos) << e.what();
    }
  }
}

TEST_F(Ros2Bag, UncompressedAndLz4ChunksReadAsTheZstdOriginal) {
  const std::string original = slurp(kMcap);
  const io::MessageLog zstd = io::parse_mcap(original, "a.mcap");
  for (const std::string compression : {"", "lz4", "zstd"}) {
    SCOPED_TRACE(compression);
    const std::string rewritten = rewrite_chunks(original, compression);
    if (compression != "zstd") {
      ASSERT_NE(rewritten, original);
    }
    const io::MessageLog b = io::parse_mcap(rewritten, "a.mcap");
    ASSERT_EQ(b.messages.size(), zstd.messages.size());
    EXPECT_EQ(b.payload, zstd.payload);
    for (std::size_t i = 0; i < b.messages.size(); ++i) {
      ASSERT_EQ(b.messages[i].sec, zstd.messages[i].sec);
      ASSERT_EQ(b.messages[i].nsec, zstd.messages[i].nsec);
      ASSERT_EQ(b.messages[i].topic, zstd.messages[i].topic);
      ASSERT_EQ(b.messages[i].place, compression.empty() ? io::MessagePlace::byte : io::MessagePlace::chunk);
    }
    // And through read_series, the same channels.
    const std::string path = put("rewritten.mcap", rewritten);
    EXPECT_EQ(io::read_series(path, imu_options()).channels, io::read_series(kMcap, imu_options()).channels);
  }
}

// A small MCAP of n IMU (/imu) and temperature (/temp) messages at 100 Hz:
// gx = i, az = 9.81 + i / 1000, temp = 20 + i / 100; in chunks of 50
// messages of each topic compressed with `compression` (or, with
// chunks = false, as records of the data section); no summary, footer and
// closing magic when killed.
std::string written_mcap(std::size_t n, const std::string& compression, bool little = true, bool chunks = true,
                         bool killed = false) {
  std::string out = kMagic + header_record();
  std::string pending = schema_record(1, "sensor_msgs/msg/Imu") + schema_record(2, "sensor_msgs/msg/Temperature") +
                        channel_record(1, 1, "/imu") + channel_record(2, 2, "/temp");
  for (std::size_t i = 0; i < n; ++i) {
    const auto sec = static_cast<std::int32_t>(1000 + i / 100);
    const auto nsec = static_cast<std::uint32_t>(i % 100) * 10000000u;
    const std::uint64_t t = static_cast<std::uint64_t>(sec) * 1000000000u + nsec + 5000;
    const double g[3] = {static_cast<double>(i), 0.5, -0.5};
    const double a[3] = {0.1, 0.2, 9.81 + static_cast<double>(i) / 1000.0};
    pending += message_record(1, static_cast<std::uint32_t>(i), t, imu_cdr(little, sec, nsec, g, a));
    pending += message_record(2, static_cast<std::uint32_t>(i), t,
                              temperature_cdr(little, sec, nsec, 20.0 + static_cast<double>(i) / 100.0));
    if ((i + 1) % 50 == 0 || i + 1 == n) {
      out += chunks ? chunk_record(pending, compression) : pending;
      pending.clear();
    }
  }
  return killed ? out : out + footer();
}

TEST_F(Ros2Bag, WrittenMcapBigEndianTemperatureAndKilledRecordings) {
  for (const bool little : {true, false}) {
    for (const std::string compression : {"", "zstd", "lz4"}) {
      for (const bool chunks : {true, false}) {
        for (const bool killed : {false, true}) {
          SCOPED_TRACE(std::to_string(little) + compression + std::to_string(chunks) + std::to_string(killed));
          const std::string path = put("w.mcap", written_mcap(300, compression, little, chunks, killed));
          io::SeriesOptions o;
          o.topics = {"/temp", "/imu"};
          o.table.extra_columns = {"temp"};
          const io::Series s = io::read_series(path, o);
          EXPECT_EQ(s.names, (std::vector<std::string>{"gx", "gy", "gz", "ax", "ay", "az"}));
          ASSERT_EQ(s.extra_names, (std::vector<std::string>{"temp"}));
          ASSERT_EQ(s.samples(), 300u);
          EXPECT_EQ(s.extra[0][7], 20.07);
          EXPECT_EQ(s.channels[0][299], 299.0);
          EXPECT_EQ(s.channels[5][2], 9.81 + 0.002);
          EXPECT_EQ(s.time[1], 1000.0 + 1e-9 * 10000000.0);
          EXPECT_NEAR(s.rate_hz, 100.0, 1e-6);
          o.time_col = "record";
          EXPECT_EQ(io::read_series(path, o).time[1], 1000.0 + 1e-9 * 10005000.0);
        }
      }
    }
  }
}

TEST_F(Ros2Bag, EveryTruncationIsAnInputErrorNamingAByteOrAWholeChunkPrefix) {
  const std::string file = slurp(kMcap);
  const io::MessageLog whole = io::parse_mcap(file, "cut.mcap");
  std::size_t errors = 0, prefixes = 0;
  for (std::size_t cut = 8; cut < file.size(); cut += 997) {
    try {
      const io::MessageLog b = io::parse_mcap(std::string_view(file).substr(0, cut), "cut.mcap");
      // A cut between records leaves a killed recording: the messages of
      // the whole chunks before it.
      ASSERT_LE(b.messages.size(), whole.messages.size());
      EXPECT_EQ(b.payload, whole.payload.substr(0, b.payload.size())) << cut;
      ++prefixes;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("cut.mcap: byte ", 0), 0u) << e.what();
      ++errors;
    }
  }
  EXPECT_GT(errors, 600u);
  (void)prefixes;
  // Cut inside the closing magic.
  EXPECT_THROW(io::parse_mcap(std::string_view(file).substr(0, file.size() - 3), "cut.mcap"), InputError);
}

std::string error_of(const std::string& bytes) {
  try {
    io::parse_mcap(bytes, "bad.mcap");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(Ros2Bag, CorruptLengthsCrcsAndCompressedBytesAreInputErrors) {
  const std::string file = slurp(kMcap);
  const std::vector<McapRecord> records = mcap_records(file, 8);
  const McapRecord& chunk = records[1];
  ASSERT_EQ(chunk.op, 0x06);
  const Chunk k = chunk_of(chunk.content);
  ASSERT_EQ(k.compression, "zstd");
  // A record length past the end.
  std::string bad = file;
  bad.replace(chunk.offset + 1, 8, u64(1ull << 40));
  EXPECT_NE(error_of(bad).find("bad.mcap: byte 80: record (op code 6) of 1099511627776 bytes runs past the end"),
            std::string::npos)
      << error_of(bad);
  // An uncompressed size that is not what the data inflate to.
  bad = file;
  bad.replace(chunk.offset + 9 + 16, 8, u64(k.size + 1));
  EXPECT_NE(error_of(bad).find("byte 80: zstd chunk inflates to " + std::to_string(k.size) +
                               " bytes, its header says " + std::to_string(k.size + 1)),
            std::string::npos)
      << error_of(bad);
  bad = file;
  bad.replace(chunk.offset + 9 + 16, 8, u64(1ull << 62));
  EXPECT_NE(error_of(bad).find("bad.mcap: byte 80: "), std::string::npos) << error_of(bad);
  // A wrong CRC.
  bad = file;
  bad.replace(chunk.offset + 9 + 24, 4, u32(k.crc ^ 1u));
  EXPECT_NE(error_of(bad).find("byte 80: the chunk's CRC does not match"), std::string::npos) << error_of(bad);
  // Compressed bytes flipped here and there.
  for (std::size_t at = 50; at < k.stored.size(); at += 4111) {
    bad = file;
    const std::size_t p = chunk.offset + 9 + 40 + 4 + at;
    bad[p] = static_cast<char>(bad[p] ^ 0x5a);
    EXPECT_EQ(error_of(bad).rfind("bad.mcap: byte 80: ", 0), 0u) << at << ": " << error_of(bad);
  }
  // An unknown compression.
  bad = file;
  bad.replace(chunk.offset + 9 + 32, 4, "zzzz");
  EXPECT_NE(error_of(bad).find("chunk compression 'zzzz' is not none, zstd or lz4"), std::string::npos)
      << error_of(bad);
  // A string length inside a record inside the chunk.
  bad = rewrite_chunks(file, "", [](std::string& plain) {
    if (plain[0] == 0x03) plain.replace(9 + 2, 4, u32(0x7fffffff));
  });
  EXPECT_NE(error_of(bad).find("schema record's name of 2147483647 bytes runs past the record"), std::string::npos)
      << error_of(bad);
  // Unknown op codes are skipped by their length.
  bad = file;
  bad.insert(chunk.offset, record(0x7f, "whatever"));
  EXPECT_EQ(io::parse_mcap(bad, "x.mcap").payload, io::parse_mcap(file, "x.mcap").payload);
}

TEST_F(Ros2Bag, CorruptCdrMessageIsAnInputErrorNamingTheMessageAndField) {
  // The first IMU message's frame_id length made huge, in an uncompressed
  // rewrite: the error gives the message's file offset.
  bool done = false;
  std::vector<std::uint64_t> imu_channels;
  const std::string bad = rewrite_chunks(slurp(kMcap), "", [&](std::string& plain) {
    for (const McapRecord& r : mcap_records(plain, 0)) {
      if (r.op == 0x04 && r.content.substr(4, 4 + 13) == str("/imu/data_raw"))
        imu_channels.push_back(get(r.content, 0, 2));
      if (done || r.op != 0x05 || imu_channels.empty() || get(r.content, 0, 2) != imu_channels.front()) continue;
      plain.replace(r.offset + 9 + 22 + 12, 4, u32(0x7fffffff));
      done = true;
    }
  });
  ASSERT_TRUE(done);
  const std::string path = put("bad.mcap", bad);
  try {
    io::read_series(path, imu_options());
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("message 1 of /imu/data_raw (at byte "), std::string::npos) << what;
    EXPECT_NE(what.find("header.frame_id of 2147483647 bytes runs past the message"), std::string::npos) << what;
    EXPECT_NE(what.find("(byte 12 of its "), std::string::npos) << what;
  }
}

TEST_F(Ros2Bag, CdrDecoderChecksEncapsulationAndLeftOverBytes) {
  const double g[3] = {1, 2, 3}, a[3] = {4, 5, 6};
  Db3Writer w(dir_ / "x.db3");
  w.topic(1, "/imu", "sensor_msgs/msg/Imu");
  std::string msg = imu_cdr(true, 5, 6, g, a);
  msg[1] = 0x07;  // XCDR2: not read
  w.message(1, 1, msg);
  try {
    io::read_series((dir_ / "x.db3").string(), io::SeriesOptions{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("message 1 of /imu (row 1 of the messages table): CDR encapsulation 00 07 "
                                         "is not plain CDR"),
              std::string::npos)
        << e.what();
  }
  Db3Writer w2(dir_ / "y.db3");
  w2.topic(1, "/imu", "sensor_msgs/msg/Imu");
  w2.message(1, 1, imu_cdr(true, 5, 6, g, a) + "xy");
  try {
    io::read_series((dir_ / "y.db3").string(), io::SeriesOptions{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 bytes left over after a sensor_msgs/msg/Imu"), std::string::npos)
        << e.what();
  }
}

// Two .db3 files: read in the order metadata.yaml lists them (b_0 holds
// the first 150 messages, a_1 the next), or without it in name order.
TEST_F(Ros2Bag, DirectoryReadsItsFilesInTheOrderMetadataListsThem) {
  fs::create_directories(dir_ / "bag");
  for (const auto& [name, first] : {std::pair<std::string, int>{"b_0.db3", 0}, {"a_1.db3", 150}}) {
    Db3Writer w(dir_ / "bag" / name);
    w.topic(7, "/imu", "sensor_msgs/msg/Imu");
    for (int i = first; i < first + 150; ++i) {
      const double g[3] = {static_cast<double>(i), 0.5, -0.5}, a[3] = {0.1, 0.2, 9.8};
      w.message(7, 1000000000000LL + i * 10000000LL, imu_cdr(i % 2 == 0, 1000 + i / 100, (i % 100) * 10000000u, g, a));
    }
  }
  put("bag/metadata.yaml",
      "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n  relative_file_paths:\n"
      "    - b_0.db3\n    - a_1.db3\n  duration:\n    nanoseconds: 3000000000\n");
  const std::string bag = (dir_ / "bag").string();
  const io::Series s = io::read_series(bag, io::SeriesOptions{});
  ASSERT_EQ(s.samples(), 300u);
  for (std::size_t i = 0; i < 300; ++i) ASSERT_EQ(s.channels[0][i], static_cast<double>(i));
  EXPECT_NEAR(s.rate_hz, 100.0, 1e-6);
  EXPECT_EQ(s.topics, (std::vector<std::string>{"/imu (sensor_msgs/msg/Imu, 300 messages)"}));
  // Flow style.
  put("bag/metadata.yaml", "rosbag2_bagfile_information:\n  relative_file_paths: [b_0.db3, \"a_1.db3\"]\n");
  EXPECT_EQ(io::read_series(bag, io::SeriesOptions{}).channels, s.channels);
  // Without metadata.yaml: a_1 first, and the stamps go back in time.
  fs::remove(dir_ / "bag" / "metadata.yaml");
  try {
    io::read_series(bag, io::SeriesOptions{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("message 151 of /imu (row 1 of b_0.db3's messages table): time stamp 1000 s "
                                         "is not after the previous one 1002.99 s"),
              std::string::npos)
        << e.what();
  }
  // A file metadata.yaml lists but the directory lacks.
  put("bag/metadata.yaml", "rosbag2_bagfile_information:\n  relative_file_paths:\n  - b_0.db3\n  - c_2.db3\n");
  EXPECT_THROW(io::read_series(bag, io::SeriesOptions{}), InputError);
  // The database files are left as they were: no journal, no lock file.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_ / "bag")) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 3u);
}

TEST_F(Ros2Bag, McapBagDirectoryReadsAsItsFile) {
  fs::create_directories(dir_ / "bag");
  fs::copy_file(kMcap, dir_ / "bag" / "phidgets_0.mcap");
  put("bag/metadata.yaml",
      "rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: mcap\n"
      "  relative_file_paths:\n    - phidgets_0.mcap\n");
  EXPECT_EQ(io::read_series((dir_ / "bag").string(), imu_options()).channels,
            io::read_series(kMcap, imu_options()).channels);
}

TEST_F(Ros2Bag, TruncatedOrCorruptDb3IsAnInputError) {
  const std::string db = slurp(kDb3);
  for (const std::size_t cut : {std::size_t{100}, std::size_t{4096}, db.size() / 3, db.size() - 4096}) {
    const std::string path = put("cut.db3", db.substr(0, cut));
    try {
      io::read_series(path, imu_options());
      ADD_FAILURE() << "no error at " << cut;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    }
  }
  std::string bad = db;
  for (std::size_t p = 8192; p < bad.size(); p += 65536) bad[p] = static_cast<char>(bad[p] ^ 0xff);
  const std::string path = put("bad.db3", bad);
  try {
    io::read_series(path, imu_options());
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
  // Not a rosbag2 database.
  Db3Writer w(dir_ / "other.db3");
  w.exec("DROP TABLE topics");
  EXPECT_THROW(io::read_series((dir_ / "other.db3").string(), io::SeriesOptions{}), InputError);
}

}  // namespace
