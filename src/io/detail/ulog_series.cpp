#include "ulog_series.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cubecal/error.hpp"
#include "cubecal/stats/sampling.hpp"
#include "series_timing.hpp"
#include "topic_channels.hpp"
#include "ulog_format.hpp"

namespace cubecal::io::detail {

namespace {

// Gauss to tesla: ROS MagneticField (and so the bag path) is in tesla.
constexpr double kTeslaPerGauss = 1e-4;
// sensor_combined.accelerometer_timestamp_relative when the message holds
// no accelerometer sample (RELATIVE_TIMESTAMP_INVALID in PX4).
constexpr std::int64_t kRelativeTimestampInvalid = std::numeric_limits<std::int32_t>::max();
constexpr std::string_view kDefaultTopic = "sensor_combined";

// One channel: where its values are in a topic's messages.
struct ChannelSpec {
  const char* name;
  const char* unit;
  const char* field;
  std::size_t element;  // index in an array field
  double scale;         // to the unit
};

struct TopicKind {
  std::string_view topic;
  std::vector<ChannelSpec> channels;
};

const std::vector<TopicKind>& kinds() {
  static const std::vector<TopicKind> k = {
      {"sensor_combined",
       {{"gx", "rad/s", "gyro_rad", 0, 1.0},
        {"gy", "rad/s", "gyro_rad", 1, 1.0},
        {"gz", "rad/s", "gyro_rad", 2, 1.0},
        {"ax", "m/s^2", "accelerometer_m_s2", 0, 1.0},
        {"ay", "m/s^2", "accelerometer_m_s2", 1, 1.0},
        {"az", "m/s^2", "accelerometer_m_s2", 2, 1.0}}},
      {"vehicle_magnetometer",
       {{"mx", "T", "magnetometer_ga", 0, kTeslaPerGauss},
        {"my", "T", "magnetometer_ga", 1, kTeslaPerGauss},
        {"mz", "T", "magnetometer_ga", 2, kTeslaPerGauss}}},
      {"sensor_gyro",
       {{"gx", "rad/s", "x", 0, 1.0},
        {"gy", "rad/s", "y", 0, 1.0},
        {"gz", "rad/s", "z", 0, 1.0},
        {"temp", "degC", "temperature", 0, 1.0}}},
      {"sensor_accel",
       {{"ax", "m/s^2", "x", 0, 1.0},
        {"ay", "m/s^2", "y", 0, 1.0},
        {"az", "m/s^2", "z", 0, 1.0},
        {"temp", "degC", "temperature", 0, 1.0}}},
      {"sensor_mag",
       {{"mx", "T", "x", 0, kTeslaPerGauss},
        {"my", "T", "y", 0, kTeslaPerGauss},
        {"mz", "T", "z", 0, kTeslaPerGauss},
        {"temp", "degC", "temperature", 0, 1.0}}},
  };
  return k;
}

std::string readable_list() {
  std::string s;
  for (const auto& k : kinds()) s += (s.empty() ? "" : ", ") + std::string(k.topic);
  return s;
}

std::string rate_text(double hz) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, hz, std::chars_format::general, 4);
  return std::string(buf, r.ptr) + " Hz";
}

// "[n]" (built piece by piece: GCC 12 warns wrongly of an overlapping
// copy in "[" + std::string).
std::string bracketed(std::size_t n) {
  std::string s(1, '[');
  s += std::to_string(n);
  s += ']';
  return s;
}

std::string described(const ULogTopic& t) {
  return t.label() + " (" + std::to_string(t.messages.size()) + (t.messages.size() == 1 ? " message)" : " messages)");
}

std::string listed(const ULog& log) {
  if (log.topics.empty()) return "none";
  std::string s;
  for (const auto& t : log.topics) s += (s.empty() ? "" : ", ") + described(t);
  return s;
}

std::string dropout_text(const ULog& log) {
  if (log.dropouts.empty()) return "no dropouts";
  return std::to_string(log.dropouts.size()) + (log.dropouts.size() == 1 ? " dropout, " : " dropouts, ") +
         std::to_string(log.dropped_ms()) + " ms lost";
}

// The value of element `k` of a basic-typed field in the message data `d`.
double value_of(const ULogField& f, std::size_t k, std::string_view d) {
  const std::size_t at = f.offset + k * f.element_size;
  std::uint64_t raw = 0;
  for (std::size_t i = f.element_size; i-- > 0;) raw = raw << 8 | static_cast<unsigned char>(d[at + i]);
  const std::string& t = f.type;
  if (t == "float") return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(raw)));
  if (t == "double") return std::bit_cast<double>(raw);
  if (t == "int8_t") return static_cast<std::int8_t>(raw);
  if (t == "int16_t") return static_cast<std::int16_t>(raw);
  if (t == "int32_t") return static_cast<std::int32_t>(raw);
  if (t == "int64_t") return static_cast<double>(static_cast<std::int64_t>(raw));
  return static_cast<double>(raw);  // unsigned, bool, char
}

bool numeric(const ULogField& f) { return f.type != "char" && ulog_basic_size(f.type) != 0; }

struct Decoded {
  const ULogTopic* topic = nullptr;
  std::vector<double> time;  // seconds
  std::vector<TopicColumn> columns;
};

InputError message_error(const ULog& log, const Decoded& d, std::size_t i, const std::string& what, std::string hint) {
  return InputError(log.file, 0, 0,
                    "byte " + std::to_string(d.topic->messages[i].offset) + ": message " + std::to_string(i + 1) +
                        " of " + d.topic->label() + ": " + what,
                    std::move(hint));
}

const ULogTopic& find_topic(const ULog& log, const std::string& label) {
  for (const auto& t : log.topics)
    if (t.label() == label || (t.multi_id == 0 && label == t.name + ":0")) return t;
  throw InputError(log.file, 0, 0, "topic " + label + " not found; topics are: " + listed(log),
                   "choose one of them with {topics} NAME");
}

const ULogField& field_of(const ULog& log, const ULogTopic& t, const std::string& name, std::size_t element) {
  const ULogFormat& f = log.format_of(t);
  const ULogField* field = f.field(name);
  if (field == nullptr || !numeric(*field) || element >= field->count) {
    std::string fields;
    for (const auto& x : f.fields) {
      if (!fields.empty()) fields += ", ";
      fields += x.type;
      if (x.array) fields += bracketed(x.count);
      fields += ' ';
      fields += x.name;
    }
    throw InputError(log.file, 0, 0,
                     "topic " + t.label() + ": its format has no numeric field " + name +
                         (element > 0 ? bracketed(element) : "") + " (its fields: " + fields + ")",
                     "this PX4 version logs " + t.name + " differently: convert the log with pyulog's ulog2csv");
  }
  return *field;
}

Decoded decode(const ULog& log, std::string_view bytes, const ULogTopic& topic, const std::string& time_field) {
  const auto kind =
      std::find_if(kinds().begin(), kinds().end(), [&](const TopicKind& k) { return k.topic == topic.name; });
  if (kind == kinds().end())
    throw InputError(log.file, 0, 0,
                     "topic " + described(topic) + " is not one cubecal reads (" + readable_list() + ")",
                     "choose another topic with {topics} NAME");
  Decoded d;
  d.topic = &topic;
  const ULogField& time = field_of(log, topic, time_field, 0);
  if (time.type.find("int") == std::string::npos || time.array)
    throw InputError(log.file, 0, 0,
                     "topic " + topic.label() + ": field " + time_field + " is a " + time.type +
                         ", not an integer time stamp in microseconds",
                     "give {time_col} timestamp (the default) or another time stamp field");
  std::vector<const ULogField*> fields;
  for (const auto& c : kind->channels) {
    fields.push_back(&field_of(log, topic, c.field, c.element));
    const ULogField& f = *fields.back();
    d.columns.push_back({c.name, c.unit, std::string(c.field) + (f.array ? bracketed(c.element) : ""), {}});
    d.columns.back().values.reserve(topic.messages.size());
  }
  // sensor_combined: the accelerometer sample may be missing from a message.
  const ULogField* relative =
      topic.name == "sensor_combined" ? log.format_of(topic).field("accelerometer_timestamp_relative") : nullptr;
  if (relative != nullptr && !numeric(*relative)) relative = nullptr;
  d.time.reserve(topic.messages.size());
  for (std::size_t i = 0; i < topic.messages.size(); ++i) {
    const ULogMessage& m = topic.messages[i];
    std::string data(bytes.substr(m.begin, m.size));
    // The padding left out at the end reads as zeros.
    data.resize(log.format_of(topic).size, '\0');
    d.time.push_back(1e-6 * value_of(time, 0, data));
    for (std::size_t c = 0; c < fields.size(); ++c)
      d.columns[c].values.push_back(kind->channels[c].scale * value_of(*fields[c], kind->channels[c].element, data));
    if (relative != nullptr && value_of(*relative, 0, data) == static_cast<double>(kRelativeTimestampInvalid))
      for (std::size_t c = 0; c < fields.size(); ++c)
        if (kind->channels[c].name[0] == 'a') d.columns[c].values.back() = std::numeric_limits<double>::quiet_NaN();
  }
  // A sensor without a temperature logs NaN in every message: no channel.
  for (std::size_t c = 0; c < d.columns.size();) {
    const auto& v = d.columns[c].values;
    if (d.columns[c].name == "temp" && !v.empty() &&
        std::all_of(v.begin(), v.end(), [](double x) { return std::isnan(x); }))
      d.columns.erase(d.columns.begin() + static_cast<std::ptrdiff_t>(c));
    else
      ++c;
  }
  return d;
}

// The rate of a topic's time stamps (1 / median interval), 0 when unknown.
double rate_of(const std::vector<double>& t) {
  if (t.size() < 2) return 0.0;
  const double m = median_interval(t);
  return m > 0.0 ? 1.0 / m : 0.0;
}

}  // namespace

Series read_ulog_series(const ULog& log, std::string_view bytes, bool gzip, const SeriesOptions& opt) {
  if (std::any_of(opt.lsb.begin(), opt.lsb.end(), [](double v) { return v != 1.0; }))
    throw UsageError(Field::counts_per_unit,
                     log.file + " is a ULog file: its values are in SI units already, without an LSB");
  if (opt.table.skip_rows != 0) throw UsageError(log.file + " is a ULog file: it has no rows to skip");
  const std::string time_field = opt.time_col.empty() ? "timestamp" : opt.time_col;

  Series s;
  s.file = log.file;
  s.gzip = gzip;
  s.bytes = bytes.size();
  s.gaps = opt.gaps;
  s.default_topic = opt.topics.empty();
  const std::vector<std::string> wanted_topics =
      opt.topics.empty() ? std::vector<std::string>{std::string(kDefaultTopic)} : opt.topics;

  std::vector<Decoded> decoded;
  for (const auto& label : wanted_topics) {
    const ULogTopic& t = find_topic(log, label);
    if (std::any_of(decoded.begin(), decoded.end(), [&](const Decoded& d) { return d.topic == &t; })) continue;
    if (t.messages.empty())
      throw InputError(log.file, 0, 0, "topic " + t.label() + " has no data messages",
                       "choose another topic with {topics} NAME");
    decoded.push_back(decode(log, bytes, t, time_field));
  }
  // One channel name per topic; then the rates must agree.
  for (std::size_t a = 0; a < decoded.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      for (const auto& ca : decoded[a].columns)
        for (const auto& cb : decoded[b].columns)
          if (ca.name == cb.name)
            throw InputError(log.file, 0, 0,
                             "topics " + decoded[b].topic->label() + " and " + decoded[a].topic->label() +
                                 " both give channel " + ca.name,
                             "read them one at a time");
  const Decoded& first = decoded.front();
  for (const auto& d : decoded) {
    const double ra = rate_of(first.time);
    const double rb = rate_of(d.time);
    if (d.time.size() != first.time.size() || std::fabs(ra - rb) > opt.tolerance * std::max(ra, rb))
      throw InputError(log.file, 0, 0,
                       "topics " + described(*first.topic) + " at " + rate_text(ra) + " and " + described(*d.topic) +
                           " at " + rate_text(rb) + " are not sampled together: their samples cannot be paired",
                       "read them one at a time");
  }
  std::vector<TopicColumn> all;
  std::vector<const Decoded*> source;  // the topic of each column
  for (auto& d : decoded)
    for (auto& c : d.columns) {
      all.push_back(std::move(c));
      source.push_back(&d);
    }
  for (const auto& d : decoded) s.topics.push_back(described(*d.topic) + ", " + dropout_text(log));
  // Only the channels read are checked: a message without an accelerometer
  // sample does not stop a run on the gyro channels.
  const auto check = [&](std::size_t i) {
    if (auto f = value_fault(all[i], " (or the sample is marked invalid)", "cut the log, or read another topic"))
      throw message_error(log, *source[i], f->index, f->what, std::move(f->hint));
  };
  take_channels(s, all, opt, check, log.file, "no channels besides the temperature in the topics read",
                "read sensor_combined or a magnetometer topic with {topics} NAME");

  const bool timing = !opt.time_col.empty() || opt.rate_hz == 0.0;
  finish_series(s, first.time, first.topic->label() + "." + time_field, timing, opt,
                [&](std::size_t row, std::string problem, std::string hint) {
                  if (!log.dropouts.empty()) hint += "; the logger reports " + dropout_text(log);
                  return message_error(log, first, row, problem, std::move(hint));
                });
  for (const auto& d : decoded) {
    for (std::size_t i = 0; i < d.time.size(); ++i) {
      if (std::fabs(d.time[i] - first.time[i]) <= opt.tolerance * s.tau0) continue;
      throw message_error(log, d, i,
                          "stamped " + shortest(d.time[i]) + " s, " + first.topic->label() + "'s message " +
                              std::to_string(i + 1) + " " + shortest(first.time[i]) + " s: the samples do not pair",
                          "read the topics one at a time");
    }
  }
  return s;
}

}  // namespace cubecal::io::detail
