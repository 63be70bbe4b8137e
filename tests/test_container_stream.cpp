// Container formats streamed (issue 33, item 4): a ROS 1 bag, an MCAP file,
// a rosbag2 .db3 and bag directory, and an HDF5 file read by SampleStream a
// chunk (or hyperslab) at a time give read_series' values, names and rate;
// `dev --stream` prints what `dev` prints, on the real bags and on files
// written here; a streamed log larger than --memory is read within an
// address-space limit.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <iterator>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/sample_stream.hpp"
#include "cubecal/io/series.hpp"
#include "ros2_bag_writer.hpp"

namespace {

namespace io = cubecal::io;
namespace r2 = cubecal::test::ros2;
using cubecal::test::run_cubecal;

const std::string kData = std::string(CUBECAL_SHARED_DATA) + "/rosbag/";
const std::string kRos1 = kData + "ros1/phidgets_imu_upside_down.bag";
const std::string kMcap = kData + "ros2-mcap/phidgets_imu_upside_down.mcap";
const std::string kDir = kData + "ros2-db3/phidgets_imu_upside_down";
const std::string kDb3 = kDir + "/phidgets_imu_upside_down_0.db3";

// The standard output without the line that says the run was streamed.
std::string without_stream_note(const std::string& out) {
  std::istringstream in(out);
  std::string kept;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("streamed", 0) != 0) kept += line + "\n";
  return kept;
}

// dev read whole and streamed: the same table to the last digit.
void expect_dev_streams(const std::string& file, const std::string& args) {
  const auto mem = run_cubecal("dev " + file + " " + args);
  const auto str = run_cubecal("dev " + file + " " + args + " --stream");
  ASSERT_EQ(mem.code, 0) << mem.err;
  ASSERT_EQ(str.code, 0) << str.err;
  EXPECT_EQ(without_stream_note(str.out), without_stream_note(mem.out)) << file;
  EXPECT_NE(str.out.find("streamed"), std::string::npos);
}

// The streamed samples, names and rate are read_series'.
void expect_same_samples(const std::string& file, const io::SeriesOptions& o) {
  const io::Series s = io::read_series(file, o);
  const auto stream = io::SampleStream::open(file, o);
  EXPECT_EQ(stream->names(), s.names);
  EXPECT_EQ(stream->rate_hz(), s.rate_hz);
  EXPECT_EQ(stream->rate_from_time(), s.rate_from_time);
  std::vector<std::vector<double>> got(s.names.size());
  io::SampleChunk c;
  while (stream->next(c))
    for (std::size_t k = 0; k < got.size(); ++k)
      got[k].insert(got[k].end(), c.channels[k].begin(), c.channels[k].end());
  for (std::size_t k = 0; k < got.size(); ++k) EXPECT_EQ(got[k], s.channels[k]) << file << " " << s.names[k];
}

// --- files written here ----------------------------------------------------

std::string u32(std::uint32_t v) { return r2::u32(v); }
std::string f64(double d) {
  std::uint64_t b = 0;
  std::memcpy(&b, &d, 8);
  return r2::u64(b);
}
std::string field(const std::string& name, const std::string& value) {
  return u32(static_cast<std::uint32_t>(name.size() + 1 + value.size())) + name + "=" + value;
}
std::string ros1_record(const std::string& header, const std::string& data) {
  return u32(static_cast<std::uint32_t>(header.size())) + header + u32(static_cast<std::uint32_t>(data.size())) + data;
}

double gyro(std::size_t i, int k) {
  return std::sin(0.1 * static_cast<double>(i) + k) + 1e-3 * static_cast<double>(i % 7);
}

// n IMU messages at 100 Hz, 500 to a chunk (uncompressed, so that the file
// is as large as what a whole read holds).
std::string ros1_bag(std::size_t n) {
  std::string bag(io::kRos1BagMagic);
  bag += ros1_record(field("op", "\x03") + field("index_pos", std::string(8, '\0')) + field("conn_count", u32(1)) +
                         field("chunk_count", u32(1)),
                     std::string(64, ' '));
  const std::string conn =
      ros1_record(field("op", "\x07") + field("conn", u32(0)) + field("topic", "/imu"),
                  field("topic", "/imu") + field("type", "sensor_msgs/Imu") + field("md5sum", std::string(32, '0')));
  std::string chunk = conn;
  for (std::size_t i = 0; i < n; ++i) {
    const auto sec = static_cast<std::uint32_t>(1000 + i / 100);
    const auto nsec = static_cast<std::uint32_t>(i % 100) * 10000000u;
    std::string m = u32(static_cast<std::uint32_t>(i)) + u32(sec) + u32(nsec) + u32(3) + "imu";
    for (int k = 0; k < 13; ++k) m += f64(0.0);
    for (int k = 0; k < 3; ++k) m += f64(gyro(i, k));
    for (int k = 0; k < 9; ++k) m += f64(0.0);
    for (int k = 0; k < 3; ++k) m += f64(9.81 * (k == 2) + gyro(i, k + 3));
    for (int k = 0; k < 9; ++k) m += f64(0.0);
    chunk += ros1_record(field("op", "\x02") + field("conn", u32(0)) + field("time", u32(sec) + u32(nsec)), m);
    if ((i + 1) % 500 == 0 || i + 1 == n) {
      bag += ros1_record(field("op", "\x05") + field("compression", "none") +
                             field("size", u32(static_cast<std::uint32_t>(chunk.size()))),
                         chunk);
      chunk.clear();
    }
  }
  return bag;
}

std::string imu_cdr(std::size_t i) {
  const double g[3] = {gyro(i, 0), gyro(i, 1), gyro(i, 2)};
  const double a[3] = {gyro(i, 3), gyro(i, 4), 9.81 + gyro(i, 5)};
  return r2::imu_cdr(true, static_cast<std::int32_t>(1000 + i / 100), static_cast<std::uint32_t>(i % 100) * 10000000u,
                     g, a);
}

// n IMU messages at 100 Hz in chunks of 500 ("" or "zstd").
std::string mcap_file(std::size_t n, const std::string& compression) {
  std::string f = r2::kMagic + r2::header_record();
  std::string plain = r2::schema_record(1, "sensor_msgs/msg/Imu") + r2::channel_record(1, 1, "/imu");
  for (std::size_t i = 0; i < n; ++i) {
    plain += r2::message_record(1, static_cast<std::uint32_t>(i), 1000000000000ull + i * 10000000ull, imu_cdr(i));
    if ((i + 1) % 500 == 0 || i + 1 == n) {
      f += r2::chunk_record(plain, compression);
      plain.clear();
    }
  }
  return f + r2::footer();
}

class ContainerStream : public cubecal::test::TempDirTest {
 protected:
  std::string put(const std::string& name, const std::string& bytes) {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  std::string db3(std::size_t n) {
    const std::string p = path("bag.db3");
    r2::Db3Writer w(p);
    w.topic(1, "/imu", "sensor_msgs/msg/Imu");
    w.exec("BEGIN");
    for (std::size_t i = 0; i < n; ++i)
      w.message(1, 1000000000000ll + static_cast<std::int64_t>(i) * 10000000ll, imu_cdr(i));
    w.exec("COMMIT");
    return p;
  }
  // A compound {t, gx, gy, temp} of n rows at 100 Hz, chunked and compressed;
  // with back_at, the stamp of that row two periods back.
  std::string hdf5(std::size_t n, std::size_t back_at = 0) {
    struct Row {
      double t, gx, gy, temp;
    };
    std::vector<Row> rows(n);
    for (std::size_t r = 0; r < n; ++r) rows[r] = {0.01 * static_cast<double>(r), gyro(r, 0), gyro(r, 1), 20.0};
    if (back_at > 0) rows[back_at].t -= 0.02;
    const std::string p = path("imu.h5");
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t type = H5Tcreate(H5T_COMPOUND, sizeof(Row));
    H5Tinsert(type, "t", offsetof(Row, t), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "gx", offsetof(Row, gx), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "gy", offsetof(Row, gy), H5T_NATIVE_DOUBLE);
    H5Tinsert(type, "temp", offsetof(Row, temp), H5T_NATIVE_DOUBLE);
    const hsize_t dims[1] = {n};
    const hsize_t chunk[1] = {1000};
    const hid_t space = H5Screate_simple(1, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk);
    H5Pset_deflate(dcpl, 1);
    const hid_t ds = H5Dcreate2(f, "imu", type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    EXPECT_GE(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()), 0);
    H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Tclose(type);
    H5Fclose(f);
    return p;
  }
};

// A 2-D dataset (col1..col3, no time): hyperslabs of rows and columns.
TEST_F(ContainerStream, TwoDimensionalDatasetStreamsByRows) {
  const std::size_t n = 70000;  // more than one hyperslab
  std::vector<float> v(n * 3);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>(gyro(i / 3, static_cast<int>(i % 3)));
  const std::string p = path("two.h5");
  const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t dims[2] = {n, 3};
  const hid_t space = H5Screate_simple(2, dims, nullptr);
  const hid_t ds = H5Dcreate2(f, "data", H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Dclose(ds);
  H5Sclose(space);
  H5Fclose(f);
  io::SeriesOptions o;
  o.rate_hz = 100;
  o.table.columns = {"3", "1"};
  o.lsb = {2.0, 0.5};
  expect_same_samples(p, o);
  expect_dev_streams(p, "--rate 100 --columns 2");
}

TEST_F(ContainerStream, RealBagsStreamAsTheyAreReadWhole) {
  io::SeriesOptions o;
  o.rate_hz = 250;  // the Phidgets stamps jitter by more than 1 %
  for (const std::string& f : {kRos1, kMcap, kDb3, kDir}) {
    expect_same_samples(f, o);
    expect_dev_streams(f, "--rate 250");
  }
  expect_dev_streams(kMcap, "--rate 250 --columns az,gx --stat adev");
  expect_dev_streams(kRos1, "--rate 250 --topic /imu/data_raw --columns gz,ax --stat hdev");
}

TEST_F(ContainerStream, WrittenLogsStreamWithTheirStampsRate) {
  const std::vector<std::string> files = {put("a.bag", ros1_bag(3000)), put("a.mcap", mcap_file(3000, "zstd")),
                                          db3(3000), hdf5(3000)};
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    expect_same_samples(f, {});
    expect_dev_streams(f, "");
    expect_dev_streams(f, "--stat ohdev");
  }
}

// analyze --stream on a log: the analysis of the same samples streamed from
// a text file (the streamed analysis sums as it goes, as for any input).
TEST_F(ContainerStream, AnalyzeStreamsAnMcapAsItsSamples) {
  io::SeriesOptions o;
  o.rate_hz = 250;
  const io::Series s = io::read_series(kMcap, o);
  std::string csv = "gx,gy,gz,ax,ay,az\n";
  char buf[64];
  for (std::size_t i = 0; i < s.samples(); ++i)
    for (std::size_t c = 0; c < 6; ++c) {
      std::snprintf(buf, sizeof buf, "%.17g%c", s.channels[c][i], c == 5 ? '\n' : ',');
      csv += buf;
    }
  const std::string text = put("same.csv", csv);
  const std::string args = " --rate 250 --unit rad/s,rad/s,rad/s,m/s^2,m/s^2,m/s^2 --stream";
  const auto bag = run_cubecal("analyze " + kMcap + args);
  const auto ref = run_cubecal("analyze " + text + args);
  ASSERT_EQ(bag.code, 0) << bag.err;
  ASSERT_EQ(ref.code, 0) << ref.err;
  const auto body = [](const std::string& out) { return out.substr(out.find('\n')); };  // after the file's name
  EXPECT_EQ(without_stream_note(body(bag.out)), without_stream_note(body(ref.out)));
  EXPECT_NE(bag.out.find("streamed"), std::string::npos);
}

// What a stream cannot take is refused with what to do.
// A rate given beside stamps: they may repeat (coarse clocks) but not go
// back, streamed as read whole (the stream checked nothing with --rate).
TEST_F(ContainerStream, RateGivenStillRefusesStampsThatGoBack) {
  const std::string f = hdf5(3000, 1500);
  for (const std::string mode : {"", " --stream"}) {
    SCOPED_TRACE(mode);
    const auto r = cubecal::test::run_cubecal("dev " + f + " --columns gx --rate 100" + mode);
    EXPECT_TRUE(cubecal::test::one_error_line(r)) << r.code << " " << r.err;
    EXPECT_NE(r.err.find("is before the previous one"), std::string::npos) << r.err;
  }
}

TEST_F(ContainerStream, SeveralTopicsAreReadWhole) {
  const auto r = run_cubecal("dev " + kRos1 + " --rate 250 --topic /imu/data_raw,/imu/mag --stream");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("leave out --stream, or stream one topic at a time"), std::string::npos) << r.err;
}

// A log whose chunks inflate beyond --memory is streamed by itself: the
// budget counts its messages decompressed (8 MB of the 0.7 MB zstd MCAP),
// not the file's size.
TEST_F(ContainerStream, CompressedChunksCountAsTheyInflate) {
  for (const std::string& f : {kMcap, kRos1, kDir}) {
    const auto mem = run_cubecal("dev " + f + " --rate 250");
    const auto auto_streamed = run_cubecal("dev " + f + " --rate 250 --memory 5M");
    ASSERT_EQ(auto_streamed.code, 0) << auto_streamed.err;
    EXPECT_NE(auto_streamed.err.find("more than the memory budget (5 MB, --memory): streaming it in one pass"),
              std::string::npos)
        << f << ": " << auto_streamed.err;
    EXPECT_EQ(without_stream_note(auto_streamed.out), without_stream_note(mem.out)) << f;
  }
}

// A PX4 ULog file is read whole: past --memory with a warning (never an
// automatic stream that fails), refused with --stream.
TEST_F(ContainerStream, ULogIsReadWholeWithAWarning) {
  const std::string ulog = std::string(CUBECAL_SHARED_DATA) + "/px4/sample.ulg";
  const auto whole = run_cubecal("dev " + ulog + " --rate 250");
  const auto past = run_cubecal("dev " + ulog + " --rate 250 --memory 1M");
  ASSERT_EQ(past.code, whole.code) << past.err;
  EXPECT_EQ(past.out, whole.out);
  EXPECT_NE(past.err.find("a PX4 ULog file is read whole, not streamed"), std::string::npos) << past.err;
  EXPECT_EQ(past.err.find("is not read as a stream"), std::string::npos) << past.err;
  const auto streamed = run_cubecal("dev " + ulog + " --rate 250 --stream");
  EXPECT_EQ(streamed.code, 2);
  EXPECT_NE(streamed.err.find("a PX4 ULog file is read whole"), std::string::npos) << streamed.err;
  EXPECT_NE(streamed.err.find("leave out --stream"), std::string::npos) << streamed.err;
}

// A log larger than --memory is streamed by itself, within an address-space
// limit below what reading it whole takes.
TEST_F(ContainerStream, LargerThanTheBudgetStreamsWithinBoundedMemory) {
  const std::string big = put("big.mcap", mcap_file(400000, ""));  // 134 MB
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlim_t limit = rlim_t{160} << 20;
    const rlimit lim{limit, limit};
    ::setrlimit(RLIMIT_AS, &lim);
    const std::string err = path("err.txt");
    std::freopen(err.c_str(), "w", stderr);
    std::freopen("/dev/null", "w", stdout);
    ::execl(CUBECAL_BINARY, CUBECAL_BINARY, "dev", big.c_str(), "--memory", "16M", "--threads", "1",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  std::ifstream e(path("err.txt"));
  const std::string err((std::istreambuf_iterator<char>(e)), {});
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << err;
  EXPECT_NE(err.find("streaming it in one pass"), std::string::npos) << err;
}

}  // namespace
