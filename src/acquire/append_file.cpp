// Buffered, fsync'd append-only files (detail/append_file.hpp).
#include "detail/append_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>

#include "cubecal/acquire/write_failure.hpp"

namespace cubecal::acquire::detail {

namespace {

std::string parent_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

int open_regular(const std::string& path, int flags, int mode) {
  const int fd = ::open(path.c_str(), flags | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, mode);
  if (fd < 0) return -1;
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    errno = EINVAL;
    return -1;
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

void sync_directory(const std::string& dir, bool follow_link) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC | (follow_link ? 0 : O_NOFOLLOW));
  if (fd < 0) throw WriteFailure(dir, errno);
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    throw WriteFailure(dir, err);
  }
  ::close(fd);
}

AppendFile::AppendFile(std::string path, bool existing, std::size_t buffer) : path_(std::move(path)), limit_(buffer) {
  fd_ = open_regular(path_, O_WRONLY | O_APPEND | (existing ? 0 : O_CREAT | O_EXCL));
  if (fd_ < 0) throw WriteFailure(path_, errno);
  if (existing) {
    struct stat st {};
    if (::fstat(fd_, &st) == 0) written_ = static_cast<std::size_t>(st.st_size);
  } else {
    sync_directory(parent_of(path_));
  }
  buf_.reserve(limit_ + 4096);
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);  // a failed recording: what was written stays, nothing more
}

void AppendFile::flush() {
  const char* p = buf_.data();
  std::size_t left = buf_.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      buf_.erase(0, static_cast<std::size_t>(p - buf_.data()));
      throw WriteFailure(path_, err);
    }
    crc_ = static_cast<std::uint32_t>(::crc32(crc_, reinterpret_cast<const Bytef*>(p), static_cast<uInt>(n)));
    p += n;
    left -= static_cast<std::size_t>(n);
    written_ += static_cast<std::size_t>(n);
  }
  buf_.clear();
}

void AppendFile::sync() {
  flush();
  if (::fdatasync(fd_) != 0) throw WriteFailure(path_, errno);
}

void AppendFile::close() {
  sync();
  if (::close(fd_) != 0) {
    fd_ = -1;
    throw WriteFailure(path_, errno);
  }
  fd_ = -1;
}

}  // namespace cubecal::acquire::detail
