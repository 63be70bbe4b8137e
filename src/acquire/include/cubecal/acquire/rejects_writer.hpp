// The rejects file of a segment (rejects.csv): every malformed line or
// frame, bytes skipped while hunting for a frame's sync, and a partial line
// cut off a crashed chunk, with the host time it was received, why it was
// rejected and its bytes (the line CSV-quoted, its control bytes, bytes that
// are not UTF-8 and backslashes written as \xNN; a frame in hex):
//   host_mono_s,host_utc_s,reason,data
// Created at the first reject; flushed and synced with the chunks.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace cubecal::acquire {

namespace detail {
class AppendFile;
}

class RejectsWriter {
 public:
  // DIR/rejects.csv, created at the first add() (appended to when it exists).
  explicit RejectsWriter(std::string dir);
  ~RejectsWriter();

  void add(std::string_view prefix, std::string_view reason, std::string_view data, bool binary);
  void flush();
  void sync();
  void close();

  std::size_t count() const noexcept { return count_; }             // entries added by this writer
  std::size_t synced_count() const noexcept { return synced_; }     // of those, fsync'd
  void set_count(std::size_t n) noexcept { count_ = synced_ = n; }  // entries already in the file

 private:
  std::string dir_;
  std::unique_ptr<detail::AppendFile> file_;
  std::size_t count_ = 0, synced_ = 0;
};

// `s` as one CSV field: quoted, its quotes doubled.
void append_csv_quoted(std::string& out, std::string_view s);
void append_hex(std::string& out, std::string_view bytes);
// `s` as valid UTF-8 text of one line that decodes back to the same bytes:
// printable_text (control bytes and malformed UTF-8 as \xNN) with each
// backslash written as \x5c.
std::string escaped_text(std::string_view s);

}  // namespace cubecal::acquire
