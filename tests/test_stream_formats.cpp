// NumPy .npy and gzip-compressed text streamed (issue 33, items 3 and 4): a
// streamed record gives the in-memory deviations (.npy of several types,
// 1-D and 2-D; gzip text of one member and of several, from a file and from
// a pipe), chosen by itself past --memory, with the in-memory reader's
// messages for damaged input.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "gzip_text.hpp"

namespace {

using cubecal::test::CliRun;
using cubecal::test::gzip;
using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;
using cubecal::test::run_cubecal_piped;
using cubecal::test::TempDirTest;

// A random walk plus white noise, `rows` x `cols`.
std::vector<double> walk(std::size_t rows, std::size_t cols, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(rows * cols);
  std::vector<double> bias(cols, 0.0);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      bias[c] += 0.01 * g(rng);
      v[r * cols + c] = 20.0 * g(rng) + bias[c];
    }
  return v;
}

// A .npy (version 1.0) of `values` (row-major) as `descr` ("<f8", "<f4",
// ">i2", "|u1"), shape (rows,) or (rows, cols).
std::string npy(const std::vector<double>& values, std::size_t rows, std::size_t cols, const std::string& descr,
                bool two_d, bool fortran = false) {
  std::string dict = "{'descr': '";
  dict += descr;
  dict += "', 'fortran_order': ";
  dict += fortran ? "True" : "False";
  dict += ", 'shape': (";
  dict += std::to_string(rows);
  dict += two_d ? ", " + std::to_string(cols) + "), }" : std::string(",), }");
  while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(dict.size() & 0xff);
  out += static_cast<char>(dict.size() >> 8);
  out += dict;
  const bool big = descr[0] == '>';
  const auto put = [&](const void* p, std::size_t n) {
    std::string b(static_cast<const char*>(p), n);
    if (big) std::reverse(b.begin(), b.end());
    out += b;
  };
  for (std::size_t k = 0; k < rows * cols; ++k) {
    const std::size_t i = fortran ? (k % rows) * cols + k / rows : k;
    const double x = values[i];
    if (descr.substr(1) == "f8") {
      put(&x, 8);
    } else if (descr.substr(1) == "f4") {
      const auto f = static_cast<float>(x);
      put(&f, 4);
    } else if (descr.substr(1) == "i2") {
      const auto s = static_cast<std::int16_t>(std::lround(x * 100.0));
      put(&s, 2);
    } else {
      const auto u = static_cast<std::uint8_t>(std::lround(std::fabs(x)) % 256);
      put(&u, 1);
    }
  }
  return out;
}

// A 100 Hz log "t,gx,gy" of `rows` rows.
std::string text_log(std::size_t rows) {
  const std::vector<double> v = walk(rows, 2, 11);
  std::string s = "t,gx,gy\n";
  char line[96];
  for (std::size_t i = 0; i < rows; ++i) {
    std::snprintf(line, sizeof line, "%.2f,%.6f,%.6f\n", static_cast<double>(i) / 100.0, v[2 * i], v[2 * i + 1]);
    s += line;
  }
  return s;
}

// The rows of a dev CSV as "column,af,tau,n,dev" (what a stream at stride 1
// equals exactly; the stride column of a stream left out).
std::vector<std::string> points(const std::string& csv) {
  std::vector<std::string> out;
  std::size_t pos = csv.find('\n') + 1;
  while (pos < csv.size()) {
    const std::size_t nl = csv.find('\n', pos);
    std::vector<std::string> f;
    for (std::size_t b = pos;;) {
      const std::size_t comma = csv.find(',', b);
      if (comma == std::string::npos || comma > nl) {
        f.push_back(csv.substr(b, nl - b));
        break;
      }
      f.push_back(csv.substr(b, comma - b));
      b = comma + 1;
    }
    out.push_back(f[0] + "," + f[1] + "," + f[2] + "," + f[3] + "," + f[7]);
    pos = nl + 1;
  }
  return out;
}

class StreamFormats : public TempDirTest {
 protected:
  std::string put(const std::string& name, const std::string& bytes) {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  // dev in memory and streamed (a window above every factor: stride 1)
  // give the same points.
  void expect_streamed_equal(const std::string& file, const std::string& args) {
    const CliRun mem = run_cubecal("dev " + file + " " + args + " --format csv");
    const CliRun st = run_cubecal("dev " + file + " " + args + " --format csv --stream --window 1048576");
    ASSERT_EQ(mem.code, 0) << mem.err;
    ASSERT_EQ(st.code, 0) << st.err;
    EXPECT_EQ(st.out.substr(0, st.out.find('\n')), "column,af,tau,n,alpha,edf,lo,dev,hi,stride");
    const auto a = points(mem.out), b = points(st.out);
    EXPECT_GT(a.size(), 10u);
    EXPECT_EQ(a, b) << file;
  }
};

TEST_F(StreamFormats, NpyStreamEqualsInMemory) {
  const std::size_t rows = 40000;
  const std::vector<double> one = walk(rows, 1, 3), three = walk(rows, 3, 4);
  expect_streamed_equal(put("f8.npy", npy(one, rows, 1, "<f8", false)), "--rate 100");
  expect_streamed_equal(put("f4x3.npy", npy(three, rows, 3, "<f4", true)), "--rate 100");
  expect_streamed_equal(put("i2x3.npy", npy(three, rows, 3, ">i2", true)), "--rate 100 --columns 1,3 --lsb 100");
  expect_streamed_equal(put("u1.npy", npy(one, rows, 1, "|u1", true)), "--rate 100");
  // gzip-compressed .npy: inflated on the way.
  expect_streamed_equal(put("f8.npy.gz", gzip(npy(one, rows, 1, "<f8", false))), "--rate 100");
}

// Past --memory the stream is chosen by itself (it was refused: "a NumPy or
// ROS bag file is not read as a stream").
TEST_F(StreamFormats, NpyBeyondTheBudgetIsStreamed) {
  const std::size_t rows = 300000;
  const std::string f = put("big.npy", npy(walk(rows, 1, 5), rows, 1, "<f4", false));
  const CliRun r = run_cubecal("dev " + f + " --rate 100 --memory 1M --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("streaming it in one pass"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.rfind("column,af,tau,n,alpha,edf,lo,dev,hi,stride\n", 0), 0u) << r.out.substr(0, 80);
}

// A damaged .npy streamed: the in-memory reader's message, in one line.
TEST_F(StreamFormats, DamagedNpyStreamedSaysWhatInMemorySays) {
  const std::size_t rows = 5000;
  const std::string whole = npy(walk(rows, 2, 6), rows, 2, "<f8", true);
  for (const std::string& bytes : {whole.substr(0, whole.size() - 12), whole + std::string(24, '\0')}) {
    const std::string f = put("bad.npy", bytes);
    const CliRun mem = run_cubecal("dev " + f + " --rate 100");
    const CliRun st = run_cubecal("dev " + f + " --rate 100 --stream");
    EXPECT_TRUE(one_error_line(st)) << st.err;
    EXPECT_EQ(st.err, mem.err);
    EXPECT_NE(
        st.err.find(bytes.size() < whole.size() ? "bytes short of the shape (5000, 2)" : "24 bytes after the data"),
        std::string::npos)
        << st.err;
  }
  // Fortran order, 2-D, gzip-compressed: not streamed (its columns lie
  // apart), refused in one line saying what to do.
  const std::string f = put("fortran.npy.gz", gzip(npy(walk(rows, 2, 6), rows, 2, "<f8", true, true)));
  EXPECT_EQ(run_cubecal("dev " + f + " --rate 100").code, 0);
  const CliRun st = run_cubecal("dev " + f + " --rate 100 --stream");
  EXPECT_TRUE(one_error_line(st)) << st.err;
  EXPECT_NE(st.err.find("numpy.ascontiguousarray"), std::string::npos) << st.err;
}

// A 2-D array in Fortran order streams from its file, each column read
// where it lies.
TEST_F(StreamFormats, FortranOrderNpyStreamEqualsInMemory) {
  const std::size_t rows = 30000;
  const std::vector<double> three = walk(rows, 3, 8);
  expect_streamed_equal(put("f8f.npy", npy(three, rows, 3, "<f8", true, true)), "--rate 100");
  expect_streamed_equal(put("i2f.npy", npy(three, rows, 3, "<i2", true, true)), "--rate 100 --columns 3,1");
  const std::string whole = npy(three, rows, 3, "<f4", true, true);
  const std::string f = put("short.npy", whole.substr(0, whole.size() - 8));
  const CliRun mem = run_cubecal("dev " + f + " --rate 100");
  const CliRun st = run_cubecal("dev " + f + " --rate 100 --stream");
  EXPECT_TRUE(one_error_line(st)) << st.err;
  EXPECT_EQ(st.err, mem.err);
}

TEST_F(StreamFormats, GzipTextStreamEqualsInMemory) {
  const std::string text = text_log(60000);
  const std::string plain = put("g.csv", text);
  const std::string one = put("one.csv.gz", gzip(text));
  const std::size_t cut = text.size() / 3;  // members cut in the middle of a line
  const std::string multi = put("multi.csv.gz", gzip(text.substr(0, cut)) + gzip(text.substr(cut, cut)) +
                                                    gzip(std::string()) + gzip(text.substr(2 * cut)));
  expect_streamed_equal(one, "--columns gx,gy");
  expect_streamed_equal(multi, "--columns gx,gy");
  const CliRun mem = run_cubecal("dev " + plain + " --columns gy --format csv");
  const CliRun piped =
      run_cubecal_piped("cat " + multi, "dev - --columns gy --format csv --stream --window 1048576 --memory 4M");
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(points(piped.out), points(mem.out));
}

// A damaged gzip file streamed: the place the in-memory reader names.
TEST_F(StreamFormats, DamagedGzipStreamedSaysWhatInMemorySays) {
  const std::string first = gzip(text_log(300));
  std::string second = gzip("200.00,1,2\n200.01,1,2\n");
  second[10] = '\x07';  // BFINAL = 1, BTYPE = 3 (reserved)
  const std::string gz = gzip(text_log(20000));
  std::size_t cut = gz.size() / 2;
  while (static_cast<unsigned char>(gz[cut - 1]) < 0x80) --cut;
  for (const std::string& bytes : {first + second, gz.substr(0, cut)}) {
    const std::string f = put("bad.csv.gz", bytes);
    const CliRun mem = run_cubecal("dev " + f);
    const CliRun st = run_cubecal("dev " + f + " --stream");
    EXPECT_TRUE(one_error_line(st)) << st.err;
    EXPECT_EQ(st.err, mem.err);
    EXPECT_NE(
        st.err.find(bytes.size() == cut ? "truncated gzip stream: the data end at byte offset " + std::to_string(cut)
                                        : "corrupt gzip data at byte offset " + std::to_string(first.size() + 11) +
                                              ", in gzip member 2"),
        std::string::npos)
        << st.err;
  }
}

// The budget counts a gzip file's text, not its compressed bytes: 8 MB of
// text in 40 kB is streamed under --memory 4M.
TEST_F(StreamFormats, GzipBudgetCountsTheInflatedText) {
  std::string text = "t,gx\n";
  char line[48];
  for (std::size_t i = 0; i < 800000; ++i) {
    std::snprintf(line, sizeof line, "%.2f,%d\n", static_cast<double>(i) / 100.0, static_cast<int>(i % 2));
    text += line;
  }
  const std::string f = put("flat.csv.gz", gzip(text, 9));
  const CliRun r = run_cubecal("dev " + f + " --memory 4M --format csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("streaming it in one pass"), std::string::npos) << r.err;
}

}  // namespace
