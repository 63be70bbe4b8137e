// A robot log streamed (container_streams.hpp): the messages of one topic
// decoded a batch (a chunk, or a MiB of .db3 rows) at a time, with the
// channels, time and checks of read_bag_series; the rate from the first
// 65536 stamps. Several topics are paired sample by sample in memory, not
// here.
#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <optional>

#include "cubecal/error.hpp"
#include "cubecal/io/mcap.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/ros2_bag.hpp"
#include "cubecal/io/ulog.hpp"
#include "detail/bag_series.hpp"
#include "detail/container_streams.hpp"
#include "detail/file_buffer.hpp"
#include "detail/message_source.hpp"
#include "detail/record_file.hpp"
#include "detail/stream_timing.hpp"

namespace cubecal::io::detail {

namespace {

constexpr std::size_t kHeadStamps = std::size_t{1} << 16;  // for the rate
constexpr std::size_t kPieceRows = std::size_t{1} << 16;

// Messages of the topic read, decoded, not yet passed on.
struct Piece {
  std::vector<LogMessage> messages;
  std::vector<TopicColumn> columns;
  std::vector<double> time;
  std::size_t first = 0;  // row of the record of the first
};

class MessageStream final : public SampleStream {
 public:
  MessageStream(std::unique_ptr<MessageSource> src, const std::string& file, const SeriesOptions& opt)
      : src_(std::move(src)), opt_(opt), timing_(opt, !opt.time_col.empty() || opt.rate_hz == 0.0, file, "") {
    file_ = file;
    shell_.file = file;
    record_time_ = bag_time_is_record(file, opt);
    total_bytes_ = src_->total_bytes;
    std::vector<double> head;
    while (head.size() < kHeadStamps && pull()) {
      const Piece& p = pending_.back();
      head.insert(head.end(), p.time.begin(), p.time.end());
    }
    if (topic_.empty()) finish();  // the end of the log without the topic: says why
    time_name_ = topic_ + (record_time_ ? " record time" : " header.stamp");
    timing_ = StreamTiming(opt, !opt.time_col.empty() || opt.rate_hz == 0.0, file, time_name_);
    timing_.start(head, place_in(pending_));
    rate_hz_ = timing_.rate_hz();
    rate_from_time_ = timing_.rate_from_time();
    if (opt.time_col.empty() && opt.rate_hz != 0.0) time_name_.clear();  // no timing: no time column
  }

  bool next(SampleChunk& out) override {
    // (A piece of no rows: batches of other topics only.)
    while (pending_.empty() || pending_.front().time.empty()) {
      if (!pending_.empty()) {
        pending_.pop_front();
        continue;
      }
      if (!pull()) {
        finish();
        return false;
      }
    }
    Piece p = std::move(pending_.front());
    pending_.pop_front();
    timing_.check(p.time, p.first, place_in(p));
    out.channels.resize(wanted_.size());
    out.extra.resize(extras_.size());
    for (std::size_t c = 0; c < wanted_.size(); ++c) out.channels[c] = std::move(p.columns[wanted_[c]].values);
    for (std::size_t c = 0; c < extras_.size(); ++c) out.extra[c] = std::move(p.columns[extras_[c]].values);
    rows_read_ += p.time.size();
    return true;
  }

 private:
  // The next batches of the log decoded into a piece of up to
  // kPieceRows rows (possibly none: a piece is what a consumer takes at
  // once, and many small ones cost it more than their rows); false at the
  // end of the log.
  bool pull() {
    Piece p;
    p.first = rows_;
    bool any = false;
    MessageLog batch;
    while (p.time.size() < kPieceRows && src_->next(batch)) {
      any = true;
      bytes_read_ = src_->bytes_read;
      shell_.parts = batch.parts;
      topics_ = batch.topics;
      if (topic_.empty()) choose(batch);
      if (topic_.empty()) continue;
      if (p.columns.empty()) p.columns = bag_columns(batch.topics[index_]);
      for (const LogMessage& m : batch.messages) {
        if (batch.topics[m.topic].name != topic_) continue;
        p.messages.push_back(m);
        p.time.push_back(decode_bag_message(batch, m, p.first + p.messages.size(), p.columns, record_time_));
      }
    }
    if (!any) return false;
    rows_ += p.time.size();
    if (!p.columns.empty()) check_values(p);
    pending_.push_back(std::move(p));
    return true;
  }

  // The topic, once the log has declared it: the one named, or the first
  // sensor_msgs/Imu topic (finish() checks that no other is).
  void choose(const MessageLog& batch) {
    for (std::size_t i = 0; i < batch.topics.size(); ++i) {
      const LogTopic& t = batch.topics[i];
      if (opt_.topics.empty() ? !is_imu_topic(t) : t.name != opt_.topics.front()) continue;
      MessageLog one;
      one.file = file_;
      one.topics = {t};
      bool by_default = false;
      (void)choose_bag_topics(one, opt_, by_default);  // its type and serialization
      topic_ = t.name;
      index_ = i;
      name_channels(t);
      return;
    }
  }

  void name_channels(const LogTopic& t) {
    std::vector<TopicColumn> all = bag_columns(t);
    Series s;
    take_channels(
        s, all, opt_, [](std::size_t) {}, file_, "no channels besides the temperature in " + t.described(),
        "read a sensor_msgs/Imu or MagneticField topic with {topics} NAME");
    names_ = s.names;
    extra_names_ = s.extra_names;
    left_out_ = s.left_out;
    default_columns_ = s.default_columns;
    for (const auto& n : names_) wanted_.push_back(resolve_channel(file_, all, n));
    for (const auto& n : extra_names_) extras_.push_back(resolve_channel(file_, all, n));
    top_.assign(all.size(), 0.0);
    top_at_.assign(all.size(), {});
  }

  // The values read_bag_series refuses, in the channels taken.
  void check_values(const Piece& p) {
    std::vector<std::size_t> taken = wanted_;
    taken.insert(taken.end(), extras_.begin(), extras_.end());
    for (const std::size_t c : taken) {
      const TopicColumn& col = p.columns[c];
      for (std::size_t i = 0; i < col.values.size(); ++i) {
        const double v = col.values[i];
        if (std::isnan(v))
          throw error(p, i, col.field + " is NaN",
                      "the driver publishes NaN where it has no reading: leave this topic out, or cut the record "
                      "before this message");
        if (!std::isfinite(v) || std::fabs(v) > kMaxMagnitude)
          throw error(p, i, col.field + " is " + shortest(v) + ", which no variance can hold",
                      "cut the record before this message");
        if (std::fabs(v) > top_[c]) {
          top_[c] = std::fabs(v);
          top_at_[c] = {p.messages[i], p.first + i + 1};
        }
      }
    }
  }

  // At the end of the log: the topic chosen as read_bag_series chooses it
  // among all the log's topics, and no channel too small for a variance.
  void finish() {
    MessageLog all;
    all.file = file_;
    all.topics = topics_;
    bool by_default = false;
    (void)choose_bag_topics(all, opt_, by_default);
    if (topic_.empty()) throw InputError(file_, 0, 0, "no message of the topics read", "choose another topic");
    for (std::size_t c = 0; c < top_.size(); ++c) {
      if (top_[c] == 0.0 || top_[c] >= kMinMagnitude) continue;
      const TopicColumn col = bag_columns(topics_[index_])[c];
      throw bag_message_error(shell_, top_at_[c].first, top_at_[c].second, topic_,
                              col.field + " " + shortest(top_[c]) + " is the largest of " + col.name +
                                  ", below the magnitude " + shortest(kMinMagnitude) +
                                  " whose square a variance can hold",
                              "the topic holds no usable " + col.field);
    }
  }

  InputError error(const Piece& p, std::size_t i, const std::string& what, std::string hint) const {
    return bag_message_error(shell_, p.messages[i], p.first + i + 1, topic_, what, std::move(hint));
  }
  // The errors of rows of piece p.
  PlaceError place_in(const Piece& p) const {
    return [this, &p](std::size_t row, std::string what, std::string hint) {
      return error(p, std::min(row - p.first, p.messages.size() - 1), what, std::move(hint));
    };
  }
  // The errors of rows of the pieces held.
  PlaceError place_in(const std::deque<Piece>& pieces) const {
    return [this, &pieces](std::size_t row, std::string what, std::string hint) {
      for (const Piece& p : pieces)
        if (row < p.first + p.time.size()) return error(p, row - p.first, what, std::move(hint));
      return InputError(file_, 0, 0, what, std::move(hint));
    };
  }

  std::unique_ptr<MessageSource> src_;
  SeriesOptions opt_;
  StreamTiming timing_;
  MessageLog shell_;  // file and parts: where a message is
  std::vector<LogTopic> topics_;
  bool record_time_ = false;
  std::string topic_;
  std::size_t index_ = 0, rows_ = 0;
  std::vector<std::size_t> wanted_, extras_;
  std::vector<double> top_;
  std::vector<std::pair<LogMessage, std::size_t>> top_at_;
  std::deque<Piece> pending_;
};

}  // namespace

std::string file_head(const std::string& path, std::size_t n) {
  std::error_code ec;
  if (path == kStdinPath || !std::filesystem::is_regular_file(path, ec)) return {};
  std::ifstream in(path, std::ios::binary);
  std::string head(n, '\0');
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

namespace {

// The chunks' uncompressed sizes and the other records' sizes of a ROS 1
// bag or MCAP file, from the record headers (one read each).
std::size_t record_bytes(const std::string& path, bool mcap) {
  const RecordFile f(path);
  std::size_t total = 0;
  std::size_t pos = mcap ? kMcapMagic.size() : kRos1BagMagic.size();
  std::string header;
  while (pos < f.size()) {
    if (mcap) {
      const std::uint64_t op = f.le(pos, 1, 0), len = f.le(pos + 1, 8, ~std::uint64_t{0});
      if (len > f.size() - pos - std::min<std::size_t>(9, f.size() - pos)) break;
      total += static_cast<std::size_t>(op == 0x06 ? f.le(pos + 9 + 16, 8, len) : len);
      pos += 9 + static_cast<std::size_t>(len);
      continue;
    }
    const std::uint64_t hlen = f.le(pos, 4, ~std::uint64_t{0});
    const std::uint64_t dlen = f.le(pos + 4 + std::min<std::uint64_t>(hlen, f.size()), 4, ~std::uint64_t{0});
    if (hlen > f.size() || dlen > f.size() || pos + 8 + hlen + dlen > f.size()) break;
    f.read(pos + 4, static_cast<std::size_t>(hlen), header);
    const std::size_t size = header.find(std::string("\x09\x00\x00\x00size=", 9));
    total += static_cast<std::size_t>(
        size != std::string::npos && size + 13 <= header.size() ? f.le(pos + 4 + size + 9, 4, dlen) : dlen);
    pos += static_cast<std::size_t>(8 + hlen + dlen);
  }
  return f.size() + total;
}

}  // namespace

std::unique_ptr<SampleStream> open_message_stream(const std::string& path, const SeriesOptions& opt) {
  if (!opt.binary.channels.empty() || path == kStdinPath) return nullptr;
  const auto stream = [&](std::unique_ptr<MessageSource> src) {
    if (opt.topics.size() > 1)
      throw UsageError(Field::topics, path +
                                          ": several topics are paired sample by sample in memory: leave out "
                                          "{stream}, or stream one topic at a time");
    return std::make_unique<MessageStream>(std::move(src), path, opt);
  };
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec) && !looks_like_recording(path))
    return stream(open_bag_directory_source(path));
  if (is_sqlite_file(path)) return stream(open_db3_source(path));
  const std::string head = file_head(path, 64);
  if (looks_like_ros_bag(head)) return stream(open_ros1_source(path));
  if (looks_like_mcap(head)) return stream(open_mcap_source(path));
  if (looks_like_ulog(head))
    throw UsageError(Field::stream, path +
                                        ": a PX4 ULog file is read whole (its topics are paired and its temperature "
                                        "channel chosen over the whole log): leave out {stream}");
  return nullptr;
}

}  // namespace cubecal::io::detail

namespace cubecal::io {

std::size_t message_log_bytes(const std::string& path) noexcept {
  try {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec) && !looks_like_recording(path)) {
      std::size_t total = 0;
      for (const auto& e : std::filesystem::directory_iterator(path, ec))
        if (e.is_regular_file(ec)) total += static_cast<std::size_t>(e.file_size(ec));
      return total;
    }
    if (is_sqlite_file(path)) return static_cast<std::size_t>(std::filesystem::file_size(path, ec));
    const std::string head = detail::file_head(path, 64);
    if (looks_like_ros_bag(head)) return detail::record_bytes(path, false);
    if (looks_like_mcap(head)) return detail::record_bytes(path, true);
  } catch (const std::exception&) {
  }
  return 0;
}

}  // namespace cubecal::io
