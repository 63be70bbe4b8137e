#include "cubecal/io/output_path.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"

namespace cubecal::io {

namespace fs = std::filesystem;

namespace {

// Creating a file is the only test of writability that holds for root, for
// read-only mounts and for ACLs alike; with O_EXCL a file of the probe's
// name, should one exist, is never touched.
void probe_writable(const fs::path& dir, Field option, const std::string& shown) {
  int err = 0;
  for (int attempt = 0; attempt < 8; ++attempt) {
    std::string name = ".cubecal-probe-" + std::to_string(::getpid());
    if (attempt > 0) name.append(1, '-').append(std::to_string(attempt));
    const fs::path probe = dir / name;
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd >= 0) {
      ::close(fd);
      std::error_code ec;
      fs::remove(probe, ec);
      return;
    }
    err = errno;
    if (err != EEXIST) break;
  }
  throw UsageError(option, "cannot write in " + shown + (err ? std::string(" (") + std::strerror(err) + ")" : "") +
                               ": choose a writable place");
}

std::string parent_text(const fs::path& p) { return p.empty() ? std::string(".") : p.string(); }

}  // namespace

void check_output_file(const std::string& path, bool force, Field option) {
  std::error_code ec;
  const fs::path p(path);
  if (path.empty()) throw UsageError(option, "the output file name is empty");
  const fs::file_status st = fs::symlink_status(p, ec);
  if (fs::is_directory(st)) throw UsageError(option, path + " is a directory: give a file name for the result");
  std::string why;
  const OutputTarget target = classify_output(path, &why);
  if (target == OutputTarget::refused) throw UsageError(option, why);
  if (target == OutputTarget::stream) return;  // a device or FIFO: written into, nothing replaced
  if (fs::exists(st) && !force)
    throw UsageError(option, path + " already exists (choose another name or add {force} to replace it)");
  const fs::path parent = p.parent_path();
  if (!parent.empty()) {
    const fs::file_status ps = fs::status(parent, ec);
    if (!fs::exists(ps))
      throw UsageError(option, "the directory " + parent.string() + " of " + path + " does not exist: create it first");
    if (!fs::is_directory(ps))
      throw UsageError(option, parent.string() + " is not a directory, so " + path + " cannot be written");
  }
  probe_writable(parent.empty() ? fs::path(".") : parent, option, parent_text(parent));
}

void prepare_output_dir(const std::string& dir, bool force, const std::vector<std::string>& files, Field option) {
  std::error_code ec;
  const fs::path d(dir);
  if (dir.empty()) throw UsageError(option, "the output directory name is empty");
  const fs::file_status st = fs::status(d, ec);
  // A symbolic link to a directory is used as that directory; one to
  // anything else, or to nothing, is not replaced by one.
  if (fs::is_symlink(fs::symlink_status(d, ec)) && !fs::is_directory(st))
    throw UsageError(option, dir + " is a symbolic link to " + fs::read_symlink(d, ec).string() +
                                 (fs::exists(st) ? ", not a directory" : ", which does not exist") +
                                 ": give a directory for the results");
  if (fs::exists(st) && !fs::is_directory(st))
    throw UsageError(option, dir + " is a file: give a directory for the results");
  if (!fs::exists(st)) {
    // Find the first existing ancestor, to say precisely what is in the way.
    for (fs::path a = d.parent_path(); !a.empty(); a = a.parent_path()) {
      const fs::file_status as = fs::status(a, ec);
      if (!fs::exists(as)) continue;
      if (!fs::is_directory(as)) throw UsageError(option, a.string() + " is a file, so " + dir + " cannot be created");
      break;
    }
    fs::create_directories(d, ec);
    if (ec) throw UsageError(option, "cannot create " + dir + " (" + ec.message() + "): choose a writable place");
  }
  for (const std::string& f : files) {
    // A directory of results (plots/) is replaced with {force}; a file only
    // when it is a regular file (or written into: a device, a FIFO).
    const fs::path p = d / f;
    std::string why;
    const OutputTarget target = classify_output(p.string(), &why);
    if (target == OutputTarget::refused && !fs::is_directory(fs::symlink_status(p, ec))) throw UsageError(option, why);
    if (!force && target != OutputTarget::absent && target != OutputTarget::stream)
      throw UsageError(option, p.string() + " already exists (choose another directory or add {force} to replace it)");
  }
  probe_writable(d, option, dir);
}

}  // namespace cubecal::io
