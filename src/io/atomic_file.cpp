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

const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  if (S_ISREG(m)) return "a regular file";
  return "not a regular file";
}

std::string link_target(const std::string& path) {
  std::string t(4096, '\0');
  const ssize_t n = ::readlink(path.c_str(), t.data(), t.size());
  t.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  return t;
}

}  // namespace

OutputTarget classify_output(const std::string& path, std::string* why) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return OutputTarget::absent;
  const auto refuse = [&](const std::string& what) {
    if (why != nullptr) *why = what;
    return OutputTarget::refused;
  };
  if (S_ISREG(st.st_mode)) return OutputTarget::regular;
  if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return OutputTarget::stream;
  if (!S_ISLNK(st.st_mode))
    return refuse(path + " is " + kind_of(st.st_mode) + ", not a file a result can be written to: give a file name");
  const std::string target = link_target(path);
  struct stat ts {};
  if (::stat(path.c_str(), &ts) == 0 && (S_ISCHR(ts.st_mode) || S_ISFIFO(ts.st_mode))) return OutputTarget::stream;
  const std::string to = ::stat(path.c_str(), &ts) != 0
                             ? "a symbolic link to " + target + ", which does not exist"
                             : "a symbolic link to " + target + " (" + kind_of(ts.st_mode) + ")";
  return refuse(path + " is " + to +
                ": results are not written through links; name the target itself or remove the link");
}

AtomicFile::AtomicFile(std::string path, bool into_streams) : path_(std::move(path)), tmp_(path_ + ".partial") {
  const OutputTarget target = classify_output(path_);
  if (target == OutputTarget::refused || (target == OutputTarget::stream && !into_streams)) {
    fail(Step::create, EEXIST);
    return;
  }
  if (target == OutputTarget::stream) {
    // A device or a FIFO: written into as it is (a FIFO waits for its reader).
    into_stream_ = true;
    tmp_ = path_;
    fd_ = ::open(path_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (fd_ < 0) fail(Step::create, errno);
    return;
  }
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
  if (into_stream_) {
    // Nothing to rename; a device or FIFO need not support fsync.
    const int fd = fd_;
    fd_ = -1;
    committed_ = true;
    if (::close(fd) != 0) return fail(Step::close, errno);
    return true;
  }
  if (::fsync(fd_) != 0) return fail(Step::sync, errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) return fail(Step::close, errno);
  // What took PATH's place since the start (a link, a FIFO) is not replaced.
  const OutputTarget now = classify_output(path_);
  if ((now != OutputTarget::absent && now != OutputTarget::regular) || ::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int err = now != OutputTarget::absent && now != OutputTarget::regular ? EEXIST : errno;
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
  std::string why;
  if (classify_output(path, &why) == OutputTarget::refused) refuse(why);
  AtomicFile f(path);
  if (!f.is_open()) refuse("cannot write " + path + " (check the directory exists and is writable)");
  if (!f.write(content) || !f.commit()) refuse("could not finish writing " + path + " (disk full?)");
}

void replace_file_atomically(const std::string& path, std::string_view content) {
  const OutputTarget target = classify_output(path);
  if (target != OutputTarget::absent && target != OutputTarget::regular)
    throw std::system_error(EEXIST, std::generic_category(), path + ": not a regular file; it is left as it is");
  AtomicFile f(path, false);
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
