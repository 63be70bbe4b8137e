// Whole-file access: memory-mapped for plain files, inflated into memory for
// gzip (detected by its magic bytes, never by the file name).
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace cubecal::io {

class FileBuffer {
 public:
  // Throws InputError (file not found, unreadable, truncated/corrupt gzip).
  static FileBuffer open(const std::string& path);

  FileBuffer(FileBuffer&&) noexcept;
  FileBuffer& operator=(FileBuffer&&) noexcept;
  ~FileBuffer();

  std::string_view view() const noexcept;
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
