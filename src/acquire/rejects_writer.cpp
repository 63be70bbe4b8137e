// The rejects file (rejects_writer.hpp).
#include "cubecal/acquire/rejects_writer.hpp"

#include <sys/stat.h>

#include <algorithm>

#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/printable_text.hpp"
#include "detail/append_file.hpp"

namespace cubecal::acquire {

void append_csv_quoted(std::string& out, std::string_view s) {
  out.push_back('"');
  for (const char c : s) {
    if (c == '"') out.push_back('"');
    out.push_back(c);
  }
  out.push_back('"');
}

void append_hex(std::string& out, std::string_view bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  for (const char c : bytes) {
    const auto b = static_cast<unsigned char>(c);
    out.push_back(kDigits[b >> 4]);
    out.push_back(kDigits[b & 15]);
  }
}

std::string escaped_text(std::string_view s) {
  // printable_text's \xNN, and the backslash itself as \x5c so that the
  // field decodes back to the exact bytes.
  std::string out;
  for (std::size_t b = 0; b <= s.size();) {
    const std::size_t slash = std::min(s.find('\\', b), s.size());
    out += printable_text(s.substr(b, slash - b));
    if (slash < s.size()) out += "\\x5c";
    b = slash + 1;
  }
  return out;
}

RejectsWriter::RejectsWriter(std::string dir) : dir_(std::move(dir)) {}
RejectsWriter::~RejectsWriter() = default;

void RejectsWriter::add(std::string_view prefix, std::string_view reason, std::string_view data, bool binary) {
  if (!file_) {
    const std::string path = dir_ + "/" + std::string(io::kRejectsName);
    struct stat st {};
    const bool exists = ::lstat(path.c_str(), &st) == 0;  // a link is then refused by AppendFile
    file_ = std::make_unique<detail::AppendFile>(path, exists, 64 << 10);
    if (!exists) file_->append("host_mono_s,host_utc_s,reason,data\n");
  }
  std::string& b = file_->buffer();
  b.append(prefix);
  append_csv_quoted(b, reason);
  b.push_back(',');
  if (binary)
    append_hex(b, data);
  else
    append_csv_quoted(b, escaped_text(data));
  b.push_back('\n');
  ++count_;
  file_->maybe_flush();
}

void RejectsWriter::flush() {
  if (file_) file_->flush();
}

void RejectsWriter::sync() {
  if (file_) file_->sync();
  synced_ = count_;
}

void RejectsWriter::close() {
  if (file_) file_->close();
  file_.reset();
  synced_ = count_;
}

}  // namespace cubecal::acquire
