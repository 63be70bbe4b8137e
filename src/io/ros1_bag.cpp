// ROS 1 bag format 2.0 (wiki.ros.org/Bags/Format/2.0): after the magic line,
// records of op codes bag header 0x03, chunk 0x05 (holding connection 0x07
// and message data 0x02 records), index data 0x04, connection 0x07 (again,
// after the chunks) and chunk info 0x06. The messages are read from the
// chunks in file order; the index is only counted, for a cross-check.
#include "cubecal/io/ros1_bag.hpp"

#include <algorithm>

#include "cubecal/error.hpp"
#include "detail/file_buffer.hpp"
#include "detail/message_source.hpp"
#include "detail/record_file.hpp"
#include "detail/ros1_chunk.hpp"
#include "detail/ros1_record.hpp"

namespace cubecal::io {

namespace {

using detail::bag_error;
using detail::BagPlace;
using detail::BagRecord;
using detail::le32;

enum Op : unsigned char {
  kMessageData = 0x02,
  kBagHeader = 0x03,
  kIndexData = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07,
};

unsigned char op_of(const BagRecord& r, const BagPlace& at) {
  const std::string_view op = detail::required_field(r, "op", 1, at, "a");
  return static_cast<unsigned char>(op[0]);
}

class BagReader {
 public:
  explicit BagReader(const std::string& file) { bag_.file = file; }

  Ros1Bag read(std::string_view bytes) {
    const BagPlace top{&bag_.file, 0, {}};
    if (!bytes.starts_with(kRos1BagMagic)) {
      const std::size_t eol = bytes.find('\n');
      const std::string version(bytes.substr(0, std::min<std::size_t>(eol, 32)));
      throw InputError(bag_.file, 0, 0, "'" + version + "' is not a ROS bag of format 2.0",
                       "migrate it with `rosbag fix` on a ROS 1 install");
    }
    std::size_t pos = kRos1BagMagic.size();
    while (pos < bytes.size()) record(bytes, pos);
    finish();
    return std::move(bag_);
  }

  // The record at `pos` of `bytes`, whose first byte is byte `base` of the
  // file (a streamed read passes one record at a time); advances pos.
  void record(std::string_view bytes, std::size_t& pos, std::size_t base = 0) {
    base_ = base;
    const BagPlace top{&bag_.file, base, {}};
    const BagRecord r = detail::read_record(bytes, pos, top);
    const unsigned char op = op_of(r, top);
    switch (op) {
      case kBagHeader: header_seen_ = true; break;
      case kChunk: chunk(r, top); break;
      case kConnection: connection(r, top); break;
      case kIndexData: index(r, top); break;
      case kMessageData: message(r, top, base + r.offset); break;  // outside chunks: allowed by readers
      case kChunkInfo: break;
      default: bag_error(top, r.offset, "record of unknown op code " + std::to_string(op));
    }
  }

  // After the last record.
  void finish() {
    if (!header_seen_) bag_error({&bag_.file, 0, {}}, kRos1BagMagic.size(), "no bag header record");
    // Index records of connections no record declares say nothing usable.
    std::erase_if(bag_.connections, [](const Ros1Connection& c) { return c.type.empty(); });
  }

  Ros1Bag& bag() noexcept { return bag_; }

 private:
  void chunk(const BagRecord& r, const BagPlace& top) {
    const std::string_view compression = detail::required_field(r, "compression", 0, top, "chunk");
    const std::uint32_t size = le32(detail::required_field(r, "size", 4, top, "chunk").data());
    const std::string plain = detail::decompress_chunk(compression, r.data, size, top, r.offset);
    const bool compressed = compression != "none";
    const BagPlace inner{
        &bag_.file, compressed ? 0 : base_ + r.data_offset,
        compressed ? " of the " + std::string(compression) + " chunk at byte " + std::to_string(base_ + r.offset)
                   : std::string()};
    std::size_t pos = 0;
    while (pos < plain.size()) {
      const BagRecord m = detail::read_record(plain, pos, inner);
      const unsigned char op = op_of(m, inner);
      if (op == kConnection) {
        connection(m, inner);
      } else if (op == kMessageData) {
        message(m, inner, base_ + (compressed ? r.offset : r.data_offset + m.offset));
        bag_.messages.back().compressed = compressed;
      } else {
        bag_error(inner, m.offset, "record of op code " + std::to_string(op) + " inside a chunk");
      }
    }
  }

  Ros1Connection& find_or_add(std::uint32_t id) {
    const auto it = std::find_if(bag_.connections.begin(), bag_.connections.end(),
                                 [&](const Ros1Connection& c) { return c.id == id; });
    if (it != bag_.connections.end()) return *it;
    bag_.connections.push_back({});
    bag_.connections.back().id = id;
    return bag_.connections.back();
  }

  void connection(const BagRecord& r, const BagPlace& at) {
    const std::uint32_t id = le32(detail::required_field(r, "conn", 4, at, "connection").data());
    const std::string_view topic = detail::required_field(r, "topic", 0, at, "connection");
    std::string type;
    std::string md5;
    detail::for_each_field(r.data, at, r.data_offset, [&](std::string_view name, std::string_view value) {
      if (name == "type") type = value;
      if (name == "md5sum") md5 = value;
    });
    if (type.empty()) bag_error(at, r.offset, "connection record without a message type");
    Ros1Connection& c = find_or_add(id);
    if (!c.topic.empty() && (c.topic != topic || c.type != type))
      bag_error(at, r.offset,
                "connection " + std::to_string(id) + " declared again with another topic or type (" +
                    std::string(topic) + ", " + type + ")");
    c.topic = topic;
    c.type = type;
    c.md5sum = md5;
  }

  void index(const BagRecord& r, const BagPlace& at) {
    const std::uint32_t id = le32(detail::required_field(r, "conn", 4, at, "index data").data());
    const std::uint32_t count = le32(detail::required_field(r, "count", 4, at, "index data").data());
    if (r.data.size() / 12 < count)
      bag_error(at, r.offset,
                "index data record counts " + std::to_string(count) + " entries in " + std::to_string(r.data.size()) +
                    " bytes");
    find_or_add(id).indexed += count;
  }

  void message(const BagRecord& r, const BagPlace& at, std::size_t file_offset) {
    const std::uint32_t id = le32(detail::required_field(r, "conn", 4, at, "message data").data());
    const std::string_view time = detail::required_field(r, "time", 8, at, "message data");
    const auto it = std::find_if(bag_.connections.begin(), bag_.connections.end(),
                                 [&](const Ros1Connection& c) { return c.id == id && !c.type.empty(); });
    if (it == bag_.connections.end())
      bag_error(at, r.offset, "message on connection " + std::to_string(id) + ", which no record declared before");
    ++it->messages;
    Ros1Message m;
    m.connection = id;
    m.sec = le32(time.data());
    m.nsec = le32(time.data() + 4);
    m.offset = file_offset;
    m.begin = bag_.payload.size();
    m.size = r.data.size();
    bag_.payload.append(r.data);
    bag_.messages.push_back(m);
  }

  Ros1Bag bag_;
  std::size_t base_ = 0;  // file offset of the bytes being read
  bool header_seen_ = false;
};

// A bag read one top-level record (a chunk) at a time.
class Ros1Source final : public detail::MessageSource {
 public:
  explicit Ros1Source(const std::string& path) : file_(path), reader_(path) {
    total_bytes = file_.size();
    std::string head;
    file_.read(0, kRos1BagMagic.size(), head);
    if (head != kRos1BagMagic) {
      file_.read(0, 32, head);
      (void)BagReader(path).read(head);  // the whole-file reader's error
    }
    pos_ = kRos1BagMagic.size();
  }

  bool next(MessageLog& batch) override {
    while (pos_ < file_.size()) {
      // The record's length from its two length fields, cut at the end of
      // the file (where read_record then says what is missing).
      const std::uint64_t header = file_.le(pos_, 4, 0);
      const std::uint64_t data = file_.le(pos_ + 4 + header, 4, 0);
      file_.read(pos_, static_cast<std::size_t>(std::min<std::uint64_t>(8 + header + data, file_.size() - pos_)), buf_);
      std::size_t at = 0;
      reader_.record(buf_, at, pos_);
      pos_ += at;
      bytes_read = pos_;
      Ros1Bag& bag = reader_.bag();
      if (bag.messages.empty()) continue;
      Ros1Bag part;
      part.file = bag.file;
      for (const auto& c : bag.connections)
        if (!c.type.empty()) part.connections.push_back(c);
      part.messages.swap(bag.messages);
      part.payload.swap(bag.payload);
      batch = message_log(std::move(part));
      return true;
    }
    if (!done_) reader_.finish();
    done_ = true;
    return false;
  }

 private:
  detail::RecordFile file_;
  BagReader reader_;
  std::size_t pos_ = 0;
  std::string buf_;
  bool done_ = false;
};

}  // namespace

bool looks_like_ros_bag(std::string_view head) noexcept { return head.starts_with("#ROSBAG V"); }

const Ros1Connection* Ros1Bag::connection(std::uint32_t id) const noexcept {
  for (const auto& c : connections)
    if (c.id == id) return &c;
  return nullptr;
}

Ros1Bag parse_ros1_bag(std::string_view bytes, const std::string& file) { return BagReader(file).read(bytes); }

std::unique_ptr<detail::MessageSource> detail::open_ros1_source(const std::string& path) {
  return std::make_unique<Ros1Source>(path);
}

Ros1Bag read_ros1_bag(const std::string& path) {
  const FileBuffer buf = FileBuffer::open(path, Content::series);
  return parse_ros1_bag(buf.view(), path);
}

}  // namespace cubecal::io
