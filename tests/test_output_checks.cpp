// Every command's output locations are checked before any work (issue 10,
// item 2): each command x each way an output can be unusable gives exit 2,
// one line naming the option and what to do, and leaves nothing behind.
//
// The inputs are broken at their last row: a command that read its input
// before checking its outputs would report the input instead.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/output_path.hpp"
#include "fifo.hpp"

namespace {

using cubecal::test::drain_fifo;
namespace fs = std::filesystem;
using cubecal::test::CliRun;
using cubecal::test::one_error_line;

class OutputChecks : public cubecal::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    std::string rec = "t,gx,gy,gz,temp\n";
    for (int i = 0; i < 200; ++i) rec += std::to_string(0.1 * i) + ",0.01,-0.02,0.03,25\n";
    rec += "20.0,0.01,oops,0.03,25\n";
    bad_ = write("bad.csv", rec);
    write("a_file", "the user's file\n");
    fs::create_directories(dir_ / "a_dir");
    fs::create_directories(dir_ / "old_report");
    write("old_report/report.html", "an earlier report\n");
  }
  CliRun run(const std::string& args) { return cubecal::test::run_cubecal(args); }
  // The commands, each with a placeholder {} where an output option goes.
  std::vector<std::string> file_commands() const {
    const std::string b = bad_;
    return {"dev " + b + " {}",
            "simulate --preset sport-gyro --duration 2h {}",
            "turnon " + b + " " + b + " {}",
            "compare " + b + " " + b + " {}",
            "calibrate rate-table " + b + " --ref-columns gx,gy,gz --columns gx,gy,gz {}",
            "calibrate mag " + b + " --columns gx,gy,gz {}",
            "calibrate multiposition " + b + " --acc-columns gx,gy,gz --rate 10 {}",
            "calibrate temperature " + b + " --columns gx --temp-col temp {}"};
  }
  std::vector<std::string> report_commands() const {
    std::vector<std::string> v;
    for (const std::string& c : file_commands())
      if (c.rfind("dev ", 0) != 0 && c.rfind("simulate ", 0) != 0) v.push_back(c);
    return v;
  }
  static std::string with(std::string cmd, const std::string& opt) { return cmd.replace(cmd.find("{}"), 2, opt); }
  std::string bad_;
};

// One run: exit 2, one line that names `option` and says `says`.
void expect_refused(const CliRun& r, const std::string& cmd, const std::string& option, const std::string& says) {
  EXPECT_EQ(r.code, 2) << cmd << "\n" << r.err;
  EXPECT_TRUE(one_error_line(r)) << cmd << "\n" << r.err;
  EXPECT_NE(r.err.find("cubecal: error: " + option + ": "), std::string::npos) << cmd << "\n" << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << cmd << "\n" << r.err;
}

TEST_F(OutputChecks, EveryFileOutputIsCheckedBeforeTheWork) {
  struct Case {
    std::string option, says;
  };
  const std::vector<Case> cases{
      {"--out " + path("a_dir"), "a_dir is a directory: give a file name"},
      {"--out " + path("a_dir") + " --force", "a_dir is a directory: give a file name"},
      {"--out " + path("missing/r.txt"), "missing of " + path("missing/r.txt") + " does not exist: create it first"},
      {"--out " + path("a_file/r.txt"), "a_file is not a directory"},
      {"--out /proc/cubecal-r.txt", "cannot write in /proc"},
      {"--out " + path("a_file"), "a_file already exists (choose another name or add --force"},
  };
  for (const std::string& c : file_commands())
    for (const Case& k : cases) {
      const std::string cmd = with(c, k.option);
      expect_refused(run(cmd), cmd, "--out", k.says);
    }
  std::ifstream in(path("a_file"));
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "the user's file");
  EXPECT_FALSE(fs::exists(path("a_dir/r.txt")));
  for (const auto& e : fs::directory_iterator(dir_))  // no probe or .partial left behind
    EXPECT_EQ(e.path().filename().string().find(".cubecal-probe"), std::string::npos) << e.path();
}

TEST_F(OutputChecks, EveryDirectoryOutputIsCheckedBeforeTheWork) {
  struct Case {
    std::string dir, says;
  };
  const std::vector<Case> cases{
      {path("a_file"), "a_file is a file: give a directory"},
      {path("a_file/sub"), "a_file is a file, so " + path("a_file/sub") + " cannot be created"},
      {"/proc/cubecal-out", "cannot create /proc/cubecal-out"},
  };
  for (const Case& k : cases) {
    for (const std::string& c : report_commands()) {
      const std::string cmd = with(c, "--report " + k.dir);
      expect_refused(run(cmd), cmd, "--report", k.says);
    }
    for (const std::string& cmd :
         {"analyze " + bad_ + " --unit deg/s --out " + k.dir,
          "analyze " + bad_ + " --unit deg/s --report --force --out " + k.dir, "demo --hours 1 --out " + k.dir})
      expect_refused(run(cmd), cmd, "--out", k.says);
  }
  // An earlier report is kept unless --force.
  for (const std::string& c : report_commands()) {
    const std::string cmd = with(c, "--report " + path("old_report"));
    expect_refused(run(cmd), cmd, "--report", "report.html already exists");
  }
  const std::string an = "analyze " + bad_ + " --unit deg/s --report --out " + path("old_report");
  expect_refused(run(an), an, "--out", "report.html already exists");
  EXPECT_FALSE(fs::exists(path("a_file/sub")));
}

TEST_F(OutputChecks, ReportIntoAnUnwritableDirectoryIsRefusedBeforeThePlots) {
  const CliRun r = run("report /proc");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("cannot write in /proc"), std::string::npos) << r.err;
}

// The writability probe never touches a file of its own name.
TEST_F(OutputChecks, TheProbeLeavesAnExistingFileOfItsNameAlone) {
  const std::string mine = write(".cubecal-probe-" + std::to_string(::getpid()), "the user's\n");
  cubecal::io::check_output_file(path("result.json"), false);
  cubecal::io::prepare_output_dir(dir_.string(), false, {"result.json"});
  std::ifstream in(mine);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "the user's");
  EXPECT_THROW(cubecal::io::check_output_file(mine, false), cubecal::UsageError);
}

// Issue 33, item 5: --force replaces regular files only. A symbolic link (to
// a file, to a directory, dangling) is refused naming it and left as it is,
// the file it points to untouched; a device or FIFO is written into.
TEST_F(OutputChecks, LinksAreRefusedDevicesAndFifosWrittenInto) {
  write("victim.txt", "the user's file\n");
  fs::create_symlink(path("victim.txt"), path("link"));
  fs::create_symlink(path("nowhere"), path("dangling"));
  fs::create_symlink(path("a_dir"), path("dir_link"));
  for (const std::string& c : file_commands())
    for (const std::string& opt : {"--out " + path("link") + " --force", "--out " + path("dangling"),
                                   "--out " + path("dir_link") + " --force"}) {
      const std::string cmd = with(c, opt);
      expect_refused(run(cmd), cmd, "--out", " is a symbolic link to ");
    }
  for (const std::string& c : report_commands()) {
    const std::string cmd = with(c, "--report " + path("dangling"));
    expect_refused(run(cmd), cmd, "--report", "dangling is a symbolic link to");
  }
  // A file inside an output directory, and the directory itself.
  fs::create_directories(path("res"));
  fs::create_symlink(path("victim.txt"), path("res/analysis.json"));
  const std::string an = "analyze " + bad_ + " --unit deg/s --force --out " + path("res");
  expect_refused(run(an), an, "--out", "res/analysis.json is a symbolic link to");
  const std::string dn = "analyze " + bad_ + " --unit deg/s --out " + path("dangling");
  expect_refused(run(dn), dn, "--out", "dangling is a symbolic link to");
  EXPECT_TRUE(fs::is_symlink(path("link")));
  EXPECT_TRUE(fs::is_symlink(path("dangling")));
  EXPECT_TRUE(fs::is_symlink(path("res/analysis.json")));
  EXPECT_FALSE(fs::exists(path("nowhere")));
  std::ifstream in(path("victim.txt"));
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "the user's file");

  // Written into: a device through a link, and a FIFO with its reader.
  const std::string rec = path("ok.csv");
  ASSERT_EQ(run("simulate --preset sport-gyro --duration 20m --out " + rec).code, 0);
  fs::create_symlink("/dev/null", path("null"));
  const CliRun n = run("dev " + rec + " --out " + path("null") + " --force");
  EXPECT_EQ(n.code, 0) << n.err;
  EXPECT_TRUE(fs::is_symlink(path("null")));
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = drain_fifo(path("fifo")); });
  const CliRun f = run("dev " + rec + " --format csv --out " + path("fifo"));
  reader.join();
  EXPECT_EQ(f.code, 0) << f.err;
  EXPECT_EQ(got.rfind("column,af,tau", 0), 0u) << got;
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
}

// The whole analysis no longer runs before an unusable --out is noticed: the
// broken input above proves the order, this proves the valid run still works
// and that --force replaces results in an existing directory.
TEST_F(OutputChecks, ValidOutputsStillWork) {
  const std::string rec = path("ok.csv");
  ASSERT_EQ(run("simulate --preset sport-gyro --duration 20m --out " + rec).code, 0);
  const CliRun a = run("analyze " + rec + " --unit deg/s --out " + path("res/deeper"));
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_TRUE(fs::exists(path("res/deeper/analysis.json")));
  const CliRun again = run("analyze " + rec + " --unit deg/s --out " + path("res/deeper"));
  expect_refused(again, "analyze again", "--out", "analysis.json already exists");
  EXPECT_EQ(run("analyze " + rec + " --unit deg/s --force --out " + path("res/deeper")).code, 0);
  const CliRun d = run("dev " + rec + " --out " + path("a_dir/dev.txt"));
  EXPECT_EQ(d.code, 0) << d.err;
  EXPECT_TRUE(fs::exists(path("a_dir/dev.txt")));
}

}  // namespace
