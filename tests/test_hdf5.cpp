// HDF5 datasets (issue 12, item 2): files written here with the HDF5 C API
// (not through the reader): 1-D, 2-D, compound, int16 with per-column LSBs,
// gzip-compressed chunks, a group of 1-D datasets, files holding several
// datasets or none, and truncated or garbage files, which must give one
// InputError line and never the library's error stack.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"

namespace {

using cubecal::InputError;
using cubecal::UsageError;
using cubecal::test::one_error_line;
using cubecal::test::run_cubecal;
using cubecal::test::run_cubecal_piped;
namespace io = cubecal::io;

constexpr std::size_t kRows = 400;

double wave(std::size_t r, std::size_t c) {
  return std::sin(0.37 * static_cast<double>(r) + static_cast<double>(c)) * static_cast<double>(1 + c) +
         1e-3 * static_cast<double>((r * 7919 + c * 104729) % 1000);
}

class Hdf5 : public cubecal::test::TempDirTest {
 protected:
  // Creates dir_/name and lets `fill` write into it.
  std::string h5(const std::string& name, const std::function<void(hid_t)>& fill) {
    const std::string p = path(name);
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(f, 0);
    fill(f);
    H5Fclose(f);
    return p;
  }
  // A dataset of `dims` and file type `type`, written from `values` of
  // memory type `mem`; `dcpl` for chunking and filters.
  static void put(hid_t loc, const char* name, std::vector<hsize_t> dims, hid_t type, hid_t mem, const void* values,
                  hid_t dcpl = H5P_DEFAULT) {
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t ds = H5Dcreate2(loc, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    ASSERT_GE(ds, 0) << name;
    ASSERT_GE(H5Dwrite(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), 0);
    H5Dclose(ds);
    H5Sclose(space);
  }
  static std::vector<double> table(std::size_t cols) {
    std::vector<double> v(kRows * cols);
    for (std::size_t r = 0; r < kRows; ++r)
      for (std::size_t c = 0; c < cols; ++c) v[r * cols + c] = wave(r, c);
    return v;
  }
  static io::SeriesOptions at_rate(double hz) {
    io::SeriesOptions o;
    o.rate_hz = hz;
    return o;
  }
  static std::string error_of(const std::string& file, const io::SeriesOptions& o) {
    try {
      (void)io::read_series(file, o);
    } catch (const InputError& e) {
      return e.what();
    } catch (const UsageError& e) {
      return std::string("usage: ") + e.what();
    }
    return "(no error)";
  }
};

TEST_F(Hdf5, OneDimensionalDatasetIsOneNamedChannel) {
  const std::vector<double> v = table(1);
  const std::string f = h5("a.h5", [&](hid_t loc) {
    const hid_t g = H5Gcreate2(loc, "imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put(g, "gyro_dps", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
    H5Gclose(g);
  });
  const io::Series s = io::read_series(f, at_rate(100));
  ASSERT_EQ(s.names, std::vector<std::string>{"gyro_dps"});
  ASSERT_EQ(s.samples(), kRows);
  for (std::size_t r = 0; r < kRows; ++r) EXPECT_EQ(s.channels[0][r], v[r]);
  EXPECT_EQ(s.rate_hz, 100.0);
}

TEST_F(Hdf5, TwoDimensionalDatasetGivesColumns) {
  const std::vector<double> v = table(3);
  std::vector<float> f32(v.begin(), v.end());
  const std::string f = h5("b.h5", [&](hid_t loc) {
    put(loc, "data", {kRows, 3}, H5T_IEEE_F32BE, H5T_NATIVE_FLOAT, f32.data());
  });
  const io::Series s = io::read_series(f, at_rate(50));
  ASSERT_EQ(s.names, (std::vector<std::string>{"col1", "col2", "col3"}));
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(s.channels[c][r], static_cast<double>(f32[r * 3 + c]));
  io::SeriesOptions o = at_rate(50);
  o.table.columns = {"3", "1"};
  const io::Series picked = io::read_series(f, o);
  EXPECT_EQ(picked.channels[0][7], static_cast<double>(f32[7 * 3 + 2]));
}

// A compound dataset: its numeric members by name, the time column taken
// by its name (t), a string member left out.
TEST_F(Hdf5, CompoundMembersAreNamedColumns) {
  struct Row {
    double t;
    float gx;
    std::int16_t raw;
    char label[4];
  };
  std::vector<Row> rows(kRows);
  for (std::size_t r = 0; r < kRows; ++r)
    rows[r] = {0.01 * static_cast<double>(r), static_cast<float>(wave(r, 0)), static_cast<std::int16_t>(r % 300 - 150),
               "ab"};
  const std::string f = h5("c.h5", [&](hid_t loc) {
    const hid_t str = H5Tcopy(H5T_C_S1);
    H5Tset_size(str, 4);
    const hid_t mem = H5Tcreate(H5T_COMPOUND, sizeof(Row));
    H5Tinsert(mem, "t", offsetof(Row, t), H5T_NATIVE_DOUBLE);
    H5Tinsert(mem, "gx", offsetof(Row, gx), H5T_NATIVE_FLOAT);
    H5Tinsert(mem, "raw", offsetof(Row, raw), H5T_NATIVE_INT16);
    H5Tinsert(mem, "label", offsetof(Row, label), str);
    put(loc, "samples", {kRows}, mem, mem, rows.data());
    H5Tclose(mem);
    H5Tclose(str);
  });
  const io::Series s = io::read_series(f, {});
  ASSERT_EQ(s.names, (std::vector<std::string>{"gx", "raw"}));
  EXPECT_EQ(s.time_name, "t");
  EXPECT_NEAR(s.rate_hz, 100.0, 1e-6);
  for (std::size_t r = 0; r < kRows; r += 37) {
    EXPECT_EQ(s.channels[0][r], static_cast<double>(rows[r].gx));
    EXPECT_EQ(s.channels[1][r], static_cast<double>(rows[r].raw));
  }
}

TEST_F(Hdf5, Int16WithAnLsbPerColumn) {
  std::vector<std::int16_t> counts(kRows * 2);
  for (std::size_t r = 0; r < kRows; ++r) {
    counts[2 * r] = static_cast<std::int16_t>(131.0 * wave(r, 0));
    counts[2 * r + 1] = static_cast<std::int16_t>(16384 + 100.0 * wave(r, 1));
  }
  const std::string f = h5("i.h5", [&](hid_t loc) {
    put(loc, "raw", {kRows, 2}, H5T_STD_I16LE, H5T_NATIVE_INT16, counts.data());
  });
  io::SeriesOptions o = at_rate(100);
  o.lsb = {131, 16384};
  const io::Series s = io::read_series(f, o);
  for (std::size_t r = 0; r < kRows; ++r) {
    EXPECT_EQ(s.channels[0][r], counts[2 * r] / 131.0);
    EXPECT_EQ(s.channels[1][r], counts[2 * r + 1] / 16384.0);
  }
  o.lsb = {131, 16384, 1};
  EXPECT_NE(error_of(f, o).find("3 LSB values for 2 columns"), std::string::npos) << error_of(f, o);
}

// Chunked, gzip-compressed data read through the library: the same values
// as a contiguous copy.
TEST_F(Hdf5, GzipChunkedDataset) {
  const std::vector<double> v = table(3);
  const std::string f = h5("z.h5", [&](hid_t loc) {
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    const hsize_t chunk[2] = {64, 3};
    H5Pset_chunk(dcpl, 2, chunk);
    H5Pset_deflate(dcpl, 6);
    put(loc, "z", {kRows, 3}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), dcpl);
    H5Pclose(dcpl);
  });
  const io::Series s = io::read_series(f, at_rate(10));
  ASSERT_EQ(s.samples(), kRows);
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(s.channels[c][r], v[r * 3 + c]);
}

TEST_F(Hdf5, SeveralDatasetsAreListedAndOneIsChosen) {
  const std::vector<double> v = table(3);
  const std::string f = h5("s.h5", [&](hid_t loc) {
    put(loc, "a", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
    const hid_t g = H5Gcreate2(loc, "imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put(g, "b", {kRows, 3}, H5T_IEEE_F32LE, H5T_NATIVE_DOUBLE, v.data());
    H5Gclose(g);
  });
  const std::string e = error_of(f, at_rate(10));
  EXPECT_NE(e.find("2 numeric datasets: /a (400,) float64; /imu/b (400, 3) float32 (choose one with dataset PATH)"),
            std::string::npos)
      << e;
  io::SeriesOptions o = at_rate(10);
  o.dataset = "/imu/b";
  EXPECT_EQ(io::read_series(f, o).channels.size(), 3U);
  o.dataset = "/imu/nope";
  const std::string missing = error_of(f, o);
  EXPECT_NE(missing.find("dataset /imu/nope not found; datasets are: /a (400,) float64; /imu/b (400, 3) float32"),
            std::string::npos)
      << missing;
}

// A group of equal-length 1-D datasets: a named column each.
TEST_F(Hdf5, GroupOfOneDimensionalDatasets) {
  const std::vector<double> v = table(2);
  std::vector<double> x(kRows), y(kRows);
  for (std::size_t r = 0; r < kRows; ++r) {
    x[r] = v[2 * r];
    y[r] = v[2 * r + 1];
  }
  const std::string f = h5("g.h5", [&](hid_t loc) {
    const hid_t g = H5Gcreate2(loc, "imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put(g, "gy_dps", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, y.data());
    put(g, "gx_dps", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, x.data());
    put(g, "short", {kRows - 1}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, x.data());
    const hid_t g2 = H5Gcreate2(g, "ok", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put(g2, "gy_dps", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, y.data());
    put(g2, "gx_dps", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, x.data());
    H5Gclose(g2);
    H5Gclose(g);
  });
  io::SeriesOptions o = at_rate(10);
  o.dataset = "/imu/ok";
  const io::Series s = io::read_series(f, o);
  ASSERT_EQ(s.names, (std::vector<std::string>{"gx_dps", "gy_dps"}));
  EXPECT_EQ(s.channels[0][5], x[5]);
  EXPECT_EQ(s.channels[1][5], y[5]);
  o.dataset = "/imu";
  const std::string e = error_of(f, o);
  EXPECT_NE(e.find("is a group whose member"), std::string::npos) << e;
}

TEST_F(Hdf5, NaNIsRefusedAtItsRow) {
  std::vector<double> v = table(2);
  v[2 * 123 + 1] = std::nan("");
  const std::string f = h5("n.h5", [&](hid_t loc) {
    put(loc, "d", {kRows, 2}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
  });
  const std::string e = error_of(f, at_rate(10));
  EXPECT_NE(e.find("NaN in dataset /d at row 124, column 2"), std::string::npos) << e;
  // Read for --gaps skip: a missing sample.
  io::SeriesOptions skip = at_rate(10);
  skip.gaps = io::GapPolicy::skip;
  const io::Series s = io::read_series(f, skip);
  EXPECT_TRUE(std::isnan(s.channels[1][123]));
  EXPECT_EQ(s.channels[1][122], v[2 * 122 + 1]);
}

// --gaps skip: a NaN in a dataset is a missing sample, as an empty field of
// text. A 2-D float64 dataset, a group of float32 1-D datasets and a
// compound with a time member (three rows never written, NaN members) give
// the same `dev --gaps skip` and `davar --gaps skip` output as the same
// numbers as CSV with empty fields; without --gaps skip the first NaN is
// refused at its row and column, naming the option; an infinity always.
TEST_F(Hdf5, NaNIsAMissingSampleUnderGapsSkip) {
  const double nan = std::nan("");
  std::vector<double> v = table(2);
  for (const std::size_t r : {10u, 11u, 250u}) v[2 * r] = nan;
  for (const std::size_t r : {123u, 399u}) v[2 * r + 1] = nan;
  std::vector<float> gx(kRows), gy(kRows);
  for (std::size_t r = 0; r < kRows; ++r) {
    gx[r] = static_cast<float>(v[2 * r]);
    gy[r] = static_cast<float>(v[2 * r + 1]);
  }
  struct Row {
    double t;
    float gx;
  };
  std::vector<Row> rows;
  for (std::size_t r = 0; r < kRows; ++r)
    if (r < 300 || r > 302) rows.push_back({0.1 * static_cast<double>(r), gx[r]});
  const std::string d2 = h5("d2.h5", [&](hid_t loc) {
    put(loc, "d", {kRows, 2}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
  });
  const std::string group = h5("g.h5", [&](hid_t loc) {
    const hid_t g = H5Gcreate2(loc, "imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    put(g, "gx_dps", {kRows}, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, gx.data());
    put(g, "gy_dps", {kRows}, H5T_IEEE_F32BE, H5T_NATIVE_FLOAT, gy.data());
    H5Gclose(g);
  });
  const std::string compound = h5("c.h5", [&](hid_t loc) {
    const hid_t mem = H5Tcreate(H5T_COMPOUND, sizeof(Row));
    H5Tinsert(mem, "t", offsetof(Row, t), H5T_NATIVE_DOUBLE);
    H5Tinsert(mem, "gx", offsetof(Row, gx), H5T_NATIVE_FLOAT);
    put(loc, "samples", {rows.size()}, mem, mem, rows.data());
    H5Tclose(mem);
  });
  // The same numbers as text, a missing value as an empty field.
  const auto num = [](double x) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", x);
    return std::isnan(x) ? std::string() : std::string(b);
  };
  std::string t2, tg = "gx_dps,gy_dps\n", tc = "t,gx\n";
  for (std::size_t r = 0; r < kRows; ++r) {
    t2 += num(v[2 * r]) + "," + num(v[2 * r + 1]) + "\n";
    tg += num(gx[r]) + "," + num(gy[r]) + "\n";
  }
  for (const Row& row : rows) tc += num(row.t) + "," + num(row.gx) + "\n";
  const auto output = [&](const std::string& args, const std::string& missing) {
    const auto r = run_cubecal(args + " --gaps skip --format csv");
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(missing + " missing sample(s)"), std::string::npos) << args << "\n" << r.err;
    return r.out;
  };
  const std::string davar = "davar --window 100 --step 50 --taus octave ";
  struct Case {
    std::string h5, csv, options, missing;
  };
  for (const Case& c :
       {Case{d2, write("d2.csv", t2), " --rate 10", "5"}, Case{group, write("g.csv", tg), " --rate 10", "5"},
        Case{compound, write("c.csv", tc), "", "6"}}) {
    SCOPED_TRACE(c.h5);
    const std::string h5_options = c.options + (c.h5 == group ? " --dataset /imu" : "");
    const std::string dev = output("dev " + c.h5 + h5_options, c.missing);
    EXPECT_NE(dev.find(",1,0.1,"), std::string::npos) << dev;  // a deviation at 10 Hz
    EXPECT_EQ(dev, output("dev " + c.csv + c.options, c.missing));
    EXPECT_EQ(output(davar + c.h5 + h5_options, c.missing), output(davar + c.csv + c.options, c.missing));
  }
  // Without --gaps skip: the first NaN, at its row and column.
  auto r = run_cubecal("dev " + d2 + " --rate 10");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find(d2 + ": NaN in dataset /d at row 11, column 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--gaps skip"), std::string::npos) << r.err;
  r = run_cubecal("davar " + group + " --rate 10 --dataset /imu");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("NaN in dataset /imu at row 11, column 1 (gx_dps)"), std::string::npos) << r.err;
  // An infinity is never a missing sample.
  v[2 * 77 + 1] = INFINITY;
  const std::string inf = h5("inf.h5", [&](hid_t loc) {
    put(loc, "d", {kRows, 2}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
  });
  r = run_cubecal("dev " + inf + " --rate 10 --gaps skip");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("infinite value in dataset /d at row 78, column 2"), std::string::npos) << r.err;
}

// Truncated and garbage files: one InputError line, no library stack.
TEST_F(Hdf5, TruncatedAndGarbageFilesGiveOneErrorLine) {
  const std::vector<double> v = table(3);
  const std::string f = h5("t.h5", [&](hid_t loc) {
    put(loc, "d", {kRows, 3}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
  });
  std::ifstream in(f, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  ASSERT_GT(bytes.size(), 2000U);
  std::size_t refused = 0, tried = 0;
  for (std::size_t cut : {8UL, 40UL, 96UL, 200UL, 800UL, 1400UL, 2000UL, bytes.size() / 2, bytes.size() - 1}) {
    std::ofstream(path("cut.h5"), std::ios::binary) << bytes.substr(0, cut);
    ++tried;
    const std::string e = error_of(path("cut.h5"), at_rate(10));
    if (e == "(no error)") continue;
    ++refused;
    EXPECT_EQ(e.rfind(path("cut.h5") + ": ", 0), 0U) << cut << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_EQ(refused, tried);
  // The signature, then garbage; and the CLI: exit 2, one line on stderr.
  std::string garbage = bytes.substr(0, 8);
  for (std::size_t i = 0; i < 5000; ++i) garbage += static_cast<char>((i * 2654435761U) >> 13);
  std::ofstream(path("garbage.h5"), std::ios::binary) << garbage;
  for (const char* name : {"cut.h5", "garbage.h5"}) {
    const auto r = run_cubecal("dev " + path(name) + " --rate 10");
    EXPECT_EQ(r.code, 2) << name;
    EXPECT_TRUE(one_error_line(r)) << r.err;
    EXPECT_NE(r.err.find("HDF5: "), std::string::npos) << r.err;
  }
}

// The CLI: --dataset, standard input and gzip (opened from memory), a
// dataset asked of a file that is not HDF5.
TEST_F(Hdf5, CommandLine) {
  const std::vector<double> v = table(3);
  const std::string f = h5("cli.h5", [&](hid_t loc) {
    put(loc, "a", {kRows}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
    put(loc, "b", {kRows, 3}, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data());
  });
  auto r = run_cubecal("dev " + f + " --rate 100 --dataset /b");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("col3 — oadev (freq data), 400 samples at 100 Hz"), std::string::npos) << r.out;
  const auto piped = run_cubecal_piped("cat " + f, "dev - --rate 100 --dataset /b");
  EXPECT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.out, r.out);
  ASSERT_EQ(std::system(("gzip -k " + f).c_str()), 0);
  const auto gz = run_cubecal("dev " + f + ".gz --rate 100 --dataset /b");
  EXPECT_EQ(gz.code, 0) << gz.err;
  EXPECT_EQ(gz.out, r.out);

  r = run_cubecal("dev " + f + " --rate 100");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("2 numeric datasets: /a (400,) float64; /b (400, 3) float64"), std::string::npos) << r.err;

  const std::string csv = write("x.csv", "1\n2\n3\n4\n");
  r = run_cubecal("dev " + csv + " --rate 100 --dataset /b");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--dataset"), std::string::npos) << r.err;
}

}  // namespace
