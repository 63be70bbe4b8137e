// The manifest of a recording directory (recording_manifest.hpp): its JSON
// and its atomic, durable replacement.
#include "cubecal/io/recording_manifest.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"

namespace cubecal::io {

namespace {

using json = nlohmann::ordered_json;

json optional_string(const std::optional<std::string>& s) { return s ? json(*s) : json(nullptr); }

json to_json(const RecordingEvent& e) {
  json j;
  j["kind"] = std::string(to_string(e.kind));
  j["sample"] = e.sample;
  switch (e.kind) {
    case RecordingEvent::Kind::gap:
      j["device_time"] = e.device_time;
      j["dt"] = e.dt;
      j["expected_dt"] = e.expected_dt;
      break;
    case RecordingEvent::Kind::reset:
      j["device_time"] = e.device_time;
      j["previous"] = e.previous;
      break;
    case RecordingEvent::Kind::reconnect: j["host_utc_s"] = e.host_utc_s; break;
  }
  return j;
}

json to_json(const RecordingChunk& c) {
  json j;
  j["file"] = c.file;
  j["samples"] = c.samples;
  j["bytes"] = c.bytes;
  j["crc32"] = c.crc32 ? json(crc32_hex(*c.crc32)) : json(nullptr);
  j["first_host_utc_s"] = c.first_host_utc_s;
  j["last_host_utc_s"] = c.last_host_utc_s;
  j["open"] = c.open;
  return j;
}

json to_json(const RecordingSegment& s) {
  json j;
  j["index"] = s.index;
  j["dir"] = s.dir;
  j["start_utc"] = s.start_utc;
  j["start_mono_s"] = s.start_mono_s;
  j["end_utc"] = s.end_utc.empty() ? json(nullptr) : json(s.end_utc);
  j["end"] = std::string(to_string(s.end));
  j["samples"] = s.samples;
  j["rejects"] = s.rejects;
  j["partial_bytes"] = s.partial_bytes;
  j["chunks"] = json::array();
  for (const auto& c : s.chunks) j["chunks"].push_back(to_json(c));
  j["events"] = json::array();
  for (const auto& e : s.events) j["events"].push_back(to_json(e));
  return j;
}

// Reading: every missing or mistyped field is an InputError naming the field.
class Reader {
 public:
  explicit Reader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file_, 0, 0, what, "the manifest of a cubecal recording directory");
  }

  const json& field(const json& obj, const char* name, const std::string& where) const {
    if (!obj.is_object()) fail(where + " is not an object");
    const auto it = obj.find(name);
    if (it == obj.end()) fail(where + ": \"" + name + "\" is missing");
    return *it;
  }

  std::string str(const json& obj, const char* name, const std::string& where) const {
    const json& v = field(obj, name, where);
    if (!v.is_string()) fail(where + ": \"" + name + "\" is not a string");
    return v.get<std::string>();
  }
  std::optional<std::string> opt_str(const json& obj, const char* name, const std::string& where) const {
    const auto it = obj.find(name);
    if (it == obj.end() || it->is_null()) return std::nullopt;
    if (!it->is_string()) fail(where + ": \"" + name + "\" is not a string or null");
    return it->get<std::string>();
  }
  double num(const json& obj, const char* name, const std::string& where) const {
    const json& v = field(obj, name, where);
    if (!v.is_number()) fail(where + ": \"" + name + "\" is not a number");
    return v.get<double>();
  }
  std::optional<double> opt_num(const json& obj, const char* name, const std::string& where) const {
    const auto it = obj.find(name);
    if (it == obj.end() || it->is_null()) return std::nullopt;
    if (!it->is_number()) fail(where + ": \"" + name + "\" is not a number or null");
    return it->get<double>();
  }
  std::size_t count(const json& obj, const char* name, const std::string& where) const {
    const json& v = field(obj, name, where);
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<long long>() >= 0))
      fail(where + ": \"" + name + "\" is not a non-negative integer");
    return v.get<std::size_t>();
  }
  bool boolean(const json& obj, const char* name, const std::string& where) const {
    const json& v = field(obj, name, where);
    if (!v.is_boolean()) fail(where + ": \"" + name + "\" is not true or false");
    return v.get<bool>();
  }
  const json& array(const json& obj, const char* name, const std::string& where) const {
    const json& v = field(obj, name, where);
    if (!v.is_array()) fail(where + ": \"" + name + "\" is not an array");
    return v;
  }

  RecordingEvent event(const json& j, const std::string& where) const {
    RecordingEvent e;
    const std::string kind = str(j, "kind", where);
    e.sample = count(j, "sample", where);
    if (kind == "gap") {
      e.kind = RecordingEvent::Kind::gap;
      e.device_time = num(j, "device_time", where);
      e.dt = num(j, "dt", where);
      e.expected_dt = num(j, "expected_dt", where);
    } else if (kind == "reset") {
      e.kind = RecordingEvent::Kind::reset;
      e.device_time = num(j, "device_time", where);
      e.previous = num(j, "previous", where);
    } else if (kind == "reconnect") {
      e.kind = RecordingEvent::Kind::reconnect;
      e.host_utc_s = num(j, "host_utc_s", where);
    } else {
      fail(where + ": unknown event kind \"" + kind + "\" (gap, reset or reconnect)");
    }
    return e;
  }

  RecordingChunk chunk(const json& j, const std::string& where) const {
    RecordingChunk c;
    c.file = str(j, "file", where);
    if (c.file.empty() || c.file.find('/') != std::string::npos || c.file == "." || c.file == "..")
      fail(where + ": \"file\" must be a plain file name");
    c.samples = count(j, "samples", where);
    c.bytes = count(j, "bytes", where);
    if (const auto crc = opt_str(j, "crc32", where)) {
      if (crc->size() != 8 || crc->find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
        fail(where + ": \"crc32\" is not 8 hexadecimal digits");
      c.crc32 = static_cast<std::uint32_t>(std::stoul(*crc, nullptr, 16));
    }
    c.first_host_utc_s = num(j, "first_host_utc_s", where);
    c.last_host_utc_s = num(j, "last_host_utc_s", where);
    c.open = boolean(j, "open", where);
    if (!c.open && !c.crc32) fail(where + ": a closed chunk without \"crc32\"");
    return c;
  }

  RecordingSegment segment(const json& j, const std::string& where) const {
    RecordingSegment s;
    const double index = num(j, "index", where);
    if (index < 1 || index > 999999 || index != static_cast<double>(static_cast<int>(index)))
      fail(where + ": \"index\" is not a positive integer");
    s.index = static_cast<int>(index);
    s.dir = str(j, "dir", where);
    if (s.dir.empty() || s.dir.find('/') != std::string::npos || s.dir == "." || s.dir == "..")
      fail(where + ": \"dir\" must be a plain directory name");
    s.start_utc = str(j, "start_utc", where);
    s.start_mono_s = num(j, "start_mono_s", where);
    s.end_utc = opt_str(j, "end_utc", where).value_or("");
    const std::string end = str(j, "end", where);
    if (end == "open")
      s.end = SegmentEnd::open;
    else if (end == "clean")
      s.end = SegmentEnd::clean;
    else if (end == "recovered")
      s.end = SegmentEnd::recovered;
    else
      fail(where + ": \"end\" is \"" + end + "\" (open, clean or recovered)");
    s.samples = count(j, "samples", where);
    s.rejects = count(j, "rejects", where);
    s.partial_bytes = count(j, "partial_bytes", where);
    const json& chunks = array(j, "chunks", where);
    for (std::size_t i = 0; i < chunks.size(); ++i)
      s.chunks.push_back(chunk(chunks[i], where + " chunk " + std::to_string(i + 1)));
    const json& events = array(j, "events", where);
    for (std::size_t i = 0; i < events.size(); ++i)
      s.events.push_back(event(events[i], where + " event " + std::to_string(i + 1)));
    return s;
  }

 private:
  std::string file_;
};

}  // namespace

std::string_view to_string(SegmentEnd e) noexcept {
  switch (e) {
    case SegmentEnd::open: return "open";
    case SegmentEnd::clean: return "clean";
    case SegmentEnd::recovered: return "recovered";
  }
  return "open";
}

std::string_view to_string(RecordingEvent::Kind k) noexcept {
  switch (k) {
    case RecordingEvent::Kind::gap: return "gap";
    case RecordingEvent::Kind::reset: return "reset";
    case RecordingEvent::Kind::reconnect: return "reconnect";
  }
  return "gap";
}

std::string crc32_hex(std::uint32_t crc) {
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", static_cast<unsigned>(crc));
  return buf;
}

namespace {

json to_json(const RecordingManifest& m) {
  json j;
  j["format"] = m.format;
  j["columns"] = m.columns;
  j["time_column"] = optional_string(m.time_column);
  j["rate_hz"] = m.rate_hz ? json(*m.rate_hz) : json(nullptr);
  j["unit"] = optional_string(m.unit);
  json framing;
  if (m.framing.kind == RecordingFraming::Kind::text) {
    framing["kind"] = "text";
    framing["delimiter"] = m.framing.delimiter;
  } else {
    framing["kind"] = "binary";
    framing["frame"] = m.framing.frame;
  }
  j["framing"] = framing;
  j["source"] = m.source;
  j["segments"] = json::array();
  for (const auto& s : m.segments) j["segments"].push_back(to_json(s));
  return j;
}

// The manifest of a JSON document; `file` names it in errors.
RecordingManifest manifest_from_json(const json& j, const std::string& file) {
  Reader r(file);
  RecordingManifest m;
  const std::string where = "manifest";
  m.format = r.str(j, "format", where);
  if (m.format != kRecordingFormat)
    r.fail("format \"" + m.format + "\" is not \"" + std::string(kRecordingFormat) + "\"");
  const json& cols = r.array(j, "columns", where);
  for (const auto& c : cols) {
    if (!c.is_string()) r.fail("manifest: \"columns\" holds a value that is not a string");
    m.columns.push_back(c.get<std::string>());
  }
  m.time_column = r.opt_str(j, "time_column", where);
  m.rate_hz = r.opt_num(j, "rate_hz", where);
  m.unit = r.opt_str(j, "unit", where);
  const json& framing = r.field(j, "framing", where);
  const std::string kind = r.str(framing, "kind", "framing");
  if (kind == "text") {
    m.framing.kind = RecordingFraming::Kind::text;
    m.framing.delimiter = r.str(framing, "delimiter", "framing");
  } else if (kind == "binary") {
    m.framing.kind = RecordingFraming::Kind::binary;
    m.framing.frame = r.str(framing, "frame", "framing");
  } else {
    r.fail("framing: \"kind\" is \"" + kind + "\" (text or binary)");
  }
  m.source = r.str(j, "source", where);
  const json& segs = r.array(j, "segments", where);
  for (std::size_t i = 0; i < segs.size(); ++i)
    m.segments.push_back(r.segment(segs[i], "segment " + std::to_string(i + 1)));
  return m;
}

}  // namespace

std::string manifest_text(const RecordingManifest& m) { return to_json(m).dump(2) + "\n"; }

RecordingManifest parse_manifest(std::string_view text, const std::string& file) {
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, out_of_range (a number beyond a double)
    Reader(file).fail(std::string("not valid JSON: ") + e.what());
  }
  return manifest_from_json(j, file);
}

RecordingManifest read_manifest(const std::string& dir) {
  const std::string path = dir + "/" + std::string(kManifestName);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "cannot be read", "a cubecal recording directory holds manifest.json");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_manifest(ss.str(), path);
}

bool is_recording_dir(const std::string& dir) {
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) return false;
  std::ifstream in(dir + "/" + std::string(kManifestName), std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  const json j = json::parse(ss.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return false;
  const auto it = j.find("format");
  return it != j.end() && it->is_string() && it->get<std::string>() == kRecordingFormat;
}

void write_manifest(const std::string& dir, const RecordingManifest& m) {
  replace_file_atomically(dir + "/" + std::string(kManifestName), manifest_text(m));
}

std::string utc_iso8601(std::int64_t seconds, long nanoseconds) {
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%09ldZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, nanoseconds);
  return buf;
}

}  // namespace cubecal::io
