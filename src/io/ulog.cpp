// The message layer of a ULog file: a 16-byte header (magic, version, start
// time), then messages of a 3-byte header (uint16 size, uint8 type) and
// `size` bytes, all little-endian. See
// https://docs.px4.io/main/en/dev_log/ulog_file_format.html
#include "cubecal/io/ulog.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <unordered_map>

#include "cubecal/error.hpp"
#include "detail/ulog_format.hpp"

namespace cubecal::io {

namespace {

constexpr std::size_t kHeaderBytes = 16;
constexpr const char* kHint = "the log is truncated or corrupt: copy it again from the vehicle's SD card";

// Incompatible flag bit 0 of byte 0: data appended after the logged data,
// from the offsets of the 'B' message on.
constexpr unsigned kDataAppended = 1;

[[noreturn]] void fail(const std::string& file, std::size_t at, const std::string& what,
                       const std::string& hint = kHint) {
  throw InputError(file, 0, 0, "byte " + std::to_string(at) + ": " + what, hint);
}

std::uint16_t le16(const char* p) noexcept {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint16_t>(u[0] | u[1] << 8);
}

std::uint64_t le64(const char* p) noexcept {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | u[i];
  return v;
}

std::string type_name(char t) {
  if (t >= 0x21 && t <= 0x7e) return std::string("'") + t + "'";
  return "0x" + std::string(1, "0123456789abcdef"[(t >> 4) & 0xf]) + "0123456789abcdef"[t & 0xf];
}

class Parser {
 public:
  Parser(std::string_view bytes, const std::string& file) : b_(bytes) { log_.file = file; }

  ULog run() {
    header();
    std::size_t pos = kHeaderBytes;
    // Without appended data: one stretch to the end of the file. With it,
    // the logged data end where the first appended data begin; a message
    // cut there (the logger was writing it when it stopped) is dropped.
    std::vector<std::size_t> ends;
    bool first = true;
    while (pos < b_.size()) {
      if (!ends.empty() && pos >= ends.front()) {
        pos = ends.front();
        ends.erase(ends.begin());
        if (pos >= b_.size()) break;
      }
      const std::size_t end = ends.empty() ? b_.size() : ends.front();
      if (end - pos < 3) {
        if (end != b_.size()) {
          pos = end;
          continue;
        }
        fail(log_.file, pos, "message header cut short: " + std::to_string(end - pos) + " bytes where 3 are");
      }
      const std::size_t size = le16(b_.data() + pos);
      const char type = b_[pos + 2];
      if (size > end - pos - 3) {
        if (end != b_.size()) {
          pos = end;
          continue;
        }
        fail(log_.file, pos,
             "message " + type_name(type) + " of " + std::to_string(size) + " bytes runs past the end of the file (" +
                 std::to_string(end - pos - 3) + " bytes left)");
      }
      const std::string_view body = b_.substr(pos + 3, size);
      if (type == 'B') {
        if (!first) fail(log_.file, pos, "flag bits message ('B') after other messages: it must come first");
        ends = flags(pos, body);
      }
      message(pos, type, body);
      first = false;
      pos += 3 + size;
    }
    finish();
    return std::move(log_);
  }

 private:
  void header() {
    if (b_.size() < kHeaderBytes)
      fail(log_.file, 0, "file header cut short: " + std::to_string(b_.size()) + " bytes where 16 are");
    if (!looks_like_ulog(b_)) fail(log_.file, 0, "not a ULog file (no 'ULog' magic bytes)", "give a PX4 .ulg log");
    log_.version = static_cast<unsigned char>(b_[7]);
    if (log_.version > 1)
      fail(log_.file, 7, "ULog version " + std::to_string(log_.version) + ": cubecal reads versions 0 and 1",
           "convert the log with a newer tool (pyulog) or report the version");
    log_.start_us = le64(b_.data() + 8);
  }

  // The 'B' message: compatible and incompatible flags, and where appended
  // data begin. Returns the ends of the stretches to read.
  std::vector<std::size_t> flags(std::size_t pos, std::string_view body) {
    if (body.size() < 40)
      fail(log_.file, pos, "flag bits message ('B') of " + std::to_string(body.size()) + " bytes, not 40");
    const auto* incompat = reinterpret_cast<const unsigned char*>(body.data() + 8);
    for (std::size_t i = 0; i < 8; ++i) {
      const unsigned unknown = i == 0 ? incompat[i] & ~kDataAppended : incompat[i];
      if (unknown != 0)
        fail(log_.file, pos + 3 + 8 + i,
             "incompatible flag bits 0x" + std::string(1, "0123456789abcdef"[unknown >> 4]) +
                 "0123456789abcdef"[unknown & 0xf] + " in byte " + std::to_string(i) +
                 " of the flags: the log holds data cubecal cannot read",
             "the log was written by a newer PX4 logger: convert it (pyulog's ulog2csv) or report the flags");
    }
    std::vector<std::size_t> ends;
    if ((incompat[0] & kDataAppended) == 0) return ends;
    log_.appended_data = true;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t off = le64(body.data() + 16 + 8 * k);
      if (off == 0) continue;
      if (off <= pos + 3 + body.size() || off > b_.size() || (!ends.empty() && off <= ends.back()))
        fail(log_.file, pos + 3 + 16 + 8 * k,
             "appended data offset " + std::to_string(off) + " lies outside the file's " + std::to_string(b_.size()) +
                 " bytes or before the data",
             "the log is corrupt or cut short: appended data the flags announce are not there");
      ends.push_back(static_cast<std::size_t>(off));
    }
    return ends;
  }

  // A key-value message ('I', 'M', 'P', 'Q'): a key of key_len bytes
  // ("type name") after `skip` bytes, then the value.
  void key_value(std::size_t pos, std::string_view body, std::size_t skip, const char* what) {
    if (body.size() < skip + 1) fail(log_.file, pos, std::string(what) + " message cut short");
    const std::size_t key_len = static_cast<unsigned char>(body[skip]);
    if (key_len > body.size() - skip - 1)
      fail(log_.file, pos,
           std::string(what) + " message's key of " + std::to_string(key_len) + " bytes runs past its " +
               std::to_string(body.size()) + " bytes");
  }

  void message(std::size_t pos, char type, std::string_view body) {
    switch (type) {
      case 'B': break;
      case 'F': {
        std::string error;
        ULogFormat f = detail::parse_ulog_format(body, error);
        if (!error.empty()) fail(log_.file, pos, error);
        if (!format_index_.emplace(f.name, log_.formats.size()).second)
          fail(log_.file, pos, "format " + f.name + " defined twice");
        format_offsets_.push_back(pos);
        log_.formats.push_back(std::move(f));
        break;
      }
      case 'I':
        key_value(pos, body, 0, "information ('I')");
        ++log_.info_messages;
        break;
      case 'M':
        key_value(pos, body, 1, "information ('M')");
        ++log_.info_messages;
        break;
      case 'P':
        key_value(pos, body, 0, "parameter ('P')");
        ++log_.parameter_messages;
        break;
      case 'Q':
        key_value(pos, body, 1, "default parameter ('Q')");
        ++log_.parameter_messages;
        break;
      case 'A': {
        if (body.size() < 4)
          fail(log_.file, pos, "add-logged-message ('A') of " + std::to_string(body.size()) + " bytes");
        const auto multi_id = static_cast<std::uint8_t>(body[0]);
        const std::uint16_t msg_id = le16(body.data() + 1);
        std::string_view name = body.substr(3);
        while (!name.empty() && name.back() == '\0') name.remove_suffix(1);
        if (active(msg_id) != nullptr)
          fail(log_.file, pos, "msg_id " + std::to_string(msg_id) + " added twice without being removed");
        const auto [it, added] = topic_index_.emplace(std::make_pair(std::string(name), multi_id), log_.topics.size());
        if (added) {
          ULogTopic t;
          t.name = std::string(name);
          t.multi_id = multi_id;
          log_.topics.push_back(std::move(t));
          topic_offsets_.push_back(pos);
        }
        ids_[msg_id] = static_cast<std::int32_t>(it->second);
        break;
      }
      case 'R': {
        if (body.size() < 2) fail(log_.file, pos, "remove-logged-message ('R') cut short");
        const std::uint16_t msg_id = le16(body.data());
        if (active(msg_id) == nullptr)
          fail(log_.file, pos, "msg_id " + std::to_string(msg_id) + " removed but never added");
        ids_[msg_id] = -1;
        break;
      }
      case 'D': {
        if (body.size() < 2) fail(log_.file, pos, "data message ('D') of " + std::to_string(body.size()) + " bytes");
        const std::uint16_t msg_id = le16(body.data());
        const std::int32_t* topic = active(msg_id);
        if (topic == nullptr)
          fail(log_.file, pos, "data message for msg_id " + std::to_string(msg_id) + ", which no 'A' message added");
        log_.topics[static_cast<std::size_t>(*topic)].messages.push_back({pos, pos + 5, body.size() - 2});
        break;
      }
      case 'L':
        if (body.size() < 9) fail(log_.file, pos, "logging message ('L') cut short");
        ++log_.logging_messages;
        break;
      case 'C':
        if (body.size() < 11) fail(log_.file, pos, "tagged logging message ('C') cut short");
        ++log_.logging_messages;
        break;
      case 'S':
        if (body.size() < 8) fail(log_.file, pos, "sync message ('S') cut short");
        ++log_.sync_messages;
        break;
      case 'O':
        if (body.size() < 2) fail(log_.file, pos, "dropout message ('O') cut short");
        log_.dropouts.push_back({pos, le16(body.data())});
        break;
      default:
        ++log_.skipped_messages;  // a type newer than this reader: its size says where the next one is
        break;
    }
  }

  // Lays out the formats and checks every topic's format and data sizes.
  void finish() {
    std::string error;
    const std::size_t bad = detail::lay_out_ulog_formats(log_.formats, error);
    if (bad != log_.formats.size()) fail(log_.file, format_offsets_[bad], error);
    for (std::size_t i = 0; i < log_.topics.size(); ++i) {
      ULogTopic& t = log_.topics[i];
      const auto found = format_index_.find(t.name);
      if (found == format_index_.end())
        fail(log_.file, topic_offsets_[i], "topic " + t.label() + " has no format definition ('F')");
      t.format = found->second;
      const ULogFormat* f = &log_.formats[t.format];
      for (const auto& m : t.messages) {
        if (m.size >= f->logged_size && m.size <= f->size) continue;
        fail(log_.file, m.offset,
             "data message of " + t.label() + " holds " + std::to_string(m.size) + " bytes; its format " + f->name +
                 " has " +
                 (f->logged_size == f->size ? std::to_string(f->size)
                                            : std::to_string(f->logged_size) + " to " + std::to_string(f->size)));
      }
    }
  }

  // The topic of an added msg_id, or null.
  const std::int32_t* active(std::uint16_t msg_id) const { return ids_[msg_id] < 0 ? nullptr : &ids_[msg_id]; }

  std::string_view b_;
  ULog log_;
  // Per msg_id, the index of its topic while added (and not removed), else -1;
  // lookups by index and name (a hostile log may hold 65536 ids and as many formats).
  std::vector<std::int32_t> ids_ = std::vector<std::int32_t>(65536, -1);
  std::map<std::pair<std::string, std::uint8_t>, std::size_t> topic_index_;
  std::unordered_map<std::string, std::size_t> format_index_;
  std::vector<std::size_t> format_offsets_;  // where each format was defined
  std::vector<std::size_t> topic_offsets_;   // where each topic was first added
};

}  // namespace

bool looks_like_ulog(std::string_view head) noexcept { return head.starts_with(kULogMagic); }

const ULogField* ULogFormat::field(std::string_view n) const noexcept {
  for (const auto& f : fields)
    if (f.name == n) return &f;
  return nullptr;
}

std::string ULogTopic::label() const { return multi_id == 0 ? name : name + ":" + std::to_string(multi_id); }

const ULogFormat* ULog::format(std::string_view name) const noexcept {
  for (const auto& f : formats)
    if (f.name == name) return &f;
  return nullptr;
}

std::size_t ULog::dropped_ms() const noexcept {
  std::size_t ms = 0;
  for (const auto& d : dropouts) ms += d.duration_ms;
  return ms;
}

ULog parse_ulog(std::string_view bytes, const std::string& file) { return Parser(bytes, file).run(); }

}  // namespace cubecal::io
