#include "bag_series.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "cubecal/error.hpp"
#include "cdr_messages.hpp"
#include "ros1_messages.hpp"
#include "series_timing.hpp"
#include "topic_channels.hpp"

namespace cubecal::io::detail {

namespace {

constexpr std::string_view kImu = "sensor_msgs/Imu";
constexpr std::string_view kMag = "sensor_msgs/MagneticField";
constexpr std::string_view kTemp = "sensor_msgs/Temperature";

using Topic = LogTopic;

// The message a type name designates, in ROS 1 ("sensor_msgs/Imu") or ROS 2
// ("sensor_msgs/msg/Imu") spelling.
enum class Kind { imu, mag, temp, other };

Kind kind_of(const Topic& t) {
  std::string type = t.type;
  if (const auto p = type.find("/msg/"); p != std::string::npos) type.erase(p, 4);
  if (type == kImu) return Kind::imu;
  if (type == kMag) return Kind::mag;
  if (type == kTemp) return Kind::temp;
  return Kind::other;
}

bool decodable(const Topic& t) { return t.encoding == "ros1" || t.encoding == "cdr"; }

std::string listed(const std::vector<const Topic*>& topics) {
  if (topics.empty()) return "none";
  std::string s;
  for (const Topic* t : topics) s += (s.empty() ? "" : ", ") + t->described();
  return s;
}

std::string listed(const std::vector<Topic>& topics) {
  std::vector<const Topic*> all;
  for (const auto& t : topics) all.push_back(&t);
  return listed(all);
}

InputError not_decodable(const MessageLog& bag, const Topic& t) {
  return InputError(
      bag.file, 0, 0,
      "topic " + t.described() + " is serialized as '" + t.encoding + "', not as ROS 1 (ros1) or ROS 2 (cdr) messages",
      "choose another topic");
}

std::vector<const Topic*> choose_topics(const MessageLog& bag, const std::vector<Topic>& topics,
                                        const SeriesOptions& opt, bool& by_default) {
  std::vector<const Topic*> chosen;
  by_default = opt.topics.empty();
  if (opt.topics.empty()) {
    for (const auto& t : topics)
      if (kind_of(t) == Kind::imu) chosen.push_back(&t);
    if (chosen.empty())
      throw InputError(bag.file, 0, 0, "no sensor_msgs/Imu topic; topics are: " + listed(topics),
                       "choose the topics to read with {topics} NAME");
    if (chosen.size() > 1)
      throw InputError(bag.file, 0, 0, "several sensor_msgs/Imu topics: " + listed(chosen),
                       "choose one with {topics} NAME");
    if (!decodable(*chosen.front())) throw not_decodable(bag, *chosen.front());
    return chosen;
  }
  for (const auto& name : opt.topics) {
    const auto it = std::find_if(topics.begin(), topics.end(), [&](const Topic& t) { return t.name == name; });
    if (it == topics.end())
      throw InputError(bag.file, 0, 0, "topic " + name + " not found; topics are: " + listed(topics),
                       "choose one of them with {topics} NAME");
    if (kind_of(*it) == Kind::other)
      throw InputError(bag.file, 0, 0,
                       "topic " + it->described() + " is not of a type cubecal reads (" + std::string(kImu) + ", " +
                           std::string(kMag) + ", " + std::string(kTemp) + ")",
                       "choose another topic");
    if (!decodable(*it)) throw not_decodable(bag, *it);
    if (std::find(chosen.begin(), chosen.end(), &*it) != chosen.end()) continue;
    for (const Topic* t : chosen)
      if (kind_of(*t) == kind_of(*it))
        throw InputError(bag.file, 0, 0, "topics " + t->name + " and " + it->name + " are both " + it->type,
                         "read one " + it->type + " topic per run");
    chosen.push_back(&*it);
  }
  return chosen;
}

// One topic's messages decoded: their times and their values.
struct Decoded {
  const Topic* topic = nullptr;
  std::vector<const LogMessage*> messages;
  std::vector<double> time;
  std::vector<TopicColumn> columns;
};

InputError message_error(const MessageLog& bag, const Decoded& d, std::size_t i, const std::string& what,
                         std::string hint) {
  return bag_message_error(bag, *d.messages[i], i + 1, d.topic->name, what, std::move(hint));
}

Decoded decode(const MessageLog& bag, std::uint32_t index, bool record_time) {
  const Topic& topic = bag.topics[index];
  Decoded d;
  d.topic = &topic;
  d.columns = bag_columns(topic);
  for (auto& c : d.columns) c.values.reserve(topic.messages);
  d.time.reserve(topic.messages);
  for (const auto& m : bag.messages) {
    if (m.topic != index) continue;
    d.messages.push_back(&m);
    d.time.push_back(decode_bag_message(bag, m, d.messages.size(), d.columns, record_time));
  }
  return d;
}

}  // namespace

InputError bag_message_error(const MessageLog& bag, const LogMessage& m, std::size_t number, const std::string& topic,
                             const std::string& what, std::string hint) {
  return InputError(bag.file, 0, 0,
                    "message " + std::to_string(number) + " of " + topic + " (" + bag.where(m) + "): " + what,
                    std::move(hint));
}

std::vector<const LogTopic*> choose_bag_topics(const MessageLog& bag, const SeriesOptions& opt, bool& by_default) {
  return choose_topics(bag, bag.topics, opt, by_default);
}

bool is_imu_topic(const LogTopic& topic) { return kind_of(topic) == Kind::imu; }

std::vector<TopicColumn> bag_columns(const LogTopic& topic) {
  std::vector<TopicColumn> columns;
  const auto add = [&](const char* name, const char* unit, const char* field) {
    columns.push_back({name, unit, field, {}});
  };
  const Kind kind = kind_of(topic);
  if (kind == Kind::imu) {
    add("gx", "rad/s", "angular_velocity.x");
    add("gy", "rad/s", "angular_velocity.y");
    add("gz", "rad/s", "angular_velocity.z");
    add("ax", "m/s^2", "linear_acceleration.x");
    add("ay", "m/s^2", "linear_acceleration.y");
    add("az", "m/s^2", "linear_acceleration.z");
  } else if (kind == Kind::mag) {
    add("mx", "T", "magnetic_field.x");
    add("my", "T", "magnetic_field.y");
    add("mz", "T", "magnetic_field.z");
  } else {
    add("temp", "degC", "temperature");
  }
  return columns;
}

double decode_bag_message(const MessageLog& bag, const LogMessage& m, std::size_t number,
                          std::vector<TopicColumn>& columns, bool record_time) {
  const Topic& topic = bag.topics[m.topic];
  const Kind kind = kind_of(topic);
  const bool cdr = topic.encoding == "cdr";
  const std::string_view bytes = bag.data(m);
  Stamp stamp;
  try {
    if (kind == Kind::imu) {
      const ImuMessage imu = cdr ? decode_cdr_imu(bytes) : decode_imu(bytes);
      stamp = imu.stamp;
      for (int k = 0; k < 3; ++k) columns[static_cast<std::size_t>(k)].values.push_back(imu.angular_velocity[k]);
      for (int k = 0; k < 3; ++k) columns[static_cast<std::size_t>(3 + k)].values.push_back(imu.linear_acceleration[k]);
    } else if (kind == Kind::mag) {
      const MagneticFieldMessage mag = cdr ? decode_cdr_magnetic_field(bytes) : decode_magnetic_field(bytes);
      stamp = mag.stamp;
      for (int k = 0; k < 3; ++k) columns[static_cast<std::size_t>(k)].values.push_back(mag.magnetic_field[k]);
    } else {
      const TemperatureMessage t = cdr ? decode_cdr_temperature(bytes) : decode_temperature(bytes);
      stamp = t.stamp;
      columns[0].values.push_back(t.temperature);
    }
  } catch (const MessageLayoutError& e) {
    throw bag_message_error(bag, m, number, topic.name,
                            std::string(e.what()) + " (byte " + std::to_string(e.position()) + " of its " +
                                std::to_string(bytes.size()) + ")",
                            "the bag is corrupt, or the topic's message definition is not the standard " + topic.type);
  }
  if (record_time) stamp = {m.sec, m.nsec};
  return static_cast<double>(stamp.sec) + 1e-9 * static_cast<double>(stamp.nsec);
}

bool bag_time_is_record(const std::string& file, const SeriesOptions& opt) {
  if (std::any_of(opt.lsb.begin(), opt.lsb.end(), [](double v) { return v != 1.0; }))
    throw UsageError(Field::counts_per_unit,
                     file + " is a ROS bag: its values are in SI units already, without an LSB");
  if (opt.table.skip_rows != 0) throw UsageError(file + " is a ROS bag: it has no rows to skip");
  if (opt.time_col == "record") return true;
  if (!opt.time_col.empty() && opt.time_col != "stamp")
    throw UsageError(Field::time_col, file +
                                          " is a ROS bag: its time is 'stamp' (header.stamp, the default) or "
                                          "'record' (when the bag recorded each message), not '" +
                                          opt.time_col + "'");
  return false;
}

Series read_bag_series(const MessageLog& bag, bool gzip, const SeriesOptions& opt) {
  const bool record_time = bag_time_is_record(bag.file, opt);
  const std::string time_name = record_time ? "record time" : "header.stamp";

  const std::vector<Topic>& topics = bag.topics;
  Series s;
  s.file = bag.file;
  s.gzip = gzip;
  s.bytes = bag.payload.size();
  s.gaps = opt.gaps;
  const std::vector<const Topic*> chosen = choose_topics(bag, topics, opt, s.default_topic);

  std::vector<Decoded> decoded;
  for (const Topic* t : chosen)
    decoded.push_back(decode(bag, static_cast<std::uint32_t>(t - topics.data()), record_time));
  // Channels in a fixed order whatever the order of --topic: IMU, field, temperature.
  const auto rank = [](const Decoded& d) { return static_cast<int>(kind_of(*d.topic)); };
  std::stable_sort(decoded.begin(), decoded.end(),
                   [&](const Decoded& a, const Decoded& b) { return rank(a) < rank(b); });
  const Decoded& first = decoded.front();
  for (const auto& d : decoded) {
    if (d.time.size() != first.time.size())
      throw InputError(bag.file, 0, 0,
                       "topics " + first.topic->described() + " and " + d.topic->described() +
                           " differ in length: their samples cannot be paired",
                       "read them one at a time");
  }
  std::vector<TopicColumn> all;
  std::vector<const Decoded*> source;  // the topic of each column
  for (auto& d : decoded)
    for (auto& c : d.columns) {
      all.push_back(std::move(c));
      source.push_back(&d);
    }
  for (const Topic* t : chosen) s.topics.push_back(t->described());
  // Drivers mark samples without a new reading with NaN (the Phidgets
  // magnetometer every other message): the fault says how many there are.
  const auto check = [&](std::size_t i) {
    const auto& c = all[i];
    const auto nans = std::count_if(c.values.begin(), c.values.end(), [](double x) { return std::isnan(x); });
    if (auto f = value_fault(c, "",
                             nans > 1 ? "the driver publishes NaN where it has no reading: leave this topic out"
                                      : "cut the record before this message"))
      throw message_error(bag, *source[i], f->index, f->what, std::move(f->hint));
  };
  take_channels(s, all, opt, check, bag.file, "no channels besides the temperature in " + listed(chosen),
                "read a sensor_msgs/Imu or MagneticField topic with {topics} NAME");

  const bool timing = !opt.time_col.empty() || opt.rate_hz == 0.0;
  finish_series(s, first.time, first.topic->name + " " + time_name, timing, opt,
                [&](std::size_t row, std::string problem, std::string hint) {
                  return message_error(bag, first, row, problem, std::move(hint));
                });
  // The other topics' samples must be the same instants.
  for (const auto& d : decoded) {
    for (std::size_t i = 0; i < d.time.size(); ++i) {
      if (std::fabs(d.time[i] - first.time[i]) <= opt.tolerance * s.tau0) continue;
      throw message_error(bag, d, i,
                          "stamped " + shortest(d.time[i]) + " s, " + first.topic->name + "'s message " +
                              std::to_string(i + 1) + " " + shortest(first.time[i]) + " s: the samples do not pair",
                          "read the topics one at a time");
    }
  }
  return s;
}

}  // namespace cubecal::io::detail
