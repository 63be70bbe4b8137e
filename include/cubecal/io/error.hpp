// Input errors with a location: every reader failure becomes one line
// "FILE:LINE:COL: what is wrong (what to do)" and exit code 2 in the CLI.
#pragma once
#include <cstddef>
#include <stdexcept>
#include <string>

namespace cubecal::io {

class InputError : public std::runtime_error {
 public:
  // line and column are 1-based; 0 means "not applicable" and is omitted
  // from the formatted message (e.g. "FILE: empty file").
  InputError(std::string file, std::size_t line, std::size_t column, std::string what,
             std::string hint = {});

  const std::string& file() const noexcept { return file_; }
  std::size_t line() const noexcept { return line_; }
  std::size_t column() const noexcept { return column_; }
  const std::string& problem() const noexcept { return problem_; }
  const std::string& hint() const noexcept { return hint_; }

 private:
  std::string file_;
  std::size_t line_;
  std::size_t column_;
  std::string problem_;
  std::string hint_;
};

// Bad command-line usage that is not tied to a file position (exit 2 too).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cubecal::io
