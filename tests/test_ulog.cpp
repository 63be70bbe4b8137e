// PX4 ULog (issue 12, item 1): the two real logs in ../shared/data/px4
// (BSD-3, PX4 Pro Drone Autopilot; see LICENSE.md there), checked against an
// independent decoder (tests/ulog_decode.py, Python struct over the
// documented file format), and logs written or damaged here for the paths
// the real ones do not reach: nested types, padding left out, appended
// data, incompatible flags, unknown message types, truncation and corrupt
// sizes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/io/ulog.hpp"

namespace {

using cubecal::InputError;
using cubecal::test::run_cubecal;
namespace io = cubecal::io;

const std::string kDir = std::string(CUBECAL_SHARED_DATA) + "/px4/";
const std::string kSample = kDir + "sample.ulg";
const std::string kSmall = kDir + "sample_log_small.ulg";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// What the independent decoder says of a log.
struct Reference {
  std::vector<std::pair<std::string, std::size_t>> topics;  // in the order added
  std::size_t dropouts = 0, dropped_ms = 0;
  struct Message {
    std::size_t where = 0;  // byte offset (first) or 1-based index (nth)
    std::uint64_t timestamp = 0;
    std::vector<double> values;
  };
  std::map<std::string, Message> first, nth;
  std::map<std::string, double> median_dt_us;
  std::map<std::string, std::size_t> second_offset;
};

Reference decode(const std::string& log) {
  const std::string cmd = "/usr/bin/python3 " + std::string(CUBECAL_TEST_SOURCE_DIR) + "/ulog_decode.py " + log;
  FILE* p = ::popen(cmd.c_str(), "r");
  EXPECT_NE(p, nullptr);
  std::string out;
  char buf[4096];
  for (std::size_t n; p != nullptr && (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  EXPECT_EQ(p != nullptr ? ::pclose(p) : -1, 0) << cmd;
  Reference r;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string tag, label;
    l >> tag >> label;
    if (tag == "topic") {
      std::size_t n = 0;
      l >> n;
      r.topics.emplace_back(label, n);
    } else if (tag == "dropouts") {
      r.dropouts = std::stoul(label);
      l >> r.dropped_ms;
    } else if (tag == "first" || tag == "nth") {
      Reference::Message m;
      l >> m.where >> m.timestamp;
      for (double v; l >> v;) m.values.push_back(v);
      (tag == "first" ? r.first : r.nth)[label] = m;
    } else if (tag == "median_dt") {
      l >> r.median_dt_us[label];
    } else if (tag == "second") {
      l >> r.second_offset[label];
    }
  }
  EXPECT_FALSE(r.topics.empty()) << out;
  return r;
}

io::SeriesOptions split_options() {
  io::SeriesOptions o;
  o.gaps = io::GapPolicy::split;
  return o;
}

// The topics, their message counts and the dropouts of both real logs.
TEST(ULogReal, TopicsCountsAndDropoutsAgreeWithAnIndependentDecoder) {
  for (const auto& file : {kSample, kSmall}) {
    const Reference ref = decode(file);
    const io::ULog log = io::parse_ulog(slurp(file), file);
    ASSERT_EQ(log.topics.size(), ref.topics.size()) << file;
    for (std::size_t i = 0; i < ref.topics.size(); ++i) {
      EXPECT_EQ(log.topics[i].label(), ref.topics[i].first) << file;
      EXPECT_EQ(log.topics[i].messages.size(), ref.topics[i].second) << file << " " << ref.topics[i].first;
    }
    EXPECT_EQ(log.dropouts.size(), ref.dropouts) << file;
    EXPECT_EQ(log.dropped_ms(), ref.dropped_ms) << file;
    EXPECT_GE(ref.dropouts, 1U);  // both logs have some: the count is tested
  }
}

// sensor_combined: gx gy gz ax ay az in rad/s and m/s^2, the first and a
// middle message's values and time stamps, and the rate of the time stamps.
TEST(ULogReal, SensorCombinedValuesTimeAndRate) {
  for (const auto& file : {kSample, kSmall}) {
    const Reference ref = decode(file);
    const io::Series s = io::read_series(file, split_options());
    EXPECT_EQ(s.names, (std::vector<std::string>{"gx", "gy", "gz", "ax", "ay", "az"}));
    EXPECT_EQ(s.units, (std::vector<std::string>{"rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2", "m/s^2"}));
    std::size_t count = 0;
    for (const auto& [label, n] : ref.topics)
      if (label == "sensor_combined") count = n;
    ASSERT_EQ(s.samples(), count) << file;
    const auto& first = ref.first.at("sensor_combined");
    const auto& nth = ref.nth.at("sensor_combined");
    for (std::size_t c = 0; c < 6; ++c) {
      EXPECT_EQ(s.channels[c][0], first.values[c]) << file << " " << s.names[c];
      EXPECT_EQ(s.channels[c][nth.where - 1], nth.values[c]) << file << " " << s.names[c];
    }
    EXPECT_EQ(s.time[0], 1e-6 * static_cast<double>(first.timestamp));
    EXPECT_EQ(s.time[nth.where - 1], 1e-6 * static_cast<double>(nth.timestamp));
    EXPECT_NEAR(s.rate_hz, 1e6 / ref.median_dt_us.at("sensor_combined"), 1e-6 * s.rate_hz) << file;
    EXPECT_TRUE(s.default_topic);
    ASSERT_EQ(s.topics.size(), 1U);
    EXPECT_NE(s.topics[0].find("sensor_combined (" + std::to_string(count) + " messages), " +
                               std::to_string(ref.dropouts) + " dropout"),
              std::string::npos)
        << s.topics[0];
  }
}

// vehicle_magnetometer: gauss converted to tesla (the unit of ROS
// MagneticField, so of the bag path).
TEST(ULogReal, MagnetometerInTesla) {
  const Reference ref = decode(kSmall);
  io::SeriesOptions o = split_options();
  o.topics = {"vehicle_magnetometer"};
  const io::Series s = io::read_series(kSmall, o);
  EXPECT_EQ(s.names, (std::vector<std::string>{"mx", "my", "mz"}));
  EXPECT_EQ(s.units, (std::vector<std::string>{"T", "T", "T"}));
  const auto& first = ref.first.at("vehicle_magnetometer");
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(s.channels[c][0], 1e-4 * first.values[c]);
  EXPECT_NEAR(s.rate_hz, 1e6 / ref.median_dt_us.at("vehicle_magnetometer"), 1e-6 * s.rate_hz);
}

std::string error_of(const std::string& file, const io::SeriesOptions& o) {
  try {
    (void)io::read_series(file, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ULogReal, MissingTopicIsListedWithCounts) {
  io::SeriesOptions o;
  o.topics = {"sensor_gyroscope"};
  const std::string e = error_of(kSmall, o);
  EXPECT_NE(e.find("topic sensor_gyroscope not found; topics are: "), std::string::npos) << e;
  EXPECT_NE(e.find("sensor_combined (1298 messages)"), std::string::npos) << e;
  EXPECT_NE(e.find("sensor_gyro:2 (6 messages)"), std::string::npos) << e;
}

TEST(ULogReal, TopicsOfDifferentRatesAreNotMerged) {
  io::SeriesOptions o = split_options();
  o.topics = {"sensor_combined", "vehicle_magnetometer"};
  const std::string e = error_of(kSmall, o);
  EXPECT_NE(e.find("sensor_combined (1298 messages) at 204.6 Hz and vehicle_magnetometer (319 messages) at 50 Hz"),
            std::string::npos)
      << e;
}

// Instance 1 of a multi-instance topic, with its temperature (left out of
// the default channels, kept when named).
TEST(ULogReal, SecondInstanceWithTemperature) {
  io::SeriesOptions o = split_options();
  o.topics = {"sensor_accel:1"};
  o.min_samples = 2;
  io::Series s = io::read_series(kSmall, o);
  EXPECT_EQ(s.names, (std::vector<std::string>{"ax", "ay", "az"}));
  EXPECT_EQ(s.left_out, (std::vector<std::string>{"temp"}));
  o.table.columns = {"az", "temp"};
  s = io::read_series(kSmall, o);
  EXPECT_EQ(s.units, (std::vector<std::string>{"m/s^2", "degC"}));
  EXPECT_GT(s.channels[1][0], -40.0);
  EXPECT_LT(s.channels[1][0], 85.0);
}

// --- logs damaged here ----------------------------------------------------

std::string expect_byte_error(const std::string& bytes, const std::string& file) {
  try {
    (void)io::parse_ulog(bytes, file);
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(w.rfind(file + ": byte ", 0), 0U) << w;
    return w;
  }
  ADD_FAILURE() << "no error";
  return {};
}

// Every prefix is read or refused with an InputError at a byte offset,
// never a crash; a cut inside a message names that message.
TEST(ULogDamaged, TruncatedAtManyOffsets) {
  const std::string bytes = slurp(kSmall);
  const Reference ref = decode(kSmall);
  std::size_t refused = 0, cuts = 0;
  for (std::size_t cut = 0; cut < bytes.size(); cut += (cut < 4096 ? 1 : 997)) {
    ++cuts;
    try {
      (void)io::parse_ulog(std::string_view(bytes).substr(0, cut), "cut.ulg");
    } catch (const InputError& e) {
      ++refused;
      EXPECT_EQ(std::string(e.what()).rfind("cut.ulg: byte ", 0), 0U) << cut << ": " << e.what();
    }
  }
  EXPECT_GT(refused, cuts * 9 / 10);
  const std::size_t at = ref.first.at("sensor_combined").where;
  const std::string e = expect_byte_error(bytes.substr(0, at + 10), "cut.ulg");
  EXPECT_NE(e.find("byte " + std::to_string(at) + ": message 'D' of "), std::string::npos) << e;
  EXPECT_NE(e.find("runs past the end of the file (7 bytes left)"), std::string::npos) << e;
}

// The message header of a log's message at `at`: its size.
void set_size(std::string& b, std::size_t at, std::uint16_t size) {
  b[at] = static_cast<char>(size & 0xff);
  b[at + 1] = static_cast<char>(size >> 8);
}

TEST(ULogDamaged, CorruptSizesAndFlags) {
  const std::string bytes = slurp(kSmall);
  const Reference ref = decode(kSmall);
  const std::size_t at = ref.first.at("sensor_combined").where;
  // A data message one byte shorter than its format: the bytes after it no
  // longer start a message; whichever check trips, it names a byte.
  std::string shorter = bytes;
  set_size(shorter, at, static_cast<std::uint16_t>(static_cast<unsigned char>(bytes[at]) - 1));
  expect_byte_error(shorter, "short.ulg");
  // A size past the end of the file.
  std::string huge = bytes;
  set_size(huge, at, 0xffff);
  huge.resize(at + 100);
  EXPECT_NE(expect_byte_error(huge, "huge.ulg").find("byte " + std::to_string(at) + ": message 'D' of 65535 bytes"),
            std::string::npos);
  // The 'B' message follows the 16-byte header: an unknown incompatible
  // flag is refused.
  ASSERT_EQ(bytes[18], 'B');
  std::string flagged = bytes;
  flagged[19 + 8] = 0x02;
  const std::string e = expect_byte_error(flagged, "flags.ulg");
  EXPECT_NE(e.find("byte 27: incompatible flag bits 0x02"), std::string::npos) << e;
  // A data message in the middle of the file whose size is corrupted.
  const std::size_t second = ref.second_offset.at("sensor_combined");
  std::string bad = bytes;
  set_size(bad, second, 3);
  expect_byte_error(bad, "bad.ulg");
}

// A message type the reader does not know is skipped by its size.
TEST(ULogDamaged, UnknownMessageTypeIsSkipped) {
  const std::string bytes = slurp(kSample);  // version 0: no 'B' message that must come first
  std::string with = bytes.substr(0, 16) + std::string("\x05\x00Z", 3) + "hello" + bytes.substr(16);
  const io::ULog a = io::parse_ulog(bytes, "a.ulg");
  const io::ULog b = io::parse_ulog(with, "b.ulg");
  EXPECT_EQ(a.skipped_messages, 0U);
  EXPECT_EQ(b.skipped_messages, 1U);
  ASSERT_EQ(a.topics.size(), b.topics.size());
  for (std::size_t i = 0; i < a.topics.size(); ++i) EXPECT_EQ(a.topics[i].messages.size(), b.topics[i].messages.size());
}

// Appended data (the 'B' flag DATA_APPENDED): a message cut where the
// appended data begin is dropped and the reading goes on there.
TEST(ULogDamaged, AppendedDataAreRead) {
  const std::string bytes = slurp(kSmall);
  const Reference ref = decode(kSmall);
  const std::size_t m = ref.second_offset.at("sensor_combined");
  // A message cut short (its header says 200 bytes, 7 follow), then the rest.
  const std::string cut = std::string(
      "\xc8\x00"
      "D"
      "\x01\x00\x00\x00",
      7);
  std::string log = bytes.substr(0, m) + cut + bytes.substr(m);
  expect_byte_error(log, "plain.ulg");  // without the flag: refused, wherever it trips
  log[19 + 8] = 0x01;                   // DATA_APPENDED
  const std::uint64_t offset = m + cut.size();
  for (int k = 0; k < 8; ++k)
    log[19 + 16 + static_cast<std::size_t>(k)] = static_cast<char>((offset >> (8 * k)) & 0xff);
  const io::ULog a = io::parse_ulog(bytes, "a.ulg");
  const io::ULog b = io::parse_ulog(log, "b.ulg");
  EXPECT_TRUE(b.appended_data);
  ASSERT_EQ(a.topics.size(), b.topics.size());
  for (std::size_t i = 0; i < a.topics.size(); ++i) EXPECT_EQ(a.topics[i].messages.size(), b.topics[i].messages.size());
  // An offset past the end of the file is refused.
  for (int k = 0; k < 8; ++k) log[19 + 16 + static_cast<std::size_t>(k)] = k == 3 ? '\x7f' : '\0';
  EXPECT_NE(expect_byte_error(log, "far.ulg").find("appended data offset"), std::string::npos);
}

// --- logs written here ------------------------------------------------------

std::string le(std::uint64_t v, int n) {
  std::string s;
  for (int k = 0; k < n; ++k) s += static_cast<char>((v >> (8 * k)) & 0xff);
  return s;
}
std::string f32(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return le(u, 4);
}
std::string msg(char type, const std::string& body) { return le(body.size(), 2) + type + body; }
std::string ulog_header() { return std::string("ULog\x01\x12\x35\x01", 8) + le(1000, 8); }

// sensor_combined laid out unlike any PX4 version: a nested type before
// the gyro, the fields in another order, trailing padding left out of the
// data. Values are found by name.
// Message `invalid` (0-based) is marked as holding no accelerometer sample.
std::string nested_log(std::size_t n, double rate_hz, std::size_t invalid = SIZE_MAX) {
  std::string s = ulog_header() + msg('B', std::string(40, '\0'));
  s += msg('F', "inner:float[2] a;uint8_t b;uint8_t[3] _padding0;");
  s += msg('F',
           "sensor_combined:uint64_t timestamp;inner[2] pre;float[3] accelerometer_m_s2;"
           "int32_t accelerometer_timestamp_relative;double[3] gyro_rad;uint8_t[5] _padding0;");
  s += msg('I', std::string("\x0e") + "char[3] sys_idpx4");
  s += msg('A', std::string("\x00\x07\x00", 3) + "sensor_combined");
  for (std::size_t i = 0; i < n; ++i) {
    std::string d = le(7, 2) + le(static_cast<std::uint64_t>(1e6 * static_cast<double>(i) / rate_hz), 8);
    d += std::string(24, '\x55');  // pre
    for (int k = 0; k < 3; ++k) d += f32(static_cast<float>(10 * k + i));
    d += le(i == invalid ? 0x7fffffff : 0, 4);
    for (int k = 0; k < 3; ++k) {
      const double g = 0.5 * k - static_cast<double>(i);
      std::uint64_t u;
      std::memcpy(&u, &g, 8);
      d += le(u, 8);
    }
    s += msg('D', d);
    if (i == 2) s += msg('O', le(12, 2)) + msg('L', std::string("\x36") + le(5, 8) + "hi");
  }
  return s;
}

TEST(ULogWritten, FieldsFoundByNameInNestedAndPaddedLayouts) {
  const io::ULog log = io::parse_ulog(nested_log(50, 100), "n.ulg");
  ASSERT_EQ(log.topics.size(), 1U);
  EXPECT_EQ(log.formats[0].size, 12U);
  EXPECT_EQ(log.formats[1].size, 8U + 24 + 12 + 4 + 24 + 5);
  EXPECT_EQ(log.formats[1].logged_size, log.formats[1].size - 5);
  EXPECT_EQ(log.dropouts.size(), 1U);
  EXPECT_EQ(log.logging_messages, 1U);
  EXPECT_EQ(log.info_messages, 1U);
}

class ULogCli : public cubecal::test::TempDirTest {
 protected:
  std::string write_bytes(const std::string& name, const std::string& bytes) {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
};

TEST_F(ULogCli, NestedLayoutValuesReadByName) {
  const std::string f = write_bytes("n.ulg", nested_log(50, 100));
  const io::Series s = io::read_series(f, {});
  ASSERT_EQ(s.samples(), 50U);
  EXPECT_EQ(s.rate_hz, 100.0);
  for (std::size_t i : {0U, 7U, 49U}) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(s.channels[k][i], 0.5 * static_cast<double>(k) - static_cast<double>(i));
      EXPECT_EQ(s.channels[3 + k][i], static_cast<double>(static_cast<float>(10 * k + i)));
    }
  }
}

// sensor_combined.accelerometer_timestamp_relative = INT32_MAX: no
// accelerometer sample in that message. Refused where the accelerometer
// is read, at the message's byte; the gyro channels alone are read.
TEST_F(ULogCli, MessageWithoutAnAccelerometerSample) {
  const std::string log = nested_log(50, 100, 20);
  const std::string f = write_bytes("inv.ulg", log);
  const io::ULog parsed = io::parse_ulog(log, f);
  const std::size_t at = parsed.topics[0].messages[20].offset;
  std::string e;
  try {
    (void)io::read_series(f, {});
  } catch (const InputError& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("byte " + std::to_string(at) +
                   ": message 21 of sensor_combined: accelerometer_m_s2[0] is NaN "
                   "(or the sample is marked invalid), in 1 of 50 messages"),
            std::string::npos)
      << e;
  io::SeriesOptions o;
  o.table.columns = {"gx", "gy", "gz"};
  EXPECT_EQ(io::read_series(f, o).samples(), 50U);
}

TEST_F(ULogCli, FormatProblemsAreRefusedAtTheirByte) {
  const std::string base = ulog_header() + msg('B', std::string(40, '\0'));
  // A nested type nobody defines, and a format that contains itself.
  const std::string unknown = base + msg('F', "sensor_combined:uint64_t timestamp;vector3 gyro;");
  EXPECT_NE(
      expect_byte_error(unknown, "u.ulg").find("byte 59: field gyro of format sensor_combined is of type vector3"),
      std::string::npos);
  const std::string loop = base + msg('F', "a:uint64_t timestamp;b x;") + msg('F', "b:a y;");
  EXPECT_NE(expect_byte_error(loop, "l.ulg").find("contains itself"), std::string::npos);
  // Data for a msg_id never added.
  const std::string orphan = base + msg('F', "t:uint64_t timestamp;") + msg('D', le(3, 2) + le(0, 8));
  EXPECT_NE(expect_byte_error(orphan, "o.ulg").find("msg_id 3, which no 'A' message added"), std::string::npos);
  // A data message longer than its format.
  const std::string longer = base + msg('F', "t:uint64_t timestamp;") + msg('A', std::string("\0\1\0t", 4)) +
                             msg('D', le(1, 2) + le(0, 8) + "x");
  EXPECT_NE(expect_byte_error(longer, "g.ulg").find("holds 9 bytes; its format t has 8"), std::string::npos);
  // A version this reader does not know.
  std::string v2 = base;
  v2[7] = 2;
  EXPECT_NE(expect_byte_error(v2, "v.ulg").find("byte 7: ULog version 2"), std::string::npos);
}

// The CLI: every record command takes a .ulg; errors are one line.
TEST_F(ULogCli, DevOnRealLogs) {
  const Reference ref = decode(kSample);
  auto r = run_cubecal("dev " + kSample);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("sample.ulg: byte " + std::to_string(ref.second_offset.at("sensor_combined")) +
                       ": message 2 of sensor_combined: gap of"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("the logger reports 4 dropouts, 119 ms lost"), std::string::npos) << r.err;

  r = run_cubecal("dev " + kSmall + " --gaps split");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx — oadev"), std::string::npos);
  EXPECT_NE(r.out.find("1298 samples"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("topic sensor_combined (1298 messages), 1 dropout, 30 ms lost"), std::string::npos) << r.err;

  r = run_cubecal("dev " + kSmall + " --gaps split --topic vehicle_magnetometer");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mx — oadev (freq data), 319 samples at 50 Hz"), std::string::npos) << r.out;

  r = run_cubecal("analyze " + kSmall + " --gaps split --topic vehicle_magnetometer --out " + path("mag"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("mx,my,mz T"), std::string::npos) << r.err;

  r = run_cubecal("dev " + kSmall + " --topic sensor_gyroscope");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("topic sensor_gyroscope not found; topics are: actuator_armed (14 messages)"), std::string::npos)
      << r.err;

  r = run_cubecal("dev " + kSmall + " --lsb 2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is a ULog file: its values are in SI units already"), std::string::npos) << r.err;
}

}  // namespace
