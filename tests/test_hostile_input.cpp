// Binary and hostile input, through the CLI: an executable, NUL bytes in the
// middle of a log, a 2 GB file of zeros, a 5-byte gzip stream whose trailer
// claims 3 GB, a truncated .gz and a corrupt gzip member are each refused
// with exit code 2 and one printable line naming the file and the place,
// under an address-space limit far below what a trailer-sized allocation
// would take.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/printable_text.hpp"
#include "gzip_text.hpp"

namespace {

using cubecal::test::gzip;
using cubecal::test::TempDirTest;

// Address-space limit of the child: the binary needs a few tens of MB here.
constexpr rlim_t kMemoryLimit = rlim_t{512} << 20;

struct LimitedRun {
  int code = -1;
  std::string err;
};

// Runs cubecal with `args` in a child limited to kMemoryLimit of address space.
LimitedRun run_limited(const std::vector<std::string>& args, const std::string& err_path) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit lim{kMemoryLimit, kMemoryLimit};
    ::setrlimit(RLIMIT_AS, &lim);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(err, 2);
    ::dup2(null, 1);
    std::vector<char*> argv{const_cast<char*>(CUBECAL_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(CUBECAL_BINARY, argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  LimitedRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_path, std::ios::binary);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  return r;
}

// Exactly one line ending in '\n', of printable ASCII and well-formed UTF-8.
bool printable_one_line(const std::string& s) {
  if (s.empty() || s.back() != '\n') return false;
  const std::string line = s.substr(0, s.size() - 1);
  return cubecal::printable_text(line) == line;
}

// A 100 Hz gyro log: t,gx,gy,gz.
std::string gyro_log(std::size_t rows) {
  std::string s = "t,gx,gy,gz\n";
  for (std::size_t i = 0; i < rows; ++i) {
    s += std::to_string(static_cast<double>(i) / 100.0) + "," + std::to_string(0.01 * static_cast<double>(i % 7)) +
         ",-0.02," + std::to_string(0.003 * static_cast<double>(i % 11)) + "\n";
  }
  return s;
}

class HostileInput : public TempDirTest {
 protected:
  std::string write_bytes(const std::string& name, const std::string& bytes) {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

  // Every reading command refuses `file`: exit 2, one printable line that
  // names the file and says each of `says`.
  void expect_refused(const std::string& file, const std::vector<std::string>& says) {
    for (const std::vector<std::string>& cmd : {std::vector<std::string>{"analyze", "--rate", "100", file},
                                                std::vector<std::string>{"dev", "--rate", "100", file}}) {
      const LimitedRun r = run_limited(cmd, path("stderr.txt"));
      SCOPED_TRACE(cmd.front() + ": " + cubecal::printable_text(r.err));
      EXPECT_EQ(r.code, 2);
      EXPECT_TRUE(printable_one_line(r.err));
      EXPECT_EQ(r.err.rfind("cubecal: error: " + file, 0), 0u);
      for (const std::string& s : says) EXPECT_NE(r.err.find(s), std::string::npos) << "missing: " << s;
    }
  }
};

TEST_F(HostileInput, ExecutableIsNamedAsSuch) {
  std::ifstream bin(CUBECAL_BINARY, std::ios::binary);
  std::stringstream ss;
  ss << bin.rdbuf();
  const std::string f = write_bytes("imu_log.csv", ss.str());
  expect_refused(f, {"ELF executable"});
}

// Old Mac line ends: the file read as one line and the error was about its
// first field ("non-numeric field 't'") or a missing sampling rate.
TEST_F(HostileInput, CarriageReturnLineEndsAreNamed) {
  const std::string f = write_bytes("mac.csv", "t,gx\r0,1\r0.01,2\r0.02,3\r");
  expect_refused(f, {f + ":1: ", "lines end in a carriage return alone", "tr '\\r' '\\n'"});
  // CR LF (Windows) is text as usual.
  const std::string w = write_bytes("win.csv", "t,gx\r\n0,1\r\n0.01,2\r\n0.02,3\r\n0.03,4\r\n");
  const cubecal::test::CliRun ok = cubecal::test::run_cubecal("dev " + w + " --format csv");
  EXPECT_EQ(ok.code, 0) << ok.err;
}

TEST_F(HostileInput, NulBytesNearTheStart) {
  const std::string f = write_bytes("imu.csv", std::string("t,gx\n0,1\n0.01,2\n0.02,3\0\0\0\n0.03,4\n", 32));
  expect_refused(f, {f + ":4:7: ", "NUL byte at byte offset 22"});
}

// Past the first bytes the parser meets the NUL bytes on its way: the row
// with them is reported, its bytes are not echoed (nor the escape sequence).
TEST_F(HostileInput, NulBytesDeepInTheFile) {
  std::string log = gyro_log(20000);
  const std::size_t offset = log.size() + 9;
  log += std::string("200.00,1,\0\0\x1b[31m,2\n", 20) + "200.01,1,2,3\n";
  const std::string f = write_bytes("imu.csv", log);
  expect_refused(f, {f + ":20002:10: ", "NUL byte at byte offset " + std::to_string(offset)});
}

// 2 GB of zeros (sparse: no disk used) under a 512 MB address-space limit:
// refused from its first bytes, not mapped.
TEST_F(HostileInput, TwoGigabytesOfZeros) {
  const std::string f = path("log0001.csv");
  const int fd = ::open(f.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, off_t{2} << 30), 0);
  ::close(fd);
  expect_refused(f, {f + ":1:1: ", "not a text or known binary format", "NUL (zero) bytes"});
}

// Binary without a NUL byte at its start: no line break in the whole probe
// (1 MB of 0xff bytes was mapped, parsed as one header line and reported as
// "no data rows").
TEST_F(HostileInput, NoLineBreakIsNotText) {
  const std::string f = write_bytes("log.dat", std::string(std::size_t{1} << 20, '\xff'));
  expect_refused(
      f, {f + ": not a text or known binary format: no line break in its first 65536 bytes", "--binary TYPE,TYPE"});
}

// Lines of bytes that are not UTF-8 (nor mostly ASCII).
TEST_F(HostileInput, MostlyNonUtf8IsNotText) {
  std::string bytes;
  for (int line = 0; line < 200; ++line) bytes += std::string(40, static_cast<char>(0x80 + line % 64)) + "\n";
  const std::string f = write_bytes("log.dat", bytes);
  expect_refused(f, {f + ": not a text or known binary format: mostly bytes that are not text"});
}

// Latin-1 text (a degree sign in the header) is still text.
TEST_F(HostileInput, Latin1HeaderIsText) {
  const std::string f = write_bytes("imu.csv",
                                    "t,gx,temp \xb0"
                                    "C\n0,1,20\n0.01,2,20\n0.02,3,20\n0.03,4,20\n");
  const cubecal::test::CliRun ok = cubecal::test::run_cubecal("dev " + f + " --columns gx --format csv");
  EXPECT_EQ(ok.code, 0) << ok.err;
}

// 1f 8b, then a method byte zlib does not know; read as a trailer, the
// last four bytes claim 3 GB.
TEST_F(HostileInput, FiveByteGzipReservesNothing) {
  const std::string f = write_bytes("x.gz", "\x1f\x8b\x67\x78\xbb");
  expect_refused(f, {"corrupt gzip data at byte offset", "unknown compression method"});
}

// A .gz cut short: its last four bytes, read as a trailer, claim over 2 GB.
TEST_F(HostileInput, TruncatedGzipSaysTruncated) {
  const std::string gz = gzip(gyro_log(20000));
  std::size_t cut = gz.size() / 2;
  while (static_cast<unsigned char>(gz[cut - 1]) < 0x80) --cut;
  const std::string f = write_bytes("imu.csv.gz", gz.substr(0, cut));
  expect_refused(f, {"truncated gzip stream", "at byte offset " + std::to_string(cut)});
}

// Two members, the second damaged (an invalid block type) with a trailer
// claiming 4 GB.
TEST_F(HostileInput, CorruptGzipMemberIsLocated) {
  const std::string first = gzip(gyro_log(100));
  std::string second = gzip("200.00,1,2,3\n200.01,1,2,3\n");
  second[10] = '\x07';  // BFINAL = 1, BTYPE = 3 (reserved)
  for (std::size_t i = second.size() - 4; i < second.size(); ++i) second[i] = '\xff';
  const std::string f = write_bytes("imu.csv.gz", first + second);
  expect_refused(f, {"corrupt gzip data at byte offset " + std::to_string(first.size() + 11), "gzip member 2",
                     "invalid block type"});
}

// `total` bytes of `pattern` repeated, gzip-compressed piece by piece (a
// gzip bomb: its text is never held whole here either).
std::string gzip_repeated(const std::string& pattern, std::size_t total) {
  z_stream zs{};
  if (deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
  std::string piece;
  while (piece.size() < (std::size_t{1} << 20)) piece += pattern;
  piece.resize((std::size_t{1} << 20) / pattern.size() * pattern.size());
  std::string out;
  std::vector<char> buf(std::size_t{1} << 16);
  for (std::size_t done = 0; done < total;) {
    const std::size_t n = std::min(piece.size(), total - done);
    done += n;
    zs.next_in = reinterpret_cast<Bytef*>(piece.data());
    zs.avail_in = static_cast<uInt>(n);
    const int flush = done == total ? Z_FINISH : Z_NO_FLUSH;
    do {
      zs.next_out = reinterpret_cast<Bytef*>(buf.data());
      zs.avail_out = static_cast<uInt>(buf.size());
      deflate(&zs, flush);
      out.append(buf.data(), buf.size() - zs.avail_out);
    } while (zs.avail_out == 0);
  }
  deflateEnd(&zs);
  return out;
}

// A gzip bomb of text (issue 33, item 3): 600 MB of "0\n1\n" in a few
// hundred kB was inflated into memory whatever --memory said (here: past
// the address-space limit). A request that cannot be streamed is refused
// once the text passes --memory, naming --memory and --stream; one that can
// is streamed within the budget; zeros are refused as binary data from
// their start, --stream or not.
TEST_F(HostileInput, GzipBombIsRefusedOrStreamedWithinTheBudget) {
  const std::string bomb = write_bytes("bomb.csv.gz", gzip_repeated("0\n1\n", std::size_t{600} << 20));
  const LimitedRun refused =
      run_limited({"dev", bomb, "--rate", "100", "--stat", "mdev", "--memory", "8M"}, path("stderr.txt"));
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("cubecal: error: " + bomb +
                             ": gzip-compressed text that inflates to more than the "
                             "memory budget"),
            std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("--stream"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--memory"), std::string::npos) << refused.err;

  const std::string small = write_bytes("small.csv.gz", gzip_repeated("0\n1\n", std::size_t{40} << 20));
  const LimitedRun streamed = run_limited({"dev", small, "--rate", "100", "--memory", "8M"}, path("stderr.txt"));
  EXPECT_EQ(streamed.code, 0) << streamed.err;
  EXPECT_NE(streamed.err.find("streaming it in one pass"), std::string::npos) << streamed.err;

  const std::string zeros = write_bytes("zeros.csv.gz", gzip_repeated(std::string(1, '\0'), std::size_t{64} << 20));
  for (const bool stream : {false, true}) {
    std::vector<std::string> cmd{"dev", zeros, "--rate", "100", "--memory", "8M"};
    if (stream) cmd.push_back("--stream");
    const LimitedRun r = run_limited(cmd, path("stderr.txt"));
    SCOPED_TRACE(cubecal::printable_text(r.err));
    EXPECT_EQ(r.code, 2);
    const std::size_t error = r.err.find("cubecal: error: ");
    ASSERT_NE(error, std::string::npos);
    EXPECT_TRUE(printable_one_line(r.err.substr(error)));  // after a note that it is streamed
    EXPECT_EQ(r.err.find(zeros + ":1:1: not a text or known binary format: its first 65536 bytes are all NUL"),
              error + 16);
  }
}

// Library callers get the same printable message from text in memory.
TEST(HostileInputMessage, QuotedBytesAreEscaped) {
  try {
    (void)cubecal::io::parse_table(std::string("gx\n1\n2\x1b[2J\n", 11), "mem.csv");
    FAIL() << "no error";
  } catch (const cubecal::InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\x1b'), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mem.csv:3:2: control byte 0x1b"), std::string::npos) << e.what();
  }
  EXPECT_EQ(cubecal::printable_text(std::string("a\0b\x1b[1m\xff\xc3\xa9\xe2\x82", 12)),
            "a\\x00b\\x1b[1m\\xff\xc3\xa9\\xe2\\x82");
}

}  // namespace
