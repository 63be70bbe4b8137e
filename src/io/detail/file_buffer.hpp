// Whole-file access: memory-mapped for plain files, inflated into memory for
// gzip (detected by its magic bytes, never by the file name). "-" is the
// standard input, read into memory.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace cubecal::io {

// What a file may hold; anything else is refused from its first bytes
// (before a large file is mapped or a pipe read to its end).
enum class Content {
  text,    // delimited text
  series,  // text, or a binary format a record reader recognises by its magic bytes (NumPy .npy, HDF5, ROS 1 bag, PX4
           // ULog)
  raw,     // any bytes (raw binary described by the caller)
};

// The path that names the standard input, and how errors name it.
inline constexpr const char* kStdinPath = "-";
inline constexpr const char* kStdinLabel = "<stdin>";

// Whether `head` starts with the magic bytes of a binary format that
// read_series recognises.
bool is_known_binary_format(std::string_view head) noexcept;

class FileBuffer {
 public:
  // Throws InputError (file not found, unreadable, truncated/corrupt gzip,
  // a gzip file that inflates to more than `max_inflated` bytes when that is
  // not 0, content that `content` does not allow).
  static FileBuffer open(const std::string& path, Content content = Content::text, std::size_t max_inflated = 0);

  FileBuffer(FileBuffer&&) noexcept;
  FileBuffer& operator=(FileBuffer&&) noexcept;
  ~FileBuffer();

  std::string_view view() const noexcept;
  // A memory-mapped file's pages, for a pass that walks it once: populate()
  // maps `part` ahead of the pass in one call (instead of a page fault per
  // few pages) and release() drops it behind, so that the pages stay in the
  // page cache but not in this process's memory (a later read of `part`
  // maps them again); only the part of `part` in the mapping counts. Both do nothing for input
  // held in memory (gzip, standard input), whose bytes must stay.
  void populate(std::string_view part) const noexcept;
  void release(std::string_view part) const noexcept;
  // Copies the bytes of `part` of a mapped file into `out` by reading the
  // file, without mapping them: for a first pass that only looks at the
  // bytes (a second pass maps them once). False, with nothing promised in
  // `out`, for input held in memory or when the read fails.
  bool copy(std::string_view part, char* out) const noexcept;
  bool was_gzip() const noexcept { return gzip_; }
  const std::string& path() const noexcept { return path_; }

 private:
  FileBuffer() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
  bool gzip_ = false;
};

}  // namespace cubecal::io
