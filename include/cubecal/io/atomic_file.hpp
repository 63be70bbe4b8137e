/// @file
/// A file written whole or not at all, the one way every command, the
/// recorder's manifest and the Python module write a result file. The bytes go
/// to PATH.partial beside the target; commit() fsyncs it, renames it over PATH
/// and fsyncs the directory, so that a reader, a crash or an interrupted run
/// sees the old file or the new one, never a half-written one.
///
/// The temporary is created afresh (exclusive, never through a symlink): a
/// stale regular PATH.partial left by a killed run is replaced, anything else
/// of that name (a symlink, a directory, a fifo) is left alone and the file
/// cannot be written. Only a regular file at PATH is ever replaced, and only
/// the temporary this writer created is ever removed, while it is still that
/// regular file. What else PATH may be (classify_output): a character device
/// or a FIFO, itself or at the end of a symbolic link (/dev/null,
/// /dev/stdout, a named pipe), is written into, without a temporary; anything
/// else (a symbolic link to a file or a directory, a dangling link, a
/// directory, a block device, a socket) is refused: the writer does not open.
///
/// Failures are returned (false, with errno in error() and the step in
/// failed_step()) so that each caller words them for its users; a failed
/// rename throws std::filesystem::filesystem_error, as std::filesystem::rename.
#pragma once
#include "cubecal/field.hpp"
#include <sys/types.h>

#include <optional>
#include <string>
#include <string_view>

namespace cubecal::io {

/// What is at an output path, and so what writing a result there does.
enum class OutputTarget {
  absent,   ///< nothing: the file is created
  regular,  ///< a regular file (not a link): replaced whole
  stream,   ///< a character device or a FIFO, or a symbolic link to one: written into, nothing replaced
  refused,  ///< anything else: never written, never removed
};

/// What is at `path` (lstat, and stat through a symbolic link). For refused,
/// `why` (when given) receives a sentence naming `path` and what it is.
OutputTarget classify_output(const std::string& path, std::string* why = nullptr);

/// Writes PATH whole or not at all, through PATH.partial beside it.
class AtomicFile {
 public:
  /// The step that failed: creating the temporary, writing it, its fsync, its
  /// close, the rename over PATH, opening the directory, its fsync.
  enum class Step { create, write, sync, close, rename, open_dir, sync_dir };

  /// Creates PATH.partial; is_open() tells whether it could. Throws nothing
  /// for a failure to create it (error() and failed_step() say why; EEXIST
  /// when PATH is refused by classify_output). With `into_streams`, a device
  /// or FIFO at PATH is opened and written into instead; without, it is
  /// refused too (a recording's manifest).
  explicit AtomicFile(std::string path, bool into_streams = true);
  /// Removes the temporary unless commit() succeeded.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// True while the temporary is open for writing.
  bool is_open() const noexcept { return fd_ >= 0; }
  /// The temporary's descriptor, for writers of their own (stdio, zlib) on a
  /// dup() of it; -1 when not open.
  int fd() const noexcept { return fd_; }
  /// The target PATH.
  const std::string& path() const noexcept { return path_; }
  /// The temporary, PATH.partial (PATH itself when writing into a stream).
  const std::string& temp_path() const noexcept { return tmp_; }
  /// True when PATH is a device or FIFO written into (no temporary, no rename).
  bool into_stream() const noexcept { return into_stream_; }
  /// The errno of the step that failed; 0 when none has.
  int error() const noexcept { return error_; }
  /// The step that failed; meaningful only once a call has returned false.
  Step failed_step() const noexcept { return step_; }

  /// Appends `bytes` (all of them, retried on EINTR and short writes).
  /// Returns false on failure (error(), failed_step()).
  bool write(std::string_view bytes) noexcept;
  /// fsync, close, rename over path(), fsync of the directory. Returns false
  /// when a step fails (error(), failed_step()); a failed rename throws
  /// std::filesystem::filesystem_error instead.
  bool commit();
  /// Closes and removes the temporary (what the destructor does).
  void discard() noexcept;

 private:
  bool fail(Step step, int err) noexcept;
  std::string path_;
  std::string tmp_;
  int fd_ = -1;
  dev_t dev_ = 0;
  ino_t ino_ = 0;
  bool committed_ = false;
  bool into_stream_ = false;
  int error_ = 0;
  Step step_ = Step::create;
};

/// A result file of a command or of the Python module: `content` written to
/// `path` through AtomicFile. Throws UsageError (naming `field` when given)
/// when the file cannot be created or finished, or `path` is refused by
/// classify_output.
void write_file(const std::string& path, std::string_view content, std::optional<Field> field = std::nullopt);

/// The same for files that are not a user's result (a recording's manifest):
/// `path` replaced by `content` through AtomicFile. After a crash at any
/// point PATH holds either the old or the new content. Throws
/// std::system_error naming the file and the step that failed, and when
/// `path` is anything but a regular file or absent.
void replace_file_atomically(const std::string& path, std::string_view content);

}  // namespace cubecal::io
