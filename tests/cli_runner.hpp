// Test support: run the built cubecal binary (path in CUBECAL_BINARY) and
// collect its exit code, standard output and standard error.
#pragma once
#include <string>

namespace cubecal::test {

struct CliRun {
  int code = -1;
  std::string out, err;
};

// `args` is appended to the binary's path as shell words.
CliRun run_cubecal(const std::string& args);

// A bad-input run: exit 2 and exactly one line "cubecal: error: ..." on stderr.
bool one_error_line(const CliRun& r);

}  // namespace cubecal::test
