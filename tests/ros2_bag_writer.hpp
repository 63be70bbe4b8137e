// Test support for ROS 2 bags, independent of cubecal's readers: an MCAP
// record walker and writer (mcap.dev/spec), chunk (de)compression with
// libzstd and liblz4, a CDR writer and a fixed-offset CDR decoder of
// sensor_msgs/msg/Imu, and a rosbag2 SQLite writer.
#pragma once
#include <gtest/gtest.h>
#include <lz4frame.h>
#include <sqlite3.h>
#include <zlib.h>
#include <zstd.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace cubecal::test::ros2 {

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline std::string le(std::uint64_t v, int n) {
  std::string s(static_cast<std::size_t>(n), '\0');
  for (int k = 0; k < n; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((v >> (8 * k)) & 0xff);
  return s;
}
inline std::string u16(std::uint64_t v) { return le(v, 2); }
inline std::string u32(std::uint64_t v) { return le(v, 4); }
inline std::string u64(std::uint64_t v) { return le(v, 8); }
inline std::uint64_t get(const std::string& s, std::size_t p, int n) {
  std::uint64_t v = 0;
  for (int k = n - 1; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(s[p + static_cast<std::size_t>(k)]);
  return v;
}
inline double get_f64(const std::string& s, std::size_t p) {
  const std::uint64_t v = get(s, p, 8);
  double d;
  std::memcpy(&d, &v, 8);
  return d;
}
inline std::string str(const std::string& s) { return u32(s.size()) + s; }

inline const std::string kMagic("\x89MCAP0\r\n", 8);

struct McapRecord {
  unsigned char op = 0;
  std::size_t offset = 0;  // of the op code
  std::string content;
};

// The records from `pos` up to the end or the footer (included).
inline std::vector<McapRecord> mcap_records(const std::string& b, std::size_t pos) {
  std::vector<McapRecord> out;
  while (pos + 9 <= b.size()) {
    McapRecord r;
    r.op = static_cast<unsigned char>(b[pos]);
    r.offset = pos;
    const std::uint64_t len = get(b, pos + 1, 8);
    r.content = b.substr(pos + 9, len);
    pos += 9 + len;
    out.push_back(r);
    if (r.op == 0x02) break;
  }
  return out;
}

inline std::string record(unsigned char op, const std::string& content) {
  return std::string(1, static_cast<char>(op)) + u64(content.size()) + content;
}

struct Chunk {
  std::uint64_t start = 0, end = 0, size = 0;
  std::uint32_t crc = 0;
  std::string compression;
  std::string stored;
};
inline Chunk chunk_of(const std::string& c) {
  Chunk k;
  k.start = get(c, 0, 8);
  k.end = get(c, 8, 8);
  k.size = get(c, 16, 8);
  k.crc = static_cast<std::uint32_t>(get(c, 24, 4));
  const std::size_t clen = get(c, 28, 4);
  k.compression = c.substr(32, clen);
  const std::size_t rlen = get(c, 32 + clen, 8);
  k.stored = c.substr(40 + clen, rlen);
  return k;
}

inline std::uint32_t crc_of(const std::string& s) {
  return static_cast<std::uint32_t>(::crc32(0, reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(s.size())));
}

inline std::string compress(const std::string& plain, const std::string& compression) {
  if (compression == "zstd") {
    std::string out(ZSTD_compressBound(plain.size()), '\0');
    const std::size_t n = ZSTD_compress(out.data(), out.size(), plain.data(), plain.size(), 3);
    EXPECT_FALSE(ZSTD_isError(n));
    out.resize(n);
    return out;
  }
  if (compression == "lz4") {
    std::string out(LZ4F_compressFrameBound(plain.size(), nullptr), '\0');
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), plain.data(), plain.size(), nullptr);
    EXPECT_FALSE(LZ4F_isError(n));
    out.resize(n);
    return out;
  }
  return plain;
}

inline std::string decompress(const Chunk& k) {
  if (k.compression.empty()) return k.stored;
  std::string out(k.size, '\0');
  if (k.compression == "zstd") {
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), k.stored.data(), k.stored.size());
    EXPECT_EQ(n, k.size);
    return out;
  }
  LZ4F_dctx* ctx = nullptr;
  LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION);
  std::size_t dst = out.size(), src = k.stored.size();
  LZ4F_decompress(ctx, out.data(), &dst, k.stored.data(), &src, nullptr);
  LZ4F_freeDecompressionContext(ctx);
  EXPECT_EQ(dst, k.size);
  return out;
}

inline std::string chunk_record(const std::string& plain, const std::string& compression, std::uint64_t start = 0,
                                std::uint64_t end = 0, bool with_crc = true) {
  const std::string stored = compress(plain, compression);
  return record(0x06, u64(start) + u64(end) + u64(plain.size()) + u32(with_crc ? crc_of(plain) : 0) + str(compression) +
                          u64(stored.size()) + stored);
}

// The file with every chunk decompressed, edited and stored again with
// `compression` ("", "zstd" or "lz4"), its CRC computed again.
template <class Edit>
std::string rewrite_chunks(const std::string& file, const std::string& compression, Edit edit) {
  std::string out = kMagic;
  for (const McapRecord& r : mcap_records(file, 8)) {
    if (r.op != 0x06) {
      out += record(r.op, r.content);
      continue;
    }
    const Chunk k = chunk_of(r.content);
    std::string plain = decompress(k);
    edit(plain);
    out += chunk_record(plain, compression, k.start, k.end);
  }
  return out + kMagic;
}
inline std::string rewrite_chunks(const std::string& file, const std::string& compression) {
  return rewrite_chunks(file, compression, [](std::string&) {});
}

// A message record's fields.
struct McapMessage {
  std::uint16_t channel = 0;
  std::uint64_t log_time = 0;
  std::string data;
};
inline McapMessage message_of(const std::string& c) {
  return {static_cast<std::uint16_t>(get(c, 0, 2)), get(c, 6, 8), c.substr(22)};
}
inline std::string message_record(std::uint16_t channel, std::uint32_t seq, std::uint64_t log_time,
                                  const std::string& data) {
  return record(0x05, u16(channel) + u32(seq) + u64(log_time) + u64(log_time) + data);
}
inline std::string schema_record(std::uint16_t id, const std::string& name) {
  return record(0x03, u16(id) + str(name) + str("ros2msg") + str(""));
}
inline std::string channel_record(std::uint16_t id, std::uint16_t schema, const std::string& topic,
                                  const std::string& encoding = "cdr") {
  return record(0x04, u16(id) + u16(schema) + str(topic) + str(encoding) + u32(0));
}
inline std::string header_record() { return record(0x01, str("ros2") + str("cubecal test")); }
inline std::string footer() { return record(0x0F, u32(0)) + record(0x02, u64(0) + u64(0) + u32(0)) + kMagic; }

// Every message of the data section, chunks decompressed, in file order.
inline std::vector<McapMessage> mcap_messages(const std::string& file) {
  std::vector<McapMessage> out;
  for (const McapRecord& r : mcap_records(file, 8)) {
    if (r.op == 0x0F) break;
    if (r.op == 0x05) out.push_back(message_of(r.content));
    if (r.op != 0x06) continue;
    for (const McapRecord& m : mcap_records(decompress(chunk_of(r.content)), 0))
      if (m.op == 0x05) out.push_back(message_of(m.content));
  }
  return out;
}

// A CDR writer: the encapsulation header, then fields aligned to their size
// from the byte after it.
class Cdr {
 public:
  explicit Cdr(bool little) : little_(little) {
    b_ = std::string("\0", 1) + (little ? '\1' : '\0') + std::string(2, '\0');
  }
  Cdr& u32v(std::uint32_t v) { return put(v, 4); }
  Cdr& f64(double d) {
    std::uint64_t v;
    std::memcpy(&v, &d, 8);
    return put(v, 8);
  }
  Cdr& text(const std::string& s) {
    u32v(static_cast<std::uint32_t>(s.size() + 1));
    b_ += s;
    b_ += '\0';
    return *this;
  }
  Cdr& header(std::int32_t sec, std::uint32_t nsec, const std::string& frame) {
    return u32v(static_cast<std::uint32_t>(sec)).u32v(nsec).text(frame);
  }
  const std::string& bytes() const { return b_; }

 private:
  Cdr& put(std::uint64_t v, int n) {
    while ((b_.size() - 4) % static_cast<std::size_t>(n) != 0) b_ += '\0';
    for (int k = 0; k < n; ++k) {
      const int shift = 8 * (little_ ? k : n - 1 - k);
      b_ += static_cast<char>((v >> shift) & 0xff);
    }
    return *this;
  }
  bool little_;
  std::string b_;
};

inline std::string imu_cdr(bool little, std::int32_t sec, std::uint32_t nsec, const double g[3], const double a[3]) {
  Cdr c(little);
  c.header(sec, nsec, "imu");
  for (int k = 0; k < 13; ++k) c.f64(0.0);
  for (int k = 0; k < 3; ++k) c.f64(g[k]);
  for (int k = 0; k < 9; ++k) c.f64(0.0);
  for (int k = 0; k < 3; ++k) c.f64(a[k]);
  for (int k = 0; k < 9; ++k) c.f64(0.0);
  return c.bytes();
}
inline std::string temperature_cdr(bool little, std::int32_t sec, std::uint32_t nsec, double t) {
  Cdr c(little);
  c.header(sec, nsec, "imu");
  return c.f64(t).f64(0.0).bytes();
}

// sensor_msgs/msg/Imu in little-endian CDR decoded by fixed offsets:
// stamp at 4 and 8, frame_id length at 12, its bytes from 16; the doubles
// from the next multiple of 8 after the header (counted from byte 4).
struct ImuFields {
  std::int32_t sec = 0;
  std::uint32_t nsec = 0;
  double g[3] = {}, a[3] = {};
  std::size_t size = 0;  // the bytes the message should have
};
inline ImuFields imu_fields(const std::string& m) {
  ImuFields f;
  EXPECT_EQ(m.substr(0, 2), std::string("\0\1", 2));
  f.sec = static_cast<std::int32_t>(get(m, 4, 4));
  f.nsec = static_cast<std::uint32_t>(get(m, 8, 4));
  std::size_t p = 16 + get(m, 12, 4);
  p = 4 + (p - 4 + 7) / 8 * 8;
  for (int k = 0; k < 3; ++k) f.g[k] = get_f64(m, p + 104 + 8 * static_cast<std::size_t>(k));
  for (int k = 0; k < 3; ++k) f.a[k] = get_f64(m, p + 200 + 8 * static_cast<std::size_t>(k));
  f.size = p + 37 * 8;
  return f;
}

// A rosbag2 SQLite file (schema of rosbag2_storage_default_plugins).
class Db3Writer {
 public:
  explicit Db3Writer(const std::string& path) {
    EXPECT_EQ(sqlite3_open(path.c_str(), &db_), SQLITE_OK);
    exec(
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
        "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
        "data BLOB NOT NULL);");
  }
  ~Db3Writer() { sqlite3_close(db_); }
  void topic(int id, const std::string& name, const std::string& type) {
    exec("INSERT INTO topics VALUES(" + std::to_string(id) + ", '" + name + "', '" + type + "', 'cdr', '')");
  }
  void message(int topic, std::int64_t timestamp, const std::string& data) {
    sqlite3_stmt* s = nullptr;
    ASSERT_EQ(
        sqlite3_prepare_v2(db_, "INSERT INTO messages(topic_id, timestamp, data) VALUES(?, ?, ?)", -1, &s, nullptr),
        SQLITE_OK);
    sqlite3_bind_int(s, 1, topic);
    sqlite3_bind_int64(s, 2, timestamp);
    sqlite3_bind_blob(s, 3, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(s), SQLITE_DONE);
    sqlite3_finalize(s);
  }
  void exec(const std::string& sql) {
    char* err = nullptr;
    EXPECT_EQ(sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "");
    sqlite3_free(err);
  }

 private:
  sqlite3* db_ = nullptr;
};

}  // namespace cubecal::test::ros2
