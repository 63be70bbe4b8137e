// Write failures of a recording (write_failure.hpp).
#include "cubecal/acquire/write_failure.hpp"

#include <cerrno>
#include <cstring>

namespace cubecal::acquire {

std::string describe_write_error(int err) {
  switch (err) {
    case EFBIG: return "file too large: the file-size limit (ulimit -f)";
    case ENOSPC: return "no space left on the device";
    case EDQUOT: return "disk quota exceeded";
    case EIO: return "input/output error on the device";
    case EROFS: return "the file system is read-only";
    default: return std::strerror(err);
  }
}

WriteFailure::WriteFailure(std::string file, int err)
    : std::runtime_error(file + ": write failed (" + describe_write_error(err) + ")"),
      file_(std::move(file)),
      err_(err) {}

}  // namespace cubecal::acquire
