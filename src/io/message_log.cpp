#include "cubecal/io/message_log.hpp"

#include <utility>

#include "cubecal/error.hpp"
#include "cubecal/io/ros1_bag.hpp"

namespace cubecal::io {

std::string LogTopic::described() const {
  return name + " (" + type + ", " + std::to_string(messages) + (messages == 1 ? " message)" : " messages)");
}

std::string MessageLog::where(const LogMessage& m) const {
  const bool part = m.part < parts.size();
  switch (m.place) {
    case MessagePlace::byte: return "at byte " + std::to_string(m.offset) + (part ? " of " + parts[m.part] : "");
    case MessagePlace::chunk:
      return "in the chunk at byte " + std::to_string(m.offset) + (part ? " of " + parts[m.part] : "");
    case MessagePlace::row: break;
  }
  return "row " + std::to_string(m.offset) + " of " + (part ? parts[m.part] + "'s" : "the") + " messages table";
}

std::uint32_t MessageLog::topic(const std::string& name, const std::string& type, const std::string& encoding) {
  for (std::size_t i = 0; i < topics.size(); ++i) {
    if (topics[i].name != name) continue;
    if (topics[i].type != type || topics[i].encoding != encoding)
      throw InputError(file, 0, 0,
                       "topic " + name + " is declared both as " + topics[i].type + " (" + topics[i].encoding +
                           ") and as " + type + " (" + encoding + ")",
                       "the log is corrupt, or was merged from other logs");
    return static_cast<std::uint32_t>(i);
  }
  topics.push_back({name, type, encoding, 0, std::nullopt});
  return static_cast<std::uint32_t>(topics.size() - 1);
}

void MessageLog::append(MessageLog&& other, const std::string& part_name) {
  const auto part = static_cast<std::uint32_t>(parts.size());
  parts.push_back(part_name);
  std::vector<std::uint32_t> to(other.topics.size());
  for (std::size_t i = 0; i < other.topics.size(); ++i) {
    const LogTopic& t = other.topics[i];
    to[i] = topic(t.name, t.type, t.encoding);
    LogTopic& mine = topics[to[i]];
    mine.messages += t.messages;
    if (t.counted) mine.counted = mine.counted.value_or(0) + *t.counted;
  }
  const std::size_t base = payload.size();
  payload += other.payload;
  messages.reserve(messages.size() + other.messages.size());
  for (LogMessage m : other.messages) {
    m.topic = to[m.topic];
    m.part = part;
    m.begin += base;
    messages.push_back(m);
  }
}

MessageLog message_log(Ros1Bag&& bag) {
  MessageLog log;
  log.file = bag.file;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> topic_of;  // connection id -> topic
  for (const auto& c : bag.connections) {
    const std::uint32_t t = log.topic(c.topic, c.type, "ros1");
    LogTopic& topic = log.topics[t];
    topic.messages += c.messages;
    if (c.indexed != 0) topic.counted = topic.counted.value_or(0) + c.indexed;
    topic_of.emplace_back(c.id, t);
  }
  log.messages.reserve(bag.messages.size());
  for (const auto& m : bag.messages) {
    LogMessage l;
    for (const auto& [id, t] : topic_of)
      if (id == m.connection) l.topic = t;
    l.place = m.compressed ? MessagePlace::chunk : MessagePlace::byte;
    l.offset = m.offset;
    l.sec = m.sec;
    l.nsec = m.nsec;
    l.begin = m.begin;
    l.size = m.size;
    log.messages.push_back(l);
  }
  log.payload = std::move(bag.payload);
  return log;
}

}  // namespace cubecal::io
