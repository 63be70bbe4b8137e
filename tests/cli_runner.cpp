#include "cli_runner.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace cubecal::test {

namespace {

CliRun run_command(const std::string& before, const std::string& args) {
  static std::atomic<int> counter{0};
  namespace fs = std::filesystem;
  const fs::path errf =
      fs::temp_directory_path() / ("cubecal_err_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string cmd = before + std::string(CUBECAL_BINARY) + " " + args + " 2>" + errf.string();
  CliRun r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = ::pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream e(errf);
  std::stringstream ss;
  ss << e.rdbuf();
  r.err = ss.str();
  fs::remove(errf);
  return r;
}

}  // namespace

CliRun run_cubecal(const std::string& args) { return run_command("", args); }

CliRun run_cubecal_piped(const std::string& producer, const std::string& args) {
  return run_command(producer + " | ", args);
}

bool one_error_line(const CliRun& r) {
  return r.code == 2 && r.err.rfind("cubecal: error: ", 0) == 0 && r.err.find('\n') == r.err.size() - 1;
}

}  // namespace cubecal::test
