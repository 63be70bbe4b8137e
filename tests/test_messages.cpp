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
      "calibrate temperature " + a + " --columns 'g\xe9x',gy --temp-col temp --format json",
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

}  // namespace
