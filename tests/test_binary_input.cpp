// Binary records through the CLI: NumPy .npy arrays (recognised by their
// magic bytes), raw interleaved frames (--binary, --header-bytes) and the
// standard input ("-"). Each gives the same deviations as the same numbers
// written as text, and every damaged file is one error line naming the byte
// offset, exit code 2.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

using cubecal::test::CliRun;
using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;
using cubecal::test::run_cubecal_piped;

// Appends the `bytes` low bytes of `u` in the given order.
void put(std::string& out, std::uint64_t u, std::size_t bytes, bool big_endian) {
  for (std::size_t i = 0; i < bytes; ++i) {
    const std::size_t k = big_endian ? bytes - 1 - i : i;
    out += static_cast<char>((u >> (8 * k)) & 0xff);
  }
}
void put_f64(std::string& out, double v, bool be = false) { put(out, std::bit_cast<std::uint64_t>(v), 8, be); }
void put_f32(std::string& out, float v, bool be = false) { put(out, std::bit_cast<std::uint32_t>(v), 4, be); }
void put_i16(std::string& out, std::int16_t v, bool be = false) { put(out, static_cast<std::uint16_t>(v), 2, be); }

// A .npy file as numpy.save writes it: magic, version, header length, the
// header dict padded with spaces to a multiple of 64 bytes and ended by a
// newline, then the data.
std::string npy(const std::string& descr, bool fortran, const std::string& shape, const std::string& data,
                int major = 1) {
  std::string dict =
      "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': " + shape + ", }";
  const std::size_t preamble = major == 1 ? 10 : 12;
  const std::size_t unpadded = preamble + dict.size() + 1;
  dict += std::string((64 - unpadded % 64) % 64, ' ') + "\n";
  std::string out("\x93NUMPY", 6);
  out += static_cast<char>(major);
  out += '\0';
  put(out, dict.size(), major == 1 ? 2 : 4, false);
  return out + dict + data;
}

// Deterministic values of both signs and many magnitudes.
double value(std::size_t row, std::size_t col) {
  return std::sin(0.37 * static_cast<double>(row) + static_cast<double>(col)) * (1.0 + static_cast<double>(col)) +
         1e-3 * static_cast<double>((row * 7919 + col * 104729) % 1000);
}

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// The same numbers as headerless CSV (columns col1..colN as well).
std::string csv(const std::vector<std::vector<double>>& rows) {
  std::string s;
  for (const auto& r : rows) {
    for (std::size_t c = 0; c < r.size(); ++c) {
      if (c != 0) s += ',';
      s += number(r[c]);
    }
    s += "\n";
  }
  return s;
}

constexpr std::size_t kRows = 400;

class BinaryInput : public cubecal::test::TempDirTest {
 protected:
  std::string write_bytes(const std::string& name, const std::string& bytes) {
    const std::string p = path(name);
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  // The deviations of `file` (and the run), for comparison with text.
  std::string dev(const std::string& file, const std::string& options = "--rate 100") {
    const CliRun r = run_cubecal("dev " + file + " " + options + " --format csv");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(r.out.empty());
    return r.out;
  }
  void expect_error(const std::string& args, const std::vector<std::string>& says) {
    const CliRun r = run_cubecal(args);
    SCOPED_TRACE(args + " -> " + r.err);
    EXPECT_TRUE(one_error_line(r));
    for (const auto& s : says) EXPECT_NE(r.err.find(s), std::string::npos) << "missing: " << s;
  }
};

TEST_F(BinaryInput, NpyTwoDimensionalFloat64MatchesText) {
  std::vector<std::vector<double>> rows(kRows, std::vector<double>(3));
  std::string c_order, f_order;
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t c = 0; c < 3; ++c) put_f64(c_order, rows[r][c] = value(r, c));
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t r = 0; r < kRows; ++r) put_f64(f_order, rows[r][c]);
  const std::string text = dev(write_bytes("imu.csv", csv(rows)));
  EXPECT_NE(text.find("col3"), std::string::npos);
  EXPECT_EQ(dev(write_bytes("c.npy", npy("<f8", false, "(400, 3)", c_order))), text);
  EXPECT_EQ(dev(write_bytes("f.npy", npy("<f8", true, "(400, 3)", f_order))), text);
  EXPECT_EQ(dev(write_bytes("v2.npy", npy("<f8", false, "(400, 3)", c_order, 2))), text);
  EXPECT_EQ(dev(write_bytes("v3.npy", npy("<f8", false, "(400, 3)", c_order, 3))), text);
  // Columns are chosen by index, as in a text file without a header.
  EXPECT_EQ(dev(path("c.npy"), "--rate 100 --columns 2"), dev(path("imu.csv"), "--rate 100 --columns 2"));
}

TEST_F(BinaryInput, NpyOneDimensionalOfEachTypeMatchesText) {
  struct Case {
    std::string descr;
    void (*put)(std::string&, double);
    double (*as_stored)(double);
  };
  const Case cases[] = {
      {">f8", [](std::string& o, double v) { put_f64(o, v, true); }, [](double v) { return v; }},
      {"<f4", [](std::string& o, double v) { put_f32(o, static_cast<float>(v)); },
       [](double v) { return static_cast<double>(static_cast<float>(v)); }},
      {"<i2", [](std::string& o, double v) { put_i16(o, static_cast<std::int16_t>(std::lround(v * 1000))); },
       [](double v) { return static_cast<double>(std::lround(v * 1000)); }},
      {">i2", [](std::string& o, double v) { put_i16(o, static_cast<std::int16_t>(std::lround(v * 1000)), true); },
       [](double v) { return static_cast<double>(std::lround(v * 1000)); }},
      {"<i4", [](std::string& o, double v) { put(o, static_cast<std::uint32_t>(std::lround(v * 1e6)), 4, false); },
       [](double v) { return static_cast<double>(std::lround(v * 1e6)); }},
      {"|u1", [](std::string& o, double v) { put(o, static_cast<std::uint8_t>(std::lround(v * 40 + 128)), 1, false); },
       [](double v) { return static_cast<double>(std::lround(v * 40 + 128)); }},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.descr);
    std::string data;
    std::vector<std::vector<double>> rows;
    for (std::size_t r = 0; r < kRows; ++r) {
      k.put(data, value(r, 0));
      rows.push_back({k.as_stored(value(r, 0))});
    }
    const std::string text = dev(write_bytes("x.csv", csv(rows)));
    EXPECT_EQ(dev(write_bytes("x.npy", npy(k.descr, false, "(400,)", data))), text);
  }
}

// No time axis: the rate is needed, unless a column is named as the time.
TEST_F(BinaryInput, NpyRateOrTimeColumn) {
  std::string data;
  std::vector<std::vector<double>> rows;
  for (std::size_t r = 0; r < kRows; ++r) {
    rows.push_back({static_cast<double>(r) * 0.02, value(r, 1)});
    for (double v : rows.back()) put_f64(data, v);
  }
  const std::string f = write_bytes("t.npy", npy("<f8", false, "(400, 2)", data));
  expect_error("dev " + f, {f + ": no sampling rate", "--rate"});
  EXPECT_EQ(dev(f, "--time-col 1"), dev(write_bytes("t.csv", csv(rows)), "--time-col 1"));
  const CliRun r = run_cubecal("dev " + f + " --time-col 1 --format json");
  EXPECT_NE(r.out.find("\"rate_hz\": 50"), std::string::npos) << r.out.substr(0, 400);
  // The timing checks of text, placed at the row and column of the array.
  std::string gap;
  for (std::size_t row = 0; row < kRows; ++row) {
    put_f64(gap, static_cast<double>(row) * 0.02 + (row >= 200 ? 1.0 : 0.0));
    put_f64(gap, value(row, 1));
  }
  const std::string g = write_bytes("gap.npy", npy("<f8", false, "(400, 2)", gap));
  expect_error("dev " + g + " --time-col 1", {g + ":201:1: gap of 1.020 s (51 periods of 0.02 s) after t = 3.98 s"});
}

TEST_F(BinaryInput, NpyDamageIsLocated) {
  std::string data;
  for (std::size_t r = 0; r < kRows; ++r) put_f64(data, value(r, 0));
  const std::string whole = npy("<f8", false, "(400,)", data);
  const std::size_t data_at = whole.size() - data.size();
  // Cut short by 5 bytes.
  const std::string cut = write_bytes("cut.npy", whole.substr(0, whole.size() - 5));
  expect_error("dev " + cut + " --rate 100",
               {cut + ": NumPy file, byte offset " + std::to_string(whole.size() - 5),
                "5 bytes short of the shape (400,) of <f8", "from byte offset " + std::to_string(data_at)});
  // A complex type, a 3-D shape and a structured type.
  const std::string cplx = write_bytes("c.npy", npy("<c16", false, "(200,)", data));
  expect_error("dev " + cplx + " --rate 100", {"byte offset 10", "data type '<c16' is not supported"});
  const std::string cube = write_bytes("d.npy", npy("<f8", false, "(10, 10, 4)", data));
  expect_error("dev " + cube + " --rate 100", {"shape (10, 10, 4) is not supported"});
  // No rows and a column count no memory holds (found by the binary_reader
  // fuzzer: the reader allocated one entry per declared column).
  const std::string wide = write_bytes("w.npy", npy("<f8", false, "(0, 55555555552555552)", ""));
  expect_error("dev " + wide + " --rate 100", {"shape (0, 55555555552555552) holds no samples"});
  const std::string none = write_bytes("n.npy", npy("<f8", false, "(0, 3)", ""));
  expect_error("dev " + none + " --rate 100", {"shape (0, 3) holds no samples"});
  std::string rec = whole;
  rec.replace(rec.find("'<f8'"), 5, "[('a',");
  const std::string structured = write_bytes("s.npy", rec);
  expect_error("dev " + structured + " --rate 100", {"byte offset 20", "structured type"});
  // A NaN sample.
  std::string nan_data = data;
  std::string nan;
  put_f64(nan, std::numeric_limits<double>::quiet_NaN());
  nan_data.replace(8 * 123, 8, nan);
  const std::string with_nan = write_bytes("nan.npy", npy("<f8", false, "(400,)", nan_data));
  expect_error(
      "dev " + with_nan + " --rate 100",
      {with_nan + ": NaN at byte offset " + std::to_string(data_at + 8 * 123) + " (row 124, column 1)", "--gaps skip"});
}

// --gaps skip: a NaN sample of a .npy array or of raw frames is a missing
// sample, as an empty field of text. The same record as CSV with empty
// fields, as .npy (C and Fortran order, float64 and float32) and as raw
// float64le / float32le frames with NaN (quiet, negative and signalling)
// gives the same `dev --gaps skip` and `davar --gaps skip` output; without
// --gaps skip the first NaN is refused at its byte offset, row and column,
// naming the option; an infinity is refused with it too.
TEST_F(BinaryInput, NanIsAMissingSampleUnderGapsSkip) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double negative_nan = std::bit_cast<double>(std::uint64_t{0xfff8000000000000});
  const double signalling_nan = std::bit_cast<double>(std::uint64_t{0x7ff0000000000001});
  std::vector<std::vector<double>> rows(kRows, std::vector<double>(2));
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t c = 0; c < 2; ++c) rows[r][c] = value(r, c);
  rows[5][0] = nan;
  rows[6][0] = negative_nan;
  rows[123][1] = signalling_nan;
  for (std::size_t r = 200; r < 210; ++r) rows[r][0] = nan;
  rows[399][1] = nan;
  // Text: headerless CSV (columns col1, col2 as in binary), empty fields.
  const auto text_of = [](const std::vector<std::vector<double>>& rs) {
    std::string t;
    for (const auto& r : rs)
      t += (std::isnan(r[0]) ? "" : number(r[0])) + "," + (std::isnan(r[1]) ? "" : number(r[1])) + "\n";
    return t;
  };
  std::string c_order, f_order, raw64 = std::string(16, '\x55'), raw32, npy32;
  std::vector<std::vector<double>> rows32 = rows;
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t c = 0; c < 2; ++c) {
      put_f64(c_order, rows[r][c]);
      put_f64(raw64, rows[r][c]);
      const auto f = static_cast<float>(rows[r][c]);
      put_f32(raw32, f);
      put_f32(npy32, f);
      rows32[r][c] = static_cast<double>(f);
    }
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t r = 0; r < kRows; ++r) put_f64(f_order, rows[r][c]);
  const std::string skip = " --rate 100 --gaps skip --format csv";
  const std::string davar = " --window 100 --step 50 --taus octave";
  const auto run_ok = [&](const std::string& args) {
    const CliRun r = run_cubecal(args);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("14 missing sample(s)"), std::string::npos) << args << "\n" << r.err;
    return r.out;
  };
  const std::string text = write_bytes("holes.csv", text_of(rows));
  const std::string text32 = write_bytes("holes32.csv", text_of(rows32));
  const std::string dev_text = run_ok("dev " + text + skip), davar_text = run_ok("davar " + text + skip + davar);
  const std::string dev_text32 = run_ok("dev " + text32 + skip);
  const std::string davar_text32 = run_ok("davar " + text32 + skip + davar);
  ASSERT_NE(dev_text.find("col2"), std::string::npos);
  struct Binary {
    std::string file, options;
    bool single;
  };
  const Binary binaries[] = {
      {write_bytes("c.npy", npy("<f8", false, "(400, 2)", c_order)), "", false},
      {write_bytes("f.npy", npy("<f8", true, "(400, 2)", f_order)), "", false},
      {write_bytes("c32.npy", npy("<f4", false, "(400, 2)", npy32)), "", true},
      {write_bytes("x.bin", raw64), " --binary float64le,float64le --header-bytes 16", false},
      {write_bytes("x32.bin", raw32), " --binary float32le,float32le", true},
  };
  for (const Binary& b : binaries) {
    SCOPED_TRACE(b.file);
    EXPECT_EQ(run_ok("dev " + b.file + b.options + skip), b.single ? dev_text32 : dev_text);
    EXPECT_EQ(run_ok("davar " + b.file + b.options + skip + davar), b.single ? davar_text32 : davar_text);
  }
  // Without --gaps skip: the first NaN (row 6, column 1) at its byte offset.
  const std::size_t npy_data_at = npy("<f8", false, "(400, 2)", "").size();
  expect_error(
      "dev " + binaries[0].file + " --rate 100",
      {binaries[0].file + ": NaN at byte offset " + std::to_string(npy_data_at + 16 * 5) + " (row 6, column 1)",
       "--gaps skip"});
  expect_error("davar " + binaries[1].file + " --rate 100",
               {"NaN at byte offset " + std::to_string(npy_data_at + 8 * 5) + " (row 6, column 1)", "--gaps skip"});
  // Raw frames: columns are checked in order, so column 1's NaN at row 6.
  expect_error("dev " + binaries[3].file + " --rate 100 --binary float64le,float64le --header-bytes 16",
               {"NaN at byte offset " + std::to_string(16 + 16 * 5) + " (row 6, column 1)", "--gaps skip"});
  // A signalling NaN of column 2 alone, at row 124: 4 bytes into the frame.
  std::string only = raw32;
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t c = 0; c < 2; ++c)
      if (!(r == 123 && c == 1)) {
        std::string v;
        put_f32(v, static_cast<float>(value(r, c)));
        only.replace(8 * r + 4 * c, 4, v);
      }
  expect_error("dev " + write_bytes("one.bin", only) + " --rate 100 --binary float32le,float32le",
               {"NaN at byte offset " + std::to_string(8 * 123 + 4) + " (row 124, column 2)", "--gaps skip"});
  // An infinity is never a missing sample.
  std::string inf = c_order;
  std::string one;
  put_f64(one, std::numeric_limits<double>::infinity());
  inf.replace(16 * 50 + 8, 8, one);
  const std::string with_inf = write_bytes("inf.npy", npy("<f8", false, "(400, 2)", inf));
  expect_error("dev " + with_inf + skip, {with_inf + ": infinite value at byte offset " +
                                          std::to_string(npy_data_at + 16 * 50 + 8) + " (row 51, column 2)"});
}

// Files written by NumPy itself, when this machine's python3 has it.
TEST_F(BinaryInput, NpyWrittenByNumpy) {
  if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no numpy for /usr/bin/python3";
  const std::string script =
      write_bytes("w.py",
                  "import numpy as np, sys\n"
                  "a = np.array([[np.sin(0.37*r + c)*(1+c) + 1e-3*((r*7919 + c*104729) % 1000) for c in range(3)] "
                  "for r in range(400)])\n"
                  "np.save(sys.argv[1] + '/c.npy', a)\n"
                  "np.save(sys.argv[1] + '/f.npy', np.asfortranarray(a))\n"
                  "np.save(sys.argv[1] + '/i.npy', (a * 1000).astype('>i2'))\n"
                  "np.savetxt(sys.argv[1] + '/a.csv', a, delimiter=',', fmt='%.17g')\n"
                  "np.savetxt(sys.argv[1] + '/i.csv', (a * 1000).astype('>i2'), delimiter=',', fmt='%d')\n");
  ASSERT_EQ(std::system(("/usr/bin/python3 " + script + " " + dir_.string()).c_str()), 0);
  const std::string text = dev(path("a.csv"));
  EXPECT_EQ(dev(path("c.npy")), text);
  EXPECT_EQ(dev(path("f.npy")), text);
  EXPECT_EQ(dev(path("i.npy")), dev(path("i.csv")));
}

// Three int16le gyro axes and a float32le temperature per frame, after a
// 16-byte header: the same as the numbers as text.
TEST_F(BinaryInput, RawFramesMatchText) {
  std::string le = std::string(16, '\x55'), be;
  std::vector<std::vector<double>> rows;
  for (std::size_t r = 0; r < kRows; ++r) {
    std::vector<double> row;
    for (std::size_t c = 0; c < 3; ++c) {
      const auto v = static_cast<std::int16_t>(std::lround(value(r, c) * 3000));
      put_i16(le, v);
      put_i16(be, v, true);
      row.push_back(v);
    }
    const auto temp = static_cast<float>(20.0 + 0.01 * value(r, 3));
    put_f32(le, temp);
    put_f32(be, temp, true);
    row.push_back(static_cast<double>(temp));
    rows.push_back(row);
  }
  const std::string text = dev(write_bytes("x.csv", csv(rows)));
  EXPECT_EQ(dev(write_bytes("le.bin", le), "--rate 100 --binary int16le,int16le,int16le,float32le --header-bytes 16"),
            text);
  EXPECT_EQ(dev(write_bytes("be.bin", be), "--rate 100 --binary int16be,int16be,int16be,float32be"), text);
  // The same through analyze, with the columns and LSB of a gyro.
  const CliRun a = run_cubecal("analyze " + path("le.bin") +
                               " --rate 100 --binary int16le,int16le,int16le,float32le --header-bytes 16 "
                               "--columns 1,2,3 --lsb 131 --unit deg/s");
  EXPECT_EQ(a.code, 0) << a.err;
}

TEST_F(BinaryInput, RawDamageAndOptionsAreRefused) {
  const std::string f = write_bytes("x.bin", std::string(16 + 10 * 14 + 3, '\x01'));
  expect_error("dev " + f + " --rate 100 --binary int16le,int16le,int16le,float64le --header-bytes 16",
               {f + ": trailing partial frame: 3 bytes at byte offset 156 after 10 whole frames",
                "the frame of 4 channels is 14 bytes"});
  expect_error("dev " + f + " --rate 100 --binary int16le,int12le", {"--binary: unknown sample type 'int12le'"});
  expect_error("dev " + f + " --rate 100 --binary int16", {"--binary: unknown sample type 'int16'"});
  expect_error("dev " + f + " --binary int8", {f + ": no sampling rate", "--rate"});
  expect_error("dev " + f + " --rate 100 --header-bytes 4", {"--header-bytes", "--binary"});
  expect_error("dev " + f + " --rate 100 --binary int8 --header-bytes 1000", {"fewer than the 1000 header bytes"});
  // An empty file: no frames (the fuzzer's first finding).
  const std::string empty = write_bytes("empty.bin", "");
  expect_error("dev " + empty + " --rate 100 --binary int16le", {empty + ": series too short: 0 samples"});
  std::string nan;
  put_f32(nan, std::numeric_limits<float>::infinity());
  const std::string inf = write_bytes("inf.bin", std::string(40, '\0') + nan + std::string(36, '\0'));
  expect_error("dev " + inf + " --rate 100 --binary float32le,float32le",
               {"infinite value at byte offset 40 (row 6, column 1)"});
}

// "-" reads the standard input: text, raw frames, NumPy, through a pipe.
TEST_F(BinaryInput, StandardInput) {
  std::vector<std::vector<double>> rows;
  std::string raw;
  for (std::size_t r = 0; r < kRows; ++r) {
    rows.push_back({value(r, 0), value(r, 1)});
    put_f64(raw, rows.back()[0]);
    put_f64(raw, rows.back()[1]);
  }
  const std::string f = write_bytes("x.csv", csv(rows));
  const std::string text = dev(f);
  for (const std::string cmd : {"dev", "analyze"}) {
    const std::string options = cmd == "dev" ? " --format csv" : " --unit deg/s --format json";
    const CliRun file = run_cubecal(cmd + " " + f + " --rate 100" + options);
    const CliRun piped = run_cubecal_piped("cat " + f, cmd + " - --rate 100" + options);
    EXPECT_EQ(piped.code, 0) << piped.err;
    if (cmd == "dev") {
      EXPECT_EQ(piped.out, file.out);
    }
  }
  const std::string b = write_bytes("x.bin", raw);
  EXPECT_EQ(run_cubecal_piped("cat " + b, "dev - --rate 100 --binary float64le,float64le --format csv").out, text);
  const std::string n = write_bytes("x.npy", npy("<f8", false, "(400, 2)", raw));
  EXPECT_EQ(run_cubecal_piped("cat " + n, "dev - --rate 100 --format csv").out, text);
  // Errors name the standard input.
  const CliRun bad = run_cubecal_piped("printf 'gx\\n1\\nx\\n'", "dev - --rate 100");
  EXPECT_TRUE(one_error_line(bad)) << bad.err;
  EXPECT_EQ(bad.err.rfind("cubecal: error: <stdin>:3:1: ", 0), 0u) << bad.err;
}

// An endless stream of zeros on the standard input is refused from its first
// bytes, not read to the end.
TEST_F(BinaryInput, TwoGigabytesOfZerosOnStandardInput) {
  const CliRun r = run_cubecal_piped("head -c 2G /dev/zero", "dev - --rate 100");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_EQ(r.err.rfind("cubecal: error: <stdin>:1:1: not a text or known binary format", 0), 0u) << r.err;
}

}  // namespace
