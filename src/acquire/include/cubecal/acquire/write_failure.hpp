// A recording that cannot be written on (a full disk, the file-size limit,
// a quota): which file, and the errno. The recorder stops; what the
// manifest describes was fsync'd before and stays intact.
#pragma once
#include <stdexcept>
#include <string>

namespace cubecal::acquire {

class WriteFailure : public std::runtime_error {
 public:
  WriteFailure(std::string file, int err);
  const std::string& file() const noexcept { return file_; }
  int error() const noexcept { return err_; }

 private:
  std::string file_;
  int err_;
};

// "file too large: the file-size limit", "no space left on the device", ...
std::string describe_write_error(int err);

}  // namespace cubecal::acquire
