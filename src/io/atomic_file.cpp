#include "cubecal/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "cubecal/error.hpp"

namespace cubecal::io {

namespace {

std::string parent_dir(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

// A stale temporary of a killed run is removed when it is a regular file;
// whatever else has that name stays, and the exclusive create then fails.
void remove_stale(const std::string& tmp) noexcept {
  struct stat st {};
  if (::lstat(tmp.c_str(), &st) == 0 && S_ISREG(st.st_mode)) ::unlink(tmp.c_str());
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".partial") {
  remove_stale(tmp_);
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd_ < 0) {
    fail(Step::create, errno);
    return;
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    ::unlink(tmp_.c_str());  // just created exclusively: ours
    fail(Step::create, err);
    return;
  }
  dev_ = st.st_dev;
  ino_ = st.st_ino;
}

AtomicFile::~AtomicFile() { discard(); }

bool AtomicFile::fail(Step step, int err) noexcept {
  step_ = step;
  error_ = err;
  return false;
}

bool AtomicFile::write(std::string_view bytes) noexcept {
  if (fd_ < 0) return fail(Step::write, EBADF);
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail(Step::write, errno);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}

bool AtomicFile::commit() {
  if (fd_ < 0) return fail(Step::write, EBADF);
  if (::fsync(fd_) != 0) return fail(Step::sync, errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) return fail(Step::close, errno);
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    fail(Step::rename, err);
    throw std::filesystem::filesystem_error("cannot rename", tmp_, path_,
                                            std::error_code(err, std::generic_category()));
  }
  committed_ = true;
  const std::string dir = parent_dir(path_);
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return fail(Step::open_dir, errno);
  const int rc = ::fsync(dfd);
  const int err = errno;
  ::close(dfd);
  if (rc != 0) return fail(Step::sync_dir, err);
  return true;
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (committed_ || ino_ == 0) return;
  struct stat st {};
  if (::lstat(tmp_.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_dev == dev_ && st.st_ino == ino_)
    ::unlink(tmp_.c_str());
  ino_ = 0;
}

void write_file(const std::string& path, std::string_view content, std::optional<Field> field) {
  const auto refuse = [&](const std::string& what) {
    if (field) throw UsageError(*field, what);
    throw UsageError(what);
  };
  AtomicFile f(path);
  if (!f.is_open()) refuse("cannot write " + path + " (check the directory exists and is writable)");
  if (!f.write(content) || !f.commit()) refuse("could not finish writing " + path + " (disk full?)");
}

void replace_file_atomically(const std::string& path, std::string_view content) {
  AtomicFile f(path);
  if (f.is_open() && f.write(content)) {
    try {
      if (f.commit()) return;
    } catch (const std::filesystem::filesystem_error& e) {
      throw std::system_error(e.code().value(), std::generic_category(), path + ": rename failed");
    }
  }
  const std::string& tmp = f.temp_path();
  const std::string what = [&]() -> std::string {
    switch (f.failed_step()) {
      case AtomicFile::Step::create: return tmp + ": cannot be created";
      case AtomicFile::Step::write: return tmp + ": write failed";
      case AtomicFile::Step::sync: return tmp + ": fsync failed";
      case AtomicFile::Step::close: return tmp + ": close failed";
      case AtomicFile::Step::rename: return path + ": rename failed";
      case AtomicFile::Step::open_dir: return parent_dir(path) + ": cannot be opened";
      case AtomicFile::Step::sync_dir: return parent_dir(path) + ": fsync failed";
    }
    return path + ": cannot be written";
  }();
  throw std::system_error(f.error(), std::generic_category(), what);
}

}  // namespace cubecal::io
