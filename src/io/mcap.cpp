// MCAP (mcap.dev/spec): after the magic, records of op code (uint8), length
// (uint64 LE) and content: Header 0x01, Footer 0x02, Schema 0x03, Channel
// 0x04, Message 0x05, Chunk 0x06 (holding Schema, Channel and Message
// records), MessageIndex 0x07, ChunkIndex 0x08, ..., Statistics 0x0B,
// DataEnd 0x0F; unknown op codes are skipped by their length. The messages
// are read from the data section in file order; the summary section only
// repeats schemas and channels and gives counts.
#include "cubecal/io/mcap.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>

#include "cubecal/error.hpp"
#include "detail/file_buffer.hpp"
#include "detail/mcap_chunk.hpp"
#include "detail/message_source.hpp"
#include "detail/record_file.hpp"
#include "detail/ros1_record.hpp"

namespace cubecal::io {

namespace {

using detail::bag_error;
using detail::BagPlace;

constexpr const char* kRepair =
    "the MCAP file is truncated or corrupt: copy it again, or repair it with `mcap recover`";

enum Op : unsigned char {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kStatistics = 0x0B,
  kDataEnd = 0x0F,
};

std::uint32_t crc32_of(std::string_view bytes) {
  uLong crc = ::crc32(0L, Z_NULL, 0);
  while (!bytes.empty()) {
    const std::size_t n = std::min<std::size_t>(bytes.size(), 1u << 30);
    crc = ::crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(n));
    bytes.remove_prefix(n);
  }
  return static_cast<std::uint32_t>(crc);
}

// The fields of one record's content, each checked against the bytes left.
class Fields {
 public:
  Fields(std::string_view content, const BagPlace& at, std::size_t pos, const char* kind)
      : b_(content), at_(at), pos_(pos), kind_(kind) {}

  std::uint64_t u(std::size_t n, const char* what) {
    need(n, what);
    std::uint64_t v = 0;
    for (std::size_t k = n; k-- > 0;) v = v << 8 | static_cast<unsigned char>(b_[p_ + k]);
    p_ += n;
    return v;
  }
  std::uint16_t u16(const char* what) { return static_cast<std::uint16_t>(u(2, what)); }
  std::uint32_t u32(const char* what) { return static_cast<std::uint32_t>(u(4, what)); }
  std::uint64_t u64(const char* what) { return u(8, what); }
  // uint32 length + bytes (string, bytes, map).
  std::string_view bytes32(const char* what) { return take(u32(what), what); }
  std::string_view bytes64(const char* what) { return take(u64(what), what); }
  std::string_view rest() {
    const std::string_view r = b_.substr(p_);
    p_ = b_.size();
    return r;
  }
  std::size_t position() const { return pos_ + p_; }  // in the bytes the record was read from

 private:
  std::string_view take(std::uint64_t n, const char* what) {
    if (n > b_.size() - p_)
      bag_error(at_, pos_ + p_,
                std::string(kind_) + " record's " + what + " of " + std::to_string(n) +
                    " bytes runs past the record (" + std::to_string(b_.size() - p_) + " bytes left)");
    const std::string_view r = b_.substr(p_, static_cast<std::size_t>(n));
    p_ += static_cast<std::size_t>(n);
    return r;
  }
  void need(std::size_t n, const char* what) const {
    if (n > b_.size() - p_)
      bag_error(at_, pos_ + p_,
                std::string(kind_) + " record of " + std::to_string(b_.size()) + " bytes ends inside its " + what);
  }
  std::string_view b_;
  const BagPlace& at_;
  std::size_t pos_;
  const char* kind_;
  std::size_t p_ = 0;
};

struct Record {
  unsigned char op = 0;
  std::size_t offset = 0;  // of the op code, in the bytes read
  std::string_view content;
  std::size_t content_offset = 0;
};

// The record at `pos`; advances pos past it.
Record read_mcap_record(std::string_view bytes, std::size_t& pos, const BagPlace& at) {
  Record r;
  r.offset = pos;
  const std::size_t left = bytes.size() - pos;
  if (left < 9)
    bag_error(at, pos, "record cut short: " + std::to_string(left) + " bytes where an op code and length are");
  r.op = static_cast<unsigned char>(bytes[pos]);
  std::uint64_t len = 0;
  for (std::size_t k = 8; k > 0; --k) len = len << 8 | static_cast<unsigned char>(bytes[pos + k]);
  if (len > left - 9)
    bag_error(at, pos,
              "record (op code " + std::to_string(r.op) + ") of " + std::to_string(len) + " bytes runs past the end (" +
                  std::to_string(left - 9) + " bytes left)");
  r.content_offset = pos + 9;
  r.content = bytes.substr(r.content_offset, static_cast<std::size_t>(len));
  pos = r.content_offset + static_cast<std::size_t>(len);
  return r;
}

struct Schema {
  std::string name;
  std::string encoding;
};

struct Channel {
  std::uint32_t topic = 0;  // MessageLog topic
  std::uint16_t schema = 0;
  std::string name;
  std::string encoding;
};

class McapReader {
 public:
  explicit McapReader(const std::string& file) { log_.file = file; }

  MessageLog read(std::string_view bytes) {
    check_magic(bytes);
    std::size_t pos = kMcapMagic.size();
    while (pos < bytes.size()) record(bytes, pos, 0, [&](std::size_t end) { return crc32_of(bytes.substr(0, end)); });
    return finish();
  }

  void check_magic(std::string_view head) const {
    if (!looks_like_mcap(head))
      throw InputError(log_.file, 0, 0, "not an MCAP file: it does not start with the MCAP magic", kRepair);
  }

  // The record at `pos` of `bytes`, whose first byte is byte `base` of the
  // file (a streamed read passes one record at a time, a footer with the
  // bytes after it); advances pos. crc_before(offset): the CRC-32 of the
  // file's bytes before `offset`.
  template <class Crc>
  void record(std::string_view bytes, std::size_t& pos, std::size_t base, Crc&& crc_before) {
    const BagPlace top{&log_.file, base, {}, kRepair};
    const Record r = read_mcap_record(bytes, pos, top);
    if (first_ && r.op != kHeader) bag_error(top, r.offset, "the first record is not a header (op code 1)");
    first_ = false;
    base_ = base;
    switch (r.op) {
      case kHeader: break;
      case kSchema: schema(r, top); break;
      case kChannel: channel(r, top); break;
      case kMessage:
        if (!data_section_) bag_error(top, r.offset, "message record after the data end record");
        message(r, top, MessagePlace::byte, base + r.offset);
        break;
      case kChunk:
        if (!data_section_) bag_error(top, r.offset, "chunk record after the data end record");
        chunk(r, top);
        break;
      case kStatistics: statistics(r, top); break;
      case kDataEnd: {
        Fields f(r.content, top, r.content_offset, "data end");
        const std::uint32_t crc = f.u32("data_section_crc");
        if (crc != 0 && crc != crc_before(base + r.offset))
          bag_error(top, r.offset, "the data section's CRC does not match its bytes");
        data_section_ = false;
        break;
      }
      case kFooter:
        if (bytes.size() - pos != kMcapMagic.size() || bytes.substr(pos) != kMcapMagic)
          bag_error(top, pos, "the footer is not followed by the closing magic and the end of the file");
        pos = bytes.size();
        break;
      default: break;  // message index, chunk index, attachments, metadata...: not needed
    }
  }

  // After the last record.
  MessageLog finish() {
    if (first_) bag_error({&log_.file, 0, {}, kRepair}, kMcapMagic.size(), "no header record");
    for (const auto& [id, c] : channels_) {
      const auto counted = counted_.find(id);
      if (counted == counted_.end()) continue;
      LogTopic& t = log_.topics[c.topic];
      t.counted = t.counted.value_or(0) + counted->second;
    }
    return std::move(log_);
  }

  MessageLog& log() noexcept { return log_; }

 private:
  void schema(const Record& r, const BagPlace& at) {
    Fields f(r.content, at, r.content_offset, "schema");
    const std::uint16_t id = f.u16("id");
    const std::string_view name = f.bytes32("name");
    const std::string_view encoding = f.bytes32("encoding");
    f.bytes32("data");
    if (id == 0) bag_error(at, r.offset, "schema record of id 0 (which means no schema)");
    const auto it = schemas_.find(id);
    if (it != schemas_.end()) {
      if (it->second.name != name || it->second.encoding != encoding)
        bag_error(at, r.offset,
                  "schema " + std::to_string(id) + " declared again as another type (" + std::string(name) + ")");
      return;
    }
    schemas_[id] = {std::string(name), std::string(encoding)};
  }

  void channel(const Record& r, const BagPlace& at) {
    Fields f(r.content, at, r.content_offset, "channel");
    const std::uint16_t id = f.u16("id");
    const std::uint16_t schema_id = f.u16("schema_id");
    const std::string topic(f.bytes32("topic"));
    const std::string encoding(f.bytes32("message_encoding"));
    f.bytes32("metadata");
    const auto known = channels_.find(id);
    if (known != channels_.end()) {
      if (known->second.name != topic || known->second.schema != schema_id || known->second.encoding != encoding)
        bag_error(at, r.offset,
                  "channel " + std::to_string(id) + " declared again with another topic or schema (" + topic + ")");
      return;
    }
    std::string type;
    if (schema_id != 0) {
      const auto s = schemas_.find(schema_id);
      if (s == schemas_.end())
        bag_error(at, r.offset,
                  "channel " + std::to_string(id) + " (" + topic + ") of schema " + std::to_string(schema_id) +
                      ", which no record declared before");
      type = s->second.name;
    }
    Channel c;
    c.name = topic;
    c.schema = schema_id;
    c.encoding = encoding;
    try {
      c.topic = log_.topic(topic, type, encoding);
    } catch (const InputError&) {
      bag_error(at, r.offset,
                "channel " + std::to_string(id) + " declares topic " + topic + " as " + type + " (" + encoding +
                    "), another channel as " + log_.topics[find_topic(topic)].type + " (" +
                    log_.topics[find_topic(topic)].encoding + ")");
    }
    channels_[id] = c;
  }

  std::size_t find_topic(const std::string& name) const {
    for (std::size_t i = 0; i < log_.topics.size(); ++i)
      if (log_.topics[i].name == name) return i;
    return 0;
  }

  void message(const Record& r, const BagPlace& at, MessagePlace place, std::size_t offset) {
    Fields f(r.content, at, r.content_offset, "message");
    const std::uint16_t id = f.u16("channel_id");
    f.u32("sequence");
    const std::uint64_t log_time = f.u64("log_time");
    f.u64("publish_time");
    const std::string_view data = f.rest();
    const auto c = channels_.find(id);
    if (c == channels_.end())
      bag_error(at, r.offset, "message on channel " + std::to_string(id) + ", which no record declared before");
    LogMessage m;
    m.topic = c->second.topic;
    m.place = place;
    m.offset = offset;
    m.sec = static_cast<std::int64_t>(log_time / 1000000000u);
    m.nsec = static_cast<std::uint32_t>(log_time % 1000000000u);
    m.begin = log_.payload.size();
    m.size = data.size();
    log_.payload.append(data);
    log_.messages.push_back(m);
    ++log_.topics[m.topic].messages;
  }

  void chunk(const Record& r, const BagPlace& top) {
    Fields f(r.content, top, r.content_offset, "chunk");
    f.u64("message_start_time");
    f.u64("message_end_time");
    const std::uint64_t size = f.u64("uncompressed_size");
    const std::uint32_t crc = f.u32("uncompressed_crc");
    const std::string_view compression = f.bytes32("compression");
    const std::size_t records_at = f.position() + 8;
    const std::string_view records = f.bytes64("records");
    if (size > SIZE_MAX / 2) bag_error(top, r.offset, "chunk of " + std::to_string(size) + " uncompressed bytes");
    const std::string plain =
        detail::decompress_mcap_chunk(compression, records, static_cast<std::size_t>(size), top, r.offset);
    if (crc != 0 && crc != crc32_of(plain))
      bag_error(top, r.offset, "the chunk's CRC does not match its " + std::to_string(plain.size()) + " bytes");
    const bool compressed = !compression.empty();
    const BagPlace inner{
        &log_.file, compressed ? 0 : base_ + records_at,
        compressed ? " of the " + std::string(compression) + " chunk at byte " + std::to_string(base_ + r.offset)
                   : std::string(),
        kRepair};
    std::size_t pos = 0;
    while (pos < plain.size()) {
      const Record m = read_mcap_record(plain, pos, inner);
      switch (m.op) {
        case kSchema: schema(m, inner); break;
        case kChannel: channel(m, inner); break;
        case kMessage:
          message(m, inner, compressed ? MessagePlace::chunk : MessagePlace::byte,
                  base_ + (compressed ? r.offset : records_at + m.offset));
          break;
        default: bag_error(inner, m.offset, "record of op code " + std::to_string(m.op) + " inside a chunk");
      }
    }
  }

  void statistics(const Record& r, const BagPlace& at) {
    Fields f(r.content, at, r.content_offset, "statistics");
    f.u64("message_count");
    f.u16("schema_count");
    f.u32("channel_count");
    f.u32("attachment_count");
    f.u32("metadata_count");
    f.u32("chunk_count");
    f.u64("message_start_time");
    f.u64("message_end_time");
    const std::size_t map_at = f.position() + 4;
    const std::string_view counts = f.bytes32("channel_message_counts");
    if (counts.size() % 10 != 0)
      bag_error(at, map_at,
                "channel_message_counts of " + std::to_string(counts.size()) +
                    " bytes, not a whole number of (uint16, uint64) entries");
    Fields e(counts, at, map_at, "statistics");
    while (e.position() < map_at + counts.size()) {
      const std::uint16_t id = e.u16("channel id");
      counted_[id] = e.u64("message count");
    }
  }

  MessageLog log_;
  std::map<std::uint16_t, Schema> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  std::map<std::uint16_t, std::uint64_t> counted_;
  std::size_t base_ = 0;  // file offset of the bytes being read
  bool first_ = true;     // no record read yet
  bool data_section_ = true;
};

// A file read one top-level record (a chunk) at a time; the data section's
// CRC, when the file has one, computed as the records go by.
class McapSource final : public detail::MessageSource {
 public:
  explicit McapSource(const std::string& path) : file_(path), reader_(path) {
    total_bytes = file_.size();
    file_.read(0, kMcapMagic.size(), buf_);
    reader_.check_magic(buf_);
    crc_ = static_cast<std::uint32_t>(
        ::crc32(::crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(buf_.data()), static_cast<uInt>(buf_.size())));
    pos_ = buf_.size();
  }

  bool next(MessageLog& batch) override {
    while (pos_ < file_.size()) {
      const std::size_t left = file_.size() - pos_;
      const std::uint64_t len = file_.le(pos_ + 1, 8, 0);
      std::uint64_t want = std::min<std::uint64_t>(9 + len, left);
      // A footer is read with what follows it (the closing magic, and the
      // end of the file).
      if (file_.le(pos_, 1, 0) == kFooter) want = std::min<std::uint64_t>(left, want + 64);
      file_.read(pos_, static_cast<std::size_t>(want), buf_);
      std::size_t at = 0;
      reader_.record(buf_, at, pos_, [&](std::size_t) { return crc_; });
      for (std::string_view rest(buf_.data(), std::min(at, buf_.size())); !rest.empty();) {
        const std::size_t n = std::min<std::size_t>(rest.size(), 1u << 30);
        crc_ = static_cast<std::uint32_t>(
            ::crc32(crc_, reinterpret_cast<const Bytef*>(rest.data()), static_cast<uInt>(n)));
        rest.remove_prefix(n);
      }
      pos_ += at;
      bytes_read = pos_;
      MessageLog& log = reader_.log();
      if (log.messages.empty()) continue;
      batch.file = log.file;
      batch.topics = log.topics;
      batch.messages.clear();
      batch.payload.clear();
      batch.messages.swap(log.messages);
      batch.payload.swap(log.payload);
      return true;
    }
    if (!done_) (void)reader_.finish();
    done_ = true;
    return false;
  }

 private:
  detail::RecordFile file_;
  McapReader reader_;
  std::size_t pos_ = 0;
  std::uint32_t crc_ = 0;  // of the bytes before pos_
  std::string buf_;
  bool done_ = false;
};

}  // namespace

std::unique_ptr<detail::MessageSource> detail::open_mcap_source(const std::string& path) {
  return std::make_unique<McapSource>(path);
}

bool looks_like_mcap(std::string_view head) noexcept { return head.starts_with(kMcapMagic); }

MessageLog parse_mcap(std::string_view bytes, const std::string& file) { return McapReader(file).read(bytes); }

MessageLog read_mcap(const std::string& path) {
  const FileBuffer buf = FileBuffer::open(path, Content::series);
  return parse_mcap(buf.view(), path);
}

}  // namespace cubecal::io
