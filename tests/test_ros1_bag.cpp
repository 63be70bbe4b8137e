// ROS 1 bags (issue 12, item 1): the three real recordings in
// ../shared/data/rosbag/ros1, and bags rewritten or written here to reach
// the uncompressed and LZ4 chunk paths, a Temperature topic and corrupt
// bytes.
//
// The first values below were decoded from the raw bytes by a separate
// reader (Python: struct + bz2 over the record layout of
// wiki.ros.org/Bags/Format/2.0 and the sensor_msgs definitions), not by
// cubecal; the counts and rates agree with ../shared/data/README.md, and the
// counts with the bags' own index records.
#include <bzlib.h>
#include <gtest/gtest.h>
#include <lz4frame.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/series.hpp"

namespace {

using cubecal::InputError;
using cubecal::test::run_cubecal;
namespace io = cubecal::io;

const std::string kDir = std::string(CUBECAL_SHARED_DATA) + "/rosbag/ros1/";
const std::string kPhidgets = kDir + "phidgets_imu_upside_down.bag";
const std::string kArdrone = kDir + "ardrone_imu.bag";
const std::string kRazor = kDir + "sparkfun_razor.bag";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// --- a minimal bag writer and rewriter, independent of the reader -------

std::string u32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int k = 0; k < 4; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((v >> (8 * k)) & 0xff);
  return s;
}
std::uint32_t get32(const std::string& s, std::size_t p) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(s[p + static_cast<std::size_t>(k)]);
  return v;
}
std::string f64(double d) {
  std::uint64_t v;
  std::memcpy(&v, &d, 8);
  std::string s(8, '\0');
  for (int k = 0; k < 8; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((v >> (8 * k)) & 0xff);
  return s;
}
std::string field(const std::string& name, const std::string& value) {
  return u32(static_cast<std::uint32_t>(name.size() + 1 + value.size())) + name + "=" + value;
}
std::string record(const std::string& header, const std::string& data) {
  return u32(static_cast<std::uint32_t>(header.size())) + header + u32(static_cast<std::uint32_t>(data.size())) + data;
}

struct Rec {
  std::map<std::string, std::string> fields;
  std::string header, data;
  std::size_t offset = 0, data_offset = 0;
};
std::vector<Rec> records(const std::string& b, std::size_t pos) {
  std::vector<Rec> out;
  while (pos < b.size()) {
    Rec r;
    r.offset = pos;
    const std::uint32_t hl = get32(b, pos);
    r.header = b.substr(pos + 4, hl);
    for (std::size_t q = 0; q < hl;) {
      const std::uint32_t l = get32(r.header, q);
      const std::string f = r.header.substr(q + 4, l);
      const auto eq = f.find('=');
      r.fields[f.substr(0, eq)] = f.substr(eq + 1);
      q += 4 + l;
    }
    const std::uint32_t dl = get32(b, pos + 4 + hl);
    r.data_offset = pos + 8 + hl;
    r.data = b.substr(r.data_offset, dl);
    pos = r.data_offset + dl;
    out.push_back(r);
  }
  return out;
}

std::string bunzip(const std::string& data, std::uint32_t size) {
  std::string out(size, '\0');
  unsigned len = size;
  EXPECT_EQ(BZ2_bzBuffToBuffDecompress(out.data(), &len, const_cast<char*>(data.data()),
                                       static_cast<unsigned>(data.size()), 0, 0),
            BZ_OK);
  EXPECT_EQ(len, size);
  return out;
}

std::string lz4_frame(const std::string& data) {
  std::string out(LZ4F_compressFrameBound(data.size(), nullptr), '\0');
  const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), data.data(), data.size(), nullptr);
  EXPECT_FALSE(LZ4F_isError(n));
  out.resize(n);
  return out;
}

// The bag with every chunk's data decompressed and stored again with
// `compression` ("none" or "lz4"); `edit` may change a chunk's plain data.
template <class Edit>
std::string rewrite_chunks(const std::string& bag, const std::string& compression, Edit edit) {
  std::string out = bag.substr(0, 13);
  for (const Rec& r : records(bag, 13)) {
    if (r.fields.at("op") != std::string(1, '\x05')) {
      out += bag.substr(r.offset, r.data_offset + r.data.size() - r.offset);
      continue;
    }
    std::string plain = bunzip(r.data, get32(r.fields.at("size"), 0));
    edit(plain);
    const std::string stored = compression == "lz4" ? lz4_frame(plain) : plain;
    out += record(field("op", "\x05") + field("compression", compression) +
                      field("size", u32(static_cast<std::uint32_t>(plain.size()))),
                  stored);
  }
  return out;
}
std::string rewrite_chunks(const std::string& bag, const std::string& compression) {
  return rewrite_chunks(bag, compression, [](std::string&) {});
}

std::string header_msg(std::uint32_t seq, std::uint32_t sec, std::uint32_t nsec, const std::string& frame) {
  return u32(seq) + u32(sec) + u32(nsec) + u32(static_cast<std::uint32_t>(frame.size())) + frame;
}
std::string imu_msg(std::uint32_t seq, std::uint32_t sec, std::uint32_t nsec, const double g[3], const double a[3]) {
  std::string s = header_msg(seq, sec, nsec, "imu");
  for (int k = 0; k < 4 + 9; ++k) s += f64(0.0);
  for (int k = 0; k < 3; ++k) s += f64(g[k]);
  for (int k = 0; k < 9; ++k) s += f64(0.0);
  for (int k = 0; k < 3; ++k) s += f64(a[k]);
  for (int k = 0; k < 9; ++k) s += f64(0.0);
  return s;
}
std::string temp_msg(std::uint32_t seq, std::uint32_t sec, std::uint32_t nsec, double t) {
  return header_msg(seq, sec, nsec, "imu") + f64(t) + f64(0.0);
}
std::string connection(std::uint32_t id, const std::string& topic, const std::string& type) {
  return record(field("op", "\x07") + field("conn", u32(id)) + field("topic", topic),
                field("topic", topic) + field("type", type) + field("md5sum", std::string(32, '0')) +
                    field("message_definition", ""));
}
std::string message(std::uint32_t id, std::uint32_t sec, std::uint32_t nsec, const std::string& data) {
  return record(field("op", "\x02") + field("conn", u32(id)) + field("time", u32(sec) + u32(nsec)), data);
}

// A bag of n IMU (topic /imu) and temperature (/temp) messages at 100 Hz in
// one uncompressed chunk; gx = i, az = 9.81 + i / 1000, temp = 20 + i / 100.
std::string written_bag(std::size_t n) {
  std::string chunk = connection(0, "/imu", "sensor_msgs/Imu") + connection(1, "/temp", "sensor_msgs/Temperature");
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t sec = 1000 + static_cast<std::uint32_t>(i / 100);
    const std::uint32_t nsec = static_cast<std::uint32_t>(i % 100) * 10000000u;
    const double g[3] = {static_cast<double>(i), 0.5, -0.5};
    const double a[3] = {0.1, 0.2, 9.81 + static_cast<double>(i) / 1000.0};
    chunk += message(0, sec, nsec, imu_msg(static_cast<std::uint32_t>(i), sec, nsec, g, a));
    chunk += message(1, sec, nsec,
                     temp_msg(static_cast<std::uint32_t>(i), sec, nsec, 20.0 + static_cast<double>(i) / 100.0));
  }
  std::string bag(io::kRos1BagMagic);
  bag += record(field("op", "\x03") + field("index_pos", std::string(8, '\0')) + field("conn_count", u32(2)) +
                    field("chunk_count", u32(1)),
                std::string(64, ' '));
  bag += record(
      field("op", "\x05") + field("compression", "none") + field("size", u32(static_cast<std::uint32_t>(chunk.size()))),
      chunk);
  return bag;
}

// --- the real bags ------------------------------------------------------

struct Expected {
  std::string file, imu, mag;
  std::size_t messages;
  double rate;
  std::uint32_t sec, nsec;
  double g[3], a[3], m[3];
};

const Expected kBags[] = {
    {kPhidgets,
     "/imu/data_raw",
     "/imu/mag",
     13964,
     250.00321869225726,
     1360242236,
     211312933,
     {0.0, 0.000351509311351658, 0.004450415059660341},
     {-0.202086008644104, -0.10555560451507569, -9.869743322172164},
     {3.6360000000000004e-06, 1.4241000000000001e-05, 3.4542e-05}},
    {kArdrone,
     "/ardrone/imu",
     "/ardrone/mag",
     4308,
     49.99110856843184,
     1352907204,
     593772365,
     {0.0009021772812690954, 0.00018132710156529633, 0.0004190723536248893},
     {0.11456839870661498, 0.11541380174458028, 9.681935966014862},
     {-4.614481946075264e-05, -8.809465533416413e-05, 1.0487458968352874e-05}},
    {kRazor,
     "/imu/data_raw",
     "/imu/mag",
     2144,
     68.9512411638994,
     1352907614,
     798383951,
     {-0.15055361895464128, -0.2501132701988396, 0.2598264069055906},
     {9.20625, 4.181171875, -0.61375},
     {-4.9347701270403665e-05, -6.37033961854302e-05, -5.92172415244844e-05}},
};

TEST(Ros1Bag, TopicsTypesAndCountsAgreeWithTheIndex) {
  for (const auto& e : kBags) {
    SCOPED_TRACE(e.file);
    const io::Ros1Bag bag = io::read_ros1_bag(e.file);
    ASSERT_EQ(bag.connections.size(), 2u);
    EXPECT_EQ(bag.connections[0].topic, e.imu);
    EXPECT_EQ(bag.connections[0].type, "sensor_msgs/Imu");
    EXPECT_EQ(bag.connections[0].md5sum, "6a62c6daae103f4ff57a132d6f95cec2");
    EXPECT_EQ(bag.connections[1].topic, e.mag);
    EXPECT_EQ(bag.connections[1].type, "sensor_msgs/MagneticField");
    for (const auto& c : bag.connections) {
      EXPECT_EQ(c.messages, e.messages);
      EXPECT_EQ(c.indexed, c.messages);
    }
    EXPECT_EQ(bag.messages.size(), 2 * e.messages);
  }
}

TEST(Ros1Bag, FirstValuesRateAndUnitsOfEachBag) {
  for (const auto& e : kBags) {
    SCOPED_TRACE(e.file);
    io::SeriesOptions o;
    o.gaps = io::GapPolicy::split;  // every one of these recordings has jitter
    o.topics = {e.imu};
    const io::Series s = io::read_series(e.file, o);
    ASSERT_EQ(s.names, (std::vector<std::string>{"gx", "gy", "gz", "ax", "ay", "az"}));
    EXPECT_EQ(s.units, (std::vector<std::string>{"rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2", "m/s^2"}));
    ASSERT_EQ(s.samples(), e.messages);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(s.channels[static_cast<std::size_t>(k)][0], e.g[k]);
      EXPECT_EQ(s.channels[static_cast<std::size_t>(3 + k)][0], e.a[k]);
    }
    EXPECT_EQ(s.time[0], static_cast<double>(e.sec) + 1e-9 * static_cast<double>(e.nsec));
    // read_series keeps nine significant digits of 1 / median interval.
    EXPECT_NEAR(s.rate_hz, e.rate, 5e-9 * e.rate);
    EXPECT_TRUE(s.rate_from_time);
  }
}

TEST(Ros1Bag, MagneticFieldInTesla) {
  for (const auto& e : kBags) {
    if (e.file == kPhidgets) continue;  // its magnetometer is NaN every other message (below)
    SCOPED_TRACE(e.file);
    io::SeriesOptions o;
    o.gaps = io::GapPolicy::split;
    o.topics = {e.mag, e.imu};
    const io::Series s = io::read_series(e.file, o);
    ASSERT_EQ(s.names.size(), 9u);
    EXPECT_EQ(s.names[6], "mx");
    EXPECT_EQ(s.units[6], "T");
    for (int k = 0; k < 3; ++k) EXPECT_EQ(s.channels[static_cast<std::size_t>(6 + k)][0], e.m[k]);
  }
}

TEST(Ros1Bag, NaNMagnetometerSamplesAreCountedAndRefused) {
  io::SeriesOptions o;
  o.rate_hz = 250;
  o.topics = {"/imu/mag"};
  try {
    io::read_series(kPhidgets, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("message 2 of /imu/mag"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("NaN, in 6990 of 13964 messages"), std::string::npos) << e.what();
  }
}

TEST(Ros1Bag, UncompressedAndLz4ChunksReadAsTheBz2Original) {
  const std::string original = slurp(kRazor);
  const io::Ros1Bag bz2 = io::parse_ros1_bag(original, "razor.bag");
  for (const std::string compression : {"none", "lz4"}) {
    SCOPED_TRACE(compression);
    const std::string rewritten = rewrite_chunks(original, compression);
    ASSERT_NE(rewritten, original);
    const io::Ros1Bag b = io::parse_ros1_bag(rewritten, "razor.bag");
    ASSERT_EQ(b.messages.size(), bz2.messages.size());
    EXPECT_EQ(b.payload, bz2.payload);
    for (std::size_t i = 0; i < b.messages.size(); ++i) {
      EXPECT_EQ(b.messages[i].sec, bz2.messages[i].sec);
      EXPECT_EQ(b.messages[i].nsec, bz2.messages[i].nsec);
      EXPECT_EQ(b.messages[i].connection, bz2.messages[i].connection);
    }
  }
}

TEST(Ros1Bag, EveryTruncationIsAnInputErrorNamingAByte) {
  const std::string bag = slurp(kRazor);
  for (std::size_t cut = 13; cut < bag.size(); cut += 331) {
    try {
      io::parse_ros1_bag(std::string_view(bag).substr(0, cut), "cut.bag");
      // A cut between records can leave a whole bag (the index records
      // follow the chunks): then every chunk's messages must be there.
      const io::Ros1Bag b = io::parse_ros1_bag(std::string_view(bag).substr(0, cut), "cut.bag");
      EXPECT_EQ(b.messages.size(), 2u * 2144u) << "cut at " << cut;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("cut.bag: byte ", 0), 0u) << e.what();
    }
  }
}

TEST(Ros1Bag, CorruptMessageLengthIsAnInputErrorNamingTheField) {
  // The first IMU message's frame_id length made huge.
  bool done = false;
  const std::string bad = rewrite_chunks(slurp(kRazor), "none", [&](std::string& plain) {
    for (const Rec& r : records(plain, 0)) {
      if (done || r.fields.at("op") != std::string(1, '\x02') || get32(r.fields.at("conn"), 0) != 0) continue;
      plain.replace(r.data_offset + 12, 4, u32(0x7fffffff));
      done = true;
    }
  });
  ASSERT_TRUE(done);
  io::SeriesOptions o;
  o.gaps = io::GapPolicy::split;
  try {
    const std::string path =
        std::filesystem::temp_directory_path() / ("cubecal_bad_" + std::to_string(::getpid()) + ".bag");
    std::ofstream(path, std::ios::binary) << bad;
    struct Remove {
      std::string p;
      ~Remove() { std::filesystem::remove(p); }
    } remove{path};
    io::read_series(path, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("message 1 of /imu/data_raw (at byte "), std::string::npos) << what;
    EXPECT_NE(what.find("header.frame_id of 2147483647 bytes runs past the message"), std::string::npos) << what;
  }
}

TEST(Ros1Bag, TemperatureTopicIsAnExtraColumnAndTimeCanBeTheRecordTime) {
  const std::string path =
      std::filesystem::temp_directory_path() / ("cubecal_temp_" + std::to_string(::getpid()) + ".bag");
  std::ofstream(path, std::ios::binary) << written_bag(300);
  struct Remove {
    std::string p;
    ~Remove() { std::filesystem::remove(p); }
  } remove{path};
  io::SeriesOptions o;
  o.topics = {"/temp", "/imu"};
  o.table.extra_columns = {"temp"};
  const io::Series s = io::read_series(path, o);
  EXPECT_EQ(s.names, (std::vector<std::string>{"gx", "gy", "gz", "ax", "ay", "az"}));
  ASSERT_EQ(s.extra_names, (std::vector<std::string>{"temp"}));
  EXPECT_EQ(s.extra[0][7], 20.07);
  EXPECT_EQ(s.channels[0][299], 299.0);
  EXPECT_EQ(s.channels[5][2], 9.81 + 0.002);
  EXPECT_NEAR(s.rate_hz, 100.0, 1e-6);
  // Without --temp-col the temperature is left out of the default channels.
  o.table.extra_columns.clear();
  const io::Series d = io::read_series(path, o);
  EXPECT_EQ(d.left_out, (std::vector<std::string>{"temp"}));
  EXPECT_EQ(d.names.size(), 6u);
  o.time_col = "record";
  EXPECT_EQ(io::read_series(path, o).time_name, "/imu record time");
  o.time_col = "nonsense";
  EXPECT_THROW(io::read_series(path, o), cubecal::UsageError);
}

TEST(Ros1Bag, SeveralImuTopicsAreListedNoneTaken) {
  std::string bag = written_bag(10);
  // A second IMU topic: one more connection record, in a chunk of its own.
  const std::string chunk = connection(5, "/imu2", "sensor_msgs/Imu");
  bag += record(
      field("op", "\x05") + field("compression", "none") + field("size", u32(static_cast<std::uint32_t>(chunk.size()))),
      chunk);
  const std::string path =
      std::filesystem::temp_directory_path() / ("cubecal_two_" + std::to_string(::getpid()) + ".bag");
  std::ofstream(path, std::ios::binary) << bag;
  struct Remove {
    std::string p;
    ~Remove() { std::filesystem::remove(p); }
  } remove{path};
  try {
    io::read_series(path, io::SeriesOptions{});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.text().find("several sensor_msgs/Imu topics: /imu (sensor_msgs/Imu, 10 messages), "
                            "/imu2 (sensor_msgs/Imu, 0 messages) (choose one with {topics} NAME)"),
              std::string::npos)
        << e.what();
  }
}

// --- the command line ---------------------------------------------------

class Ros1BagCli : public cubecal::test::TempDirTest {};

TEST_F(Ros1BagCli, DevReadsTheNamedTopic) {
  const auto r = run_cubecal("dev " + kPhidgets + " --topic /imu/data_raw --rate 250 --columns gx,gy,gz");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx — oadev (freq data), 13964 samples at 250 Hz"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gz — oadev"), std::string::npos);
  EXPECT_EQ(r.out.find("ax — oadev"), std::string::npos);
}

TEST_F(Ros1BagCli, TheOnlyImuTopicIsTakenAndNamed) {
  const auto r = run_cubecal("dev " + kArdrone + " --rate 50");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("topic /ardrone/imu (sensor_msgs/Imu, 4308 messages) (--topic chooses others)"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("az — oadev"), std::string::npos);
}

TEST_F(Ros1BagCli, AnalyzeKnowsTheUnits) {
  const auto r = run_cubecal("analyze " + kRazor + " --gaps split");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("units from the message types: gx,gy,gz rad/s; ax,ay,az m/s^2"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("gx [rad/s, rate]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("az [m/s^2, acceleration]"), std::string::npos) << r.out;
}

TEST_F(Ros1BagCli, AnalyzeTakesTheTemperatureTopicAsTempCol) {
  const std::string path = dir_ / "temp.bag";
  std::ofstream(path, std::ios::binary) << written_bag(3000);
  const auto r = run_cubecal("analyze " + path + " --topic /imu --topic /temp --temp-col temp --columns gx");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx [rad/s, rate]"), std::string::npos) << r.out;
}

TEST_F(Ros1BagCli, CompareTakesEveryRunsUnitsFromTheBag) {
  const auto r = run_cubecal("compare " + kRazor + " " + kArdrone + " --gaps split");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gx"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("units from the message types"), std::string::npos) << r.err;
}

TEST_F(Ros1BagCli, MissingTopicListsTheTopics) {
  const auto r = run_cubecal("dev " + kPhidgets + " --topic /imu/nope");
  EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.code << r.err;
  EXPECT_NE(r.err.find("topic /imu/nope not found; topics are: /imu/data_raw (sensor_msgs/Imu, 13964 messages), "
                       "/imu/mag (sensor_msgs/MagneticField, 13964 messages)"),
            std::string::npos)
      << r.err;
}

TEST_F(Ros1BagCli, TruncatedBagIsOneLineAndExitTwo) {
  const std::string bag = slurp(kPhidgets);
  const std::string path = dir_ / "cut.bag";
  std::ofstream(path, std::ios::binary) << bag.substr(0, bag.size() / 2);
  const auto r = run_cubecal("dev " + path + " --rate 250");
  EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.code << r.err;
  EXPECT_NE(r.err.find(path + ": byte "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the bag is truncated or corrupt"), std::string::npos) << r.err;
}

}  // namespace
