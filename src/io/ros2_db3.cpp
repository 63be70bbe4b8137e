// rosbag2's SQLite storage (storage_identifier sqlite3): the topics table
// gives each topic's name, type ("sensor_msgs/msg/Imu") and serialization
// format ("cdr"); the messages table each message's topic, receive
// timestamp (int64 ns) and serialized bytes.
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/io/ros2_bag.hpp"
#include "detail/message_source.hpp"

namespace cubecal::io {

namespace {

constexpr const char* kHint = "the .db3 is truncated or corrupt, or not a rosbag2 database: copy it again";

// file: URI of `path`, every byte but unreserved ones and '/' percent-encoded.
std::string file_uri(const std::string& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string uri = "file:";
  // A relative path stays relative; one starting with "//" would be read
  // as an authority.
  if (path.starts_with("//")) uri += "//";
  for (const char ch : path) {
    const auto u = static_cast<unsigned char>(ch);
    const bool plain = (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || u == '/' ||
                       u == '-' || u == '_' || u == '.' || u == '~';
    if (plain) {
      uri += ch;
    } else {
      uri += '%';
      uri += kHex[u >> 4];
      uri += kHex[u & 15];
    }
  }
  return uri + "?immutable=1";
}

class Db {
 public:
  explicit Db(const std::string& path) : path_(path) {
    const int rc = sqlite3_open_v2(file_uri(path).c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr);
    if (rc != SQLITE_OK) {
      // The handle is allocated even when opening fails: closed here, as
      // the destructor of a constructor that throws does not run.
      const std::string why = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      db_ = nullptr;
      throw InputError(path_, 0, 0, "cannot open the database (SQLite: " + why + ")", kHint);
    }
  }
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;
  ~Db() { sqlite3_close(db_); }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, 0, 0, what + " (SQLite: " + (db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory") + ")",
                     kHint);
  }

  using Statement = std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)>;
  Statement prepare(const char* sql, const char* what) {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_, sql, -1, &raw, nullptr) != SQLITE_OK) fail(what);
    return Statement(raw, sqlite3_finalize);
  }
  // The next row of `stmt`: false at its end.
  bool step(sqlite3_stmt* stmt, const char* what) const {
    const int rc = sqlite3_step(stmt);
    if (rc == SQLITE_DONE) return false;
    if (rc != SQLITE_ROW) fail(what);
    return true;
  }

  // Runs `sql`, calling row(statement) for each row.
  template <class Row>
  void query(const char* sql, const char* what, Row&& row) {
    const Statement stmt = prepare(sql, what);
    while (step(stmt.get(), what)) row(stmt.get());
  }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

std::string text(sqlite3_stmt* s, int col) {
  const unsigned char* t = sqlite3_column_text(s, col);
  return t == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(t));
}

}  // namespace

bool looks_like_sqlite(std::string_view head) noexcept { return head.starts_with(kSqliteMagic); }

bool is_sqlite_file(const std::string& path) {
  // Only a regular file: reading the start of a pipe or device would take
  // those bytes from the reader that comes after.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char head[16] = {};
  if (!in.read(head, sizeof head)) return false;
  return looks_like_sqlite(std::string_view(head, sizeof head));
}

namespace {

constexpr const char* kMessages = "SELECT id, topic_id, timestamp, data FROM messages ORDER BY timestamp, id";

// The topics table into log.topics; topic id -> log topic.
std::map<std::int64_t, std::uint32_t> read_topics(Db& db, MessageLog& log) {
  std::map<std::int64_t, std::uint32_t> topic_of;
  db.query("SELECT id, name, type, serialization_format FROM topics ORDER BY id", "cannot read the topics table",
           [&](sqlite3_stmt* s) {
             const std::int64_t id = sqlite3_column_int64(s, 0);
             const std::string name = text(s, 1);
             if (topic_of.contains(id))
               throw InputError(log.file, 0, 0, "topics table holds id " + std::to_string(id) + " twice", kHint);
             topic_of[id] = log.topic(name, text(s, 2), text(s, 3));
           });
  return topic_of;
}

// The message of row `s` of kMessages appended to `log`.
void add_message(sqlite3_stmt* s, const std::map<std::int64_t, std::uint32_t>& topic_of, MessageLog& log) {
  const std::int64_t row = sqlite3_column_int64(s, 0);
  const std::int64_t topic = sqlite3_column_int64(s, 1);
  const auto t = topic_of.find(topic);
  if (t == topic_of.end())
    throw InputError(log.file, 0, 0,
                     "row " + std::to_string(row) + " of the messages table is of topic_id " + std::to_string(topic) +
                         ", which the topics table does not hold",
                     kHint);
  const std::int64_t ns = sqlite3_column_int64(s, 2);
  LogMessage m;
  m.topic = t->second;
  m.place = MessagePlace::row;
  m.offset = static_cast<std::uint64_t>(row);
  // Floor division: a time before 1970 keeps 0 <= nsec < 1e9.
  std::int64_t nsec = ns % 1000000000;
  m.sec = ns / 1000000000;
  if (nsec < 0) {
    nsec += 1000000000;
    --m.sec;
  }
  m.nsec = static_cast<std::uint32_t>(nsec);
  const void* blob = sqlite3_column_blob(s, 3);
  const int n = sqlite3_column_bytes(s, 3);
  m.begin = log.payload.size();
  m.size = static_cast<std::size_t>(n);
  if (n > 0) log.payload.append(static_cast<const char*>(blob), static_cast<std::size_t>(n));
  log.messages.push_back(m);
  ++log.topics[m.topic].messages;
}

void check_sqlite(const std::string& path) {
  if (!is_sqlite_file(path))
    throw InputError(path, 0, 0, "not an SQLite database (it does not start with \"SQLite format 3\")", kHint);
}

// The messages in the order of read_db3, through a cursor: a batch of up
// to a MiB of messages at a time.
class Db3Source final : public detail::MessageSource {
 public:
  explicit Db3Source(const std::string& path) : db_((check_sqlite(path), path)), stmt_(nullptr, sqlite3_finalize) {
    log_.file = path;
    topic_of_ = read_topics(db_, log_);
    stmt_ = db_.prepare(kMessages, "cannot read the messages table");
    std::error_code ec;
    total_bytes = static_cast<std::size_t>(std::filesystem::file_size(path, ec));
  }

  bool next(MessageLog& batch) override {
    log_.messages.clear();
    log_.payload.clear();
    while (!done_ && log_.payload.size() < (std::size_t{1} << 20)) {
      // (A statement stepped past its end starts again: never.)
      done_ = !db_.step(stmt_.get(), "cannot read the messages table");
      if (done_) break;
      add_message(stmt_.get(), topic_of_, log_);
      bytes_read += log_.messages.back().size;
    }
    if (log_.messages.empty()) return false;
    batch.file = log_.file;
    batch.topics = log_.topics;
    batch.messages.swap(log_.messages);
    batch.payload.swap(log_.payload);
    return true;
  }

 private:
  Db db_;
  Db::Statement stmt_;
  MessageLog log_;
  std::map<std::int64_t, std::uint32_t> topic_of_;
  bool done_ = false;
};

}  // namespace

std::unique_ptr<detail::MessageSource> detail::open_db3_source(const std::string& path) {
  return std::make_unique<Db3Source>(path);
}

MessageLog read_db3(const std::string& path) {
  check_sqlite(path);
  Db db(path);
  MessageLog log;
  log.file = path;
  const auto topic_of = read_topics(db, log);
  db.query(kMessages, "cannot read the messages table", [&](sqlite3_stmt* s) { add_message(s, topic_of, log); });
  return log;
}

}  // namespace cubecal::io
