// Issue 33, items 1 and 12: text that leaves cubecal. A column name that is
// not UTF-8 is shown with its bad bytes as \xNN by every writer (JSON of each
// command, CSV, tables, reports, messages), and each misleading message of
// the hostile run names the real problem.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/printable_text.hpp"

namespace {

namespace fs = std::filesystem;

using Result = cubecal::test::CliRun;
using cubecal::test::one_error_line;
Result run(const std::string& args) { return cubecal::test::run_cubecal(args); }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Well-formed UTF-8: the text is what utf8_text leaves unchanged.
bool is_utf8(const std::string& s) { return cubecal::utf8_text(s) == s; }

class Messages : public cubecal::test::TempDirTest {
 protected:
  // A static three-axis record at 100 Hz whose first channel is named
  // "g\xe9x" (Latin-1, not UTF-8), with a temperature column.
  std::string latin1_record(const std::string& name, unsigned seed, std::size_t n = 6000) {
    std::string text = "t,g\xe9x,gy,gz,temp\n";
    unsigned s = seed;
    const auto noise = [&s] {
      s = s * 1103515245u + 12345u;
      return (static_cast<double>((s >> 8) & 0xffff) / 65536.0 - 0.5) * 0.02;
    };
    char line[160];
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) * 0.01;
      std::snprintf(line, sizeof line, "%.2f,%.6f,%.6f,%.6f,%.3f\n", t, 0.01 * seed + noise(), noise(), noise(),
                    25.0 + 5.0 * std::sin(t / 20.0));
      text += line;
    }
    return write(name, text);
  }
};

// --- item 1: names that are not UTF-8 ---------------------------------------

TEST(PrintableText, Utf8TextEscapesOnlyMalformedBytes) {
  EXPECT_EQ(cubecal::utf8_text("g\xe9x"), "g\\xe9x");
  EXPECT_EQ(cubecal::utf8_text("caf\xc3\xa9\n\t"), "caf\xc3\xa9\n\t") << "UTF-8 and control bytes are kept";
  EXPECT_EQ(cubecal::printable_text("g\xe9x\n"), "g\\xe9x\\x0a");
}

// Every JSON writer: exit 0 (was "internal error: [json.exception.type_error.316]"),
// a document that parses, the name with its byte escaped.
TEST_F(Messages, JsonOfEveryCommandEscapesNonUtf8Names) {
  const std::string a = latin1_record("a.csv", 1), b = latin1_record("b.csv", 2), c = latin1_record("c.csv", 3);
  const std::vector<std::string> commands = {
      "dev " + a + " --columns 2,3 --format json",
      "psd " + a + " --format json",
      "analyze " + a + " --unit deg/s --format json",
      "model " + a + " --model WN+RW --format json",
      "davar " + a + " --columns 2 --format json",
      "turnon " + a + " " + b + " " + c + " --unit deg/s --format json",
      "calibrate temperature " + a + " --columns 'g\xe9x',gy --temp-col temp --unit deg/s --format json",
  };
  for (const auto& cmd : commands) {
    const Result r = run(cmd);
    ASSERT_EQ(r.code, 0) << cmd << "\n" << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << cmd << "\n" << r.err;
    EXPECT_TRUE(is_utf8(r.out) && is_utf8(r.err)) << cmd;
    EXPECT_TRUE(nlohmann::json::accept(r.out)) << cmd;
    EXPECT_NE(r.out.find("g\\\\xe9x"), std::string::npos) << cmd << ": the name, escaped in JSON";
  }
}

TEST_F(Messages, CalibrationJsonEscapesNonUtf8Names) {
  std::string table = "t,g\xe9x,gy,gz,rx,ry,rz\n";
  std::size_t k = 0;
  char line[200];
  for (int axis = 0; axis < 3; ++axis)
    for (const double rate : {0.0, 10.0, -10.0, 100.0, -100.0})
      for (int i = 0; i < 700; ++i, ++k) {
        double r[3] = {0, 0, 0};
        if (i >= 100) r[axis] = rate;
        const double wiggle = 1e-3 * std::sin(static_cast<double>(k));
        std::snprintf(line, sizeof line, "%.1f,%.6g,%.6g,%.6g,%g,%g,%g\n", static_cast<double>(k) * 0.1,
                      1.01 * r[0] + 0.1 + wiggle, 0.99 * r[1] - 0.05 - wiggle, 1.02 * r[2] + 0.02 + wiggle, r[0], r[1],
                      r[2]);
        table += line;
      }
  const std::string t = write("table.csv", table);
  std::string xs =
      "t ax\xe9 ay az\n" + slurp(std::string(CUBECAL_SHARED_DATA) + "/imu/xsens-multiposition/xsens_acc.txt");
  const std::string x = write("xs.txt", xs);
  for (const auto& cmd :
       {"calibrate rate-table " + t + " --columns 'g\xe9x',gy,gz --ref-columns rx,ry,rz --format json",
        "calibrate multiposition " + x +
            " --acc-columns 'ax\xe9',ay,az --time-col t --g 9.81744 --acc-bias 32768 --format json"}) {
    const Result r = run(cmd);
    ASSERT_EQ(r.code, 0) << cmd << "\n" << r.err;
    EXPECT_TRUE(is_utf8(r.out) && is_utf8(r.err)) << cmd;
    EXPECT_TRUE(nlohmann::json::accept(r.out)) << cmd;
    EXPECT_NE(r.out.find("\\\\xe9"), std::string::npos) << cmd;
  }
}

// CSV, tables, the analysis directory, the report and the notes on stderr:
// the same \xNN text, never the raw byte.
TEST_F(Messages, TablesCsvFilesAndNotesEscapeNonUtf8Names) {
  const std::string a = latin1_record("a.csv", 1);
  for (const auto& cmd : {"dev " + a + " --columns 2 --format csv", "dev " + a + " --columns 2", "psd " + a,
                          "analyze " + a + " --unit deg/s", "davar " + a + " --columns 2"}) {
    const Result r = run(cmd);
    ASSERT_EQ(r.code, 0) << cmd << "\n" << r.err;
    EXPECT_TRUE(is_utf8(r.out) && is_utf8(r.err)) << cmd;
    EXPECT_NE(r.out.find("g\\xe9x"), std::string::npos) << cmd;
  }
  const Result note = run("dev " + a);
  EXPECT_NE(note.err.find("columns g\\xe9x,gy,gz"), std::string::npos) << note.err;
  // The name is chosen by its raw bytes or by the escape the output shows.
  EXPECT_EQ(run("dev " + a + " --columns 'g\\xe9x'").code, 0);
  const fs::path dir = dir_ / "an";
  ASSERT_EQ(run("analyze " + a + " --unit deg/s --out " + dir.string()).code, 0);
  ASSERT_EQ(run("report " + dir.string()).code, 0);
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() != ".png") {
      EXPECT_TRUE(is_utf8(slurp(e.path()))) << e.path();
    }
  }
}

// --- item 12: each message names the real problem ----------------------------

const std::string kData = CUBECAL_SHARED_DATA;

bool has(const Result& r, const std::string& text) { return r.err.find(text) != std::string::npos; }

// A regular file whose size is 0 but that has content is read (was "the file is empty").
TEST_F(Messages, ProcFileOfSizeZeroIsRead) {
  const Result r = run("dev /proc/self/status --rate 1");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_FALSE(has(r, "empty")) << r.err;
  EXPECT_TRUE(has(r, "/proc/self/status:2:1: non-numeric field")) << r.err;
  const Result empty = run("dev " + write("empty.csv", ""));
  EXPECT_TRUE(has(empty, "the file is empty")) << empty.err;
}

// Was "A subcommand is required".
TEST_F(Messages, UnknownCommandIsNamedWithTheCommands) {
  const Result top = run("frobnicate");
  EXPECT_TRUE(one_error_line(top)) << top.err;
  EXPECT_TRUE(has(top, "unknown command 'frobnicate' (cubecal commands: dev, analyze, ")) << top.err;
  const Result sub = run("calibrate frob");
  EXPECT_TRUE(has(sub, "unknown command 'frob' (cubecal calibrate commands: rate-table, mag, ")) << sub.err;
  EXPECT_TRUE(has(run(""), "A subcommand is required")) << "no command at all";
}

// The refusal of a .npy said "cubecal reads ... NumPy .npy": calibrate now does.
TEST_F(Messages, CalibrateReadsNpyAsItsMessageSays) {
  const std::size_t n = 400;
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(n) + ", 3), }";
  header.append(64 - (10 + header.size() + 1) % 64, ' ');
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes += static_cast<char>(header.size() & 0xff);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  for (std::size_t i = 0; i < n; ++i) {  // points on an offset, stretched sphere
    const double z = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double r = std::sqrt(1.0 - z * z), phi = 2.39996323 * static_cast<double>(i);
    const double p[3] = {0.3 + 1.2 * r * std::cos(phi), -0.1 + 0.9 * r * std::sin(phi), 0.2 + z};
    bytes.append(reinterpret_cast<const char*>(p), sizeof p);
  }
  const fs::path npy = dir_ / "mag.npy";
  std::ofstream(npy, std::ios::binary) << bytes;
  const Result r = run("calibrate mag " + npy.string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("400 points used of 400"), std::string::npos) << r.out;
}

// Was "give the time column (--time-col) or the sampling rate (--rate)".
TEST_F(Messages, MultipositionNegativeRateIsNamed) {
  const Result r = run("calibrate multiposition " + kData +
                       "/imu/xsens-multiposition/xsens_acc.txt --acc-columns 2,3,4 --rate -100");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_TRUE(has(r, "--rate: '-100' is not a positive number")) << r.err;
}

// Was "--model: model 'WN+FOO': unknown term 'FOO'".
TEST_F(Messages, CompositeTermIsNamedAsComposite) {
  const Result r = run("analyze " + latin1_record("a.csv", 1, 2000) + " --composite WN+FOO");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_TRUE(has(r, "--composite: model 'WN+FOO': unknown term 'FOO'")) << r.err;
  EXPECT_FALSE(has(r, "--model")) << r.err;
}

// Was "--out: DIR/report.html already exists".
TEST_F(Messages, ReportWrittenTwiceNamesTheReport) {
  const fs::path dir = dir_ / "an";
  ASSERT_EQ(run("analyze " + latin1_record("a.csv", 1, 2000) + " --unit deg/s --out " + dir.string()).code, 0);
  ASSERT_EQ(run("report " + dir.string()).code, 0);
  const Result again = run("report " + dir.string());
  EXPECT_TRUE(one_error_line(again)) << again.err;
  EXPECT_TRUE(has(again, "report.html already exists: " + dir.string() + " has a report already (add --force"))
      << again.err;
  EXPECT_FALSE(has(again, "--out")) << again.err;
}

// A recording of `lines` (a shell command printing CSV) made by cubecal record.
std::string record(const fs::path& dir, const std::string& producer) {
  const Result r = cubecal::test::run_cubecal_piped(producer, "record - --out " + dir.string());
  EXPECT_EQ(r.code, 0) << r.err;
  return dir.string();
}

// Was "NUL byte at byte offset 200 (a binary log, ...)".
TEST_F(Messages, DamagedRecordingChunkIsACrcMismatch) {
  const std::string rec =
      record(dir_ / "rec", "awk 'BEGIN{print \"t,gx\"; for(i=0;i<3000;i++) printf \"%.2f,%d\\n\", i*0.01, i%7}'");
  {
    std::fstream chunk(dir_ / "rec/seg-001/chunk-000001.csv", std::ios::in | std::ios::out | std::ios::binary);
    chunk.seekp(200);
    chunk.put('\0');
  }
  const Result r = run("dev " + rec);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_TRUE(has(r, "chunk-000001.csv: CRC-32 ")) << r.err;
  EXPECT_FALSE(has(r, "NUL")) << r.err;
}

// Was "time stamp 29.99 s is not after the previous one 29.99 s": the file holds 5.
TEST_F(Messages, DeviceClockThatWentBackIsNamedByItsStamps) {
  const std::string rec = record(dir_ / "rec",
                                 "awk 'BEGIN{print \"t,gx\"; for(i=0;i<3000;i++) printf \"%.2f,%d\\n\", i*0.01, i%7; "
                                 "for(i=0;i<3000;i++) printf \"%.2f,%d\\n\", 5+i*0.01, i%5}'");
  const Result r = run("dev " + rec);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(has(r, ":3002: ")) << r.err;
  EXPECT_TRUE(has(r, "the device clock went back")) << r.err;
  EXPECT_TRUE(has(r, "from 29.99 s to 5 s")) << r.err;
}

// Was "after t = 20.326715999999998 s" and "m = inf".
TEST_F(Messages, NumbersInMessagesCarryNoConversionNoise) {
  const Result ulog = run("dev " + kData + "/px4/sample_log_small.ulg");
  EXPECT_TRUE(has(ulog, "after t = 20.326716 s ")) << ulog.err;
  const Result bag = run("dev " + kData + "/rosbag/ros1/ardrone_imu.bag");
  EXPECT_TRUE(has(bag, "after t = 1352907204.5937724 s ")) << bag.err << "a real digit is kept";
  const Result huge = run("dev " + latin1_record("a.csv", 1, 2000) + " --columns 2 --taus 1,1e308");
  EXPECT_EQ(huge.code, 0) << huge.err;
  EXPECT_TRUE(has(huge, "1e+308 s (oadev at 1e+308 s: more sample periods of 0.01 s than a number holds")) << huge.err;
  EXPECT_FALSE(has(huge, "inf")) << huge.err;
}

// Was silent: with jittery stamps, AF 1 pooled 37 segments and AF 4 one.
TEST_F(Messages, GapsSplitWarnsWhenTausPoolDifferentSegments) {
  const Result r = run("dev " + kData + "/rosbag/ros1/ardrone_imu.bag --gaps split");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r, "cubecal: warning: ")) << r.err;
  EXPECT_TRUE(has(r,
                  "irregular intervals cut the record into 3315 segments of 1 to 16 samples: tau 0.0200036 s pools "
                  "37 of them, tau 0.0800142 s only 1, so each tau averages a different part of the record"))
      << r.err;
  // Two long pieces, each long enough for every tau: nothing to warn about.
  std::string text = "t,g\n";
  for (int i = 0; i < 4000; ++i) text += std::to_string(i < 2000 ? i : i + 500) + "," + std::to_string(i % 7) + "\n";
  const Result two = run("dev " + write("two.csv", text) + " --gaps split");
  EXPECT_EQ(two.code, 0) << two.err;
  EXPECT_FALSE(has(two, "warning")) << two.err;
}

// Was exit 0: the rate given, the time column was never checked.
TEST_F(Messages, RateGivenStillRefusesATimeColumnThatGoesBack) {
  std::string text = "t,g\n";
  char line[64];
  for (int i = 0; i < 3000; ++i) {
    std::snprintf(line, sizeof line, "%.2f,%d\n", (i < 1500 ? i : 3000 - i) * 0.01, i % 7);
    text += line;
  }
  const std::string f = write("back.csv", text);
  for (const std::string extra : {"", " --stream"}) {
    const Result r = run("dev " + f + " --rate 100" + extra);
    EXPECT_TRUE(one_error_line(r)) << extra << r.err;
    EXPECT_TRUE(has(r, "back.csv:1503")) << extra << r.err;
    EXPECT_TRUE(has(r, "time stamp 14.99 s is before the previous one 15 s")) << extra << r.err;
  }
  // Repeated stamps (a coarse clock) are what --rate is for.
  std::string coarse = "t,g\n";
  for (int i = 0; i < 3000; ++i) coarse += std::to_string(i / 10) + "," + std::to_string(i % 7) + "\n";
  EXPECT_EQ(run("dev " + write("coarse.csv", coarse) + " --rate 10").code, 0);
}

}  // namespace
