// Test support: run the built cubecal binary (path in CUBECAL_BINARY) and
// collect its exit code, standard output and standard error.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace cubecal::test {

struct CliRun {
  int code = -1;
  std::string out, err;
};

// `args` is appended to the binary's path as shell words.
CliRun run_cubecal(const std::string& args);

// Same, with the standard input read from a pipe fed by the shell command
// `producer` (e.g. "cat FILE" or "head -c 2G /dev/zero").
CliRun run_cubecal_piped(const std::string& producer, const std::string& args);

// A bad-input run: exit 2 and exactly one line "cubecal: error: ..." on stderr.
bool one_error_line(const CliRun& r);

// A test with its own temporary directory (removed after the test), named
// after the process and the test so that parallel ctest runs never share one.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("cubecal_test_" + std::to_string(::getpid()) + "_" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // Writes `text` to dir_/name; returns its path.
  std::string write(const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

}  // namespace cubecal::test
