#include "binary_input.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "cubecal/error.hpp"

namespace cubecal::io::detail {

namespace {

constexpr const char* kReads =
    "cubecal reads delimited text (CSV, TSV or whitespace-separated, plain or gzip-compressed), NumPy .npy, "
    "and raw interleaved binary described by {binary} TYPE,TYPE,...";

struct Signature {
  std::string_view magic;
  const char* what;
  const char* hint;  // what to do instead; null: check the file name
};

using namespace std::string_view_literals;

// Formats met where a text log is expected. Only signatures that text cannot
// start with (a byte text does not hold, or a long fixed phrase).
constexpr Signature kSignatures[] = {
    {"\x7f"
     "ELF"sv,
     "an ELF executable or library", nullptr},
    {"\xcf\xfa\xed\xfe"sv, "a Mach-O executable", nullptr},
    {"\x1f\x8b"sv, "gzip data inside gzip (compressed twice?)", "decompress it once with gunzip"},
    {"\xfd"
     "7zXZ\0"sv,
     "an xz-compressed file", "decompress it first (xz -d), or recompress it with gzip"},
    {"\x28\xb5\x2f\xfd"sv, "a zstd-compressed file", "decompress it first (zstd -d), or recompress it with gzip"},
    {"BZh"sv, nullptr, nullptr},  // bzip2: checked with its block magic below
    {"PK\x03\x04"sv, "a zip archive (or an .xlsx/.ods spreadsheet)", "unpack it, or export the sheet as CSV"},
    {"7z\xbc\xaf\x27\x1c"sv, "a 7-Zip archive", "unpack it first"},
    {"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"sv, "an old Office document (.xls?)", "export the sheet as CSV"},
    {"#ROSBAG V"sv, "a ROS 1 bag", "export the topic as CSV, e.g. rostopic echo -b FILE -p /imu > imu.csv"},
    {"\x89MCAP"sv, "an MCAP file (ROS 2 bag)", "export the topic as CSV first"},
    {"SQLite format 3\0"sv, "an SQLite database (a ROS 2 .db3 bag?)", "export the topic as CSV first"},
    {"\x89HDF\r\n\x1a\n"sv, "an HDF5 file (or MATLAB v7.3 .mat)", "export the data as CSV first"},
    {"MATLAB 5.0 MAT-file"sv, "a MATLAB .mat file", "export the data as CSV first, e.g. with writematrix"},
    {"\x93NUMPY"sv, "a NumPy .npy file", "write it as text first, e.g. with numpy.savetxt"},
    {"\x89PNG\r\n\x1a\n"sv, "a PNG image", nullptr},
    {"\xff\xd8\xff"sv, "a JPEG image", nullptr},
    {"%PDF-"sv, "a PDF document", nullptr},
    {"\xd4\xc3\xb2\xa1"sv, "a pcap capture", nullptr},
    {"\xa1\xb2\xc3\xd4"sv, "a pcap capture", nullptr},
    {"\x0a\x0d\x0d\x0a"sv, "a pcapng capture", nullptr},
    {"\xff\xfe"sv, "UTF-16 text", "save it as UTF-8, e.g. iconv -f UTF-16 -t UTF-8 FILE > out.csv"},
    {"\xfe\xff"sv, "UTF-16 text", "save it as UTF-8, e.g. iconv -f UTF-16 -t UTF-8 FILE > out.csv"},
};

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

const Signature* signature_of(std::string_view head) {
  for (const Signature& s : kSignatures) {
    if (!starts_with(head, s.magic)) continue;
    if (s.what != nullptr) return &s;
    // "BZh" + block size '1'..'9' + the block magic (the digits of pi).
    static constexpr Signature kBzip2{"BZh"sv, "a bzip2-compressed file",
                                      "decompress it first (bunzip2), or recompress it with gzip"};
    if (head.size() >= 10 && head[3] >= '1' && head[3] <= '9' && head.substr(4, 6) == "\x31\x41\x59\x26\x53\x59"sv)
      return &kBzip2;
  }
  return nullptr;
}

std::string hex_byte(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", c);
  return buf;
}

std::string offset_text(std::size_t offset, bool decompressed) {
  return "byte offset " + std::to_string(offset) + (decompressed ? " of the decompressed text" : "");
}

// UTF-16 without a byte-order mark: in ASCII text every other byte is NUL.
bool looks_like_utf16(std::string_view head) {
  const std::size_t n = std::min<std::size_t>(head.size() & ~std::size_t{1}, 256);
  if (n < 8) return false;
  for (std::size_t parity = 0; parity < 2; ++parity) {
    bool ok = true;
    for (std::size_t i = 0; i < n && ok; i += 2) {
      const auto zero = static_cast<unsigned char>(head[i + parity]);
      const auto text = static_cast<unsigned char>(head[i + 1 - parity]);
      ok = zero == 0 && text >= 0x09 && text < 0x80;
    }
    if (ok) return true;
  }
  return false;
}

// Bytes that are no part of a well-formed UTF-8 sequence.
std::size_t invalid_utf8_bytes(std::string_view s) {
  std::size_t bad = 0;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t len = c < 0x80                ? 1
                      : c >= 0xc2 && c < 0xe0 ? 2
                      : c >= 0xe0 && c < 0xf0 ? 3
                      : c >= 0xf0 && c < 0xf5 ? 4
                                              : 0;
    bool ok = len != 0 && i + len <= s.size();
    for (std::size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(s[i + k]) & 0xc0) == 0x80;
    if (ok) {
      i += len;
    } else {
      ++bad;
      ++i;
    }
  }
  return bad;
}

// A start free of control bytes that is still no text: no line break in a
// whole probe (a file of 0xff bytes, compressed or encrypted data without a
// known signature), or mostly bytes that are not UTF-8 (a Latin-1 degree
// sign here and there is fine).
void check_text_like(std::string_view head, const std::string& file, bool decompressed) {
  const char* what = nullptr;
  if (head.size() == kTextProbeBytes && head.find_first_of("\n\r") == std::string_view::npos)
    what = "no line break in its first ";
  else if (invalid_utf8_bytes(head) * 16 > head.size())
    what = "mostly bytes that are not text (nor UTF-8) in its first ";
  if (what == nullptr) return;
  throw InputError(file, 0, 0,
                   "not a text or known binary format: " + std::string(what) + std::to_string(head.size()) + " bytes" +
                       (decompressed ? " of decompressed data" : ""),
                   "a raw binary log? give its layout with {binary} TYPE,TYPE,... (e.g. int16le,int16le,int16le) "
                   "and {rate}; " +
                       std::string(kReads));
}

}  // namespace

const char* find_binary_byte(const char* begin, const char* end) noexcept {
  for (const char* p = begin; p < end; ++p) {
    const auto c = static_cast<unsigned char>(*p);
    if ((c < 0x20 && (c < 0x09 || c > 0x0d)) || c == 0x7f) return p;
  }
  return nullptr;
}

void check_text_start(std::string_view head, const std::string& file, bool decompressed) {
  head = head.substr(0, std::min(head.size(), kTextProbeBytes));
  if (head.empty()) return;  // (an empty text's data() may be null)
  if (!decompressed && starts_with(head, "\x1f\x8b"sv)) {
    throw InputError(file, 0, 0, "not a text or known binary format: it looks like gzip data",
                     "cubecal decompresses a gzip file it reads from disk; give the file itself");
  }
  if (const Signature* s = signature_of(head)) {
    throw InputError(file, 0, 0, std::string("not a text or known binary format: it looks like ") + s->what,
                     std::string(s->hint != nullptr ? s->hint : "check the file name") + "; " + kReads);
  }
  // Lines ended by CR alone (classic Mac OS text) would read as one line
  // and give a misleading error about its first field.
  if (std::memchr(head.data(), '\n', head.size()) == nullptr) {
    if (const auto* cr = static_cast<const char*>(std::memchr(head.data(), '\r', head.size()));
        cr != nullptr && cr + 1 < head.data() + head.size()) {
      throw InputError(file, 1, 0,
                       "lines end in a carriage return alone (classic Mac OS text); cubecal reads lines "
                       "ending in LF or CR LF",
                       "convert it, e.g. tr '\\r' '\\n' < " + file + " > out.csv");
    }
  }
  const auto* nul = static_cast<const char*>(std::memchr(head.data(), '\0', head.size()));
  if (nul == nullptr) {
    check_text_like(head, file, decompressed);
    return;
  }
  if (looks_like_utf16(head)) {
    throw InputError(file, 0, 0, "not a text or known binary format: it looks like UTF-16 text",
                     "save it as UTF-8, e.g. iconv -f UTF-16LE -t UTF-8 FILE > out.csv");
  }
  const std::size_t zeros =
      static_cast<std::size_t>(std::find_if(head.begin(), head.end(), [](char c) { return c != '\0'; }) - head.begin());
  if (zeros == head.size()) {
    throw InputError(
        file, 1, 1,
        "not a text or known binary format: its first " + std::to_string(zeros) + " bytes are all NUL (zero) bytes",
        "a file that was allocated but never written, e.g. by a logger that lost power? " + std::string(kReads));
  }
  std::size_t line = 1;
  const char* line_begin = head.data();
  for (const char* c = head.data(); c < nul; ++c) {
    if (*c == '\n') {
      ++line;
      line_begin = c + 1;
    }
  }
  std::size_t column = 1;
  for (const char* c = line_begin; c < nul; ++c) column += (static_cast<unsigned char>(*c) & 0xc0) != 0x80;
  throw InputError(file, line, column,
                   "not a text or known binary format: NUL byte at " +
                       offset_text(static_cast<std::size_t>(nul - head.data()), decompressed),
                   "a binary log, or a file cut short by a crash? " + std::string(kReads));
}

void throw_binary_byte(std::string_view text, const char* where, const std::string& file, std::size_t line,
                       std::size_t column, std::size_t offset_base) {
  const auto c = static_cast<unsigned char>(*where);
  const std::string what = c == 0 ? std::string("NUL byte") : "control byte " + hex_byte(c);
  throw InputError(file, line, column,
                   what + " at byte offset " +
                       std::to_string(offset_base + static_cast<std::size_t>(where - text.data())) +
                       ": binary data, not text",
                   "a binary log, or a file cut short by a crash? " + std::string(kReads));
}

}  // namespace cubecal::io::detail
