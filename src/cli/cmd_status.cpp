// cubecal status DIR: the live status of a recording (record --target) from
// another terminal: each channel's terms with their interval, precision now
// against the target, the time still needed; the status's age and whether
// the recorder still runs (docs/record.md).
#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/pipeline/record_status.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::cli {

namespace {

struct StatusCliOptions {
  std::string dir;
  std::string format = "table";
};

// A manifest not rewritten for this long while its segment is open: the
// recorder (which rewrites it every 0.5 s) is not running.
constexpr double kStaleManifestS = 5.0;

double now_unix() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double mtime_of(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0.0;
  return static_cast<double>(st.st_mtim.tv_sec) + 1e-9 * static_cast<double>(st.st_mtim.tv_nsec);
}

std::string hms(double s) {
  if (!std::isfinite(s)) return "?";
  const auto t = static_cast<long long>(std::ceil(std::max(0.0, s)));
  return fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60);
}

std::string age_text(double s) {
  if (s < 120) return fmt::format("{:.0f} s", std::max(0.0, s));
  if (s < 7200) return fmt::format("{:.0f} min", s / 60);
  return fmt::format("{:.1f} h", s / 3600);
}

// Whether the recorder still runs, from the manifest (rewritten every 0.5 s
// while a segment is open).
std::string recorder_state(const std::string& dir, const io::RecordingManifest& m, int status_segment) {
  if (m.segments.empty()) return "no segment yet";
  const io::RecordingSegment& last = m.segments.back();
  std::string s;
  if (last.end == io::SegmentEnd::clean)
    s = fmt::format("ended cleanly ({})", last.end_utc);
  else if (last.end == io::SegmentEnd::recovered)
    s = "ended by a crash, recovered by a restart";
  else {
    const double age = now_unix() - mtime_of(dir + "/" + std::string(io::kManifestName));
    s = age <= kStaleManifestS
            ? "running"
            : fmt::format(
                  "not running: segment {} is open but the manifest has not changed for {} (killed? a "
                  "restart with the same --out recovers it)",
                  last.index, age_text(age));
  }
  if (status_segment > 0 && status_segment != last.index)
    s += fmt::format("; this status is of segment {}, the recording's last is segment {}", status_segment, last.index);
  return s;
}

// A field of the status as a flag: false when missing or not a boolean.
bool flag(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_boolean() && it->get<bool>();
}

std::string number(const nlohmann::json& v, int digits = 4) {
  return v.is_number() ? fmt::format("{:.{}g}", v.get<double>(), digits) : std::string("—");
}

// "12.7 ± 0.28 deg/h [12.4, 13.0]", or the bound, or "—".
std::string value_text(const nlohmann::json& t) {
  const nlohmann::json& d = t.at("display");
  const std::string unit = d.value("unit", "");
  if (!flag(t, "resolved")) {
    if (flag(t, "upper_bound") && d.at("value").is_number()) return "< " + number(d.at("value")) + " " + unit;
    return "—";
  }
  std::string s = number(d.at("value")) + " ± " + number(d.at("sigma"), 2) + " " + unit;
  const nlohmann::json& iv = d.at("interval");
  if (iv.is_array() && iv.size() == 2) s += " [" + number(iv[0]) + ", " + number(iv[1]) + "]";
  return s;
}

// Characters on a terminal (the ± and — of the table are one each).
std::size_t utf8_width(const std::string& s) {
  std::size_t n = 0;
  for (const char c : s) n += (static_cast<unsigned char>(c) & 0xc0) != 0x80 ? 1 : 0;
  return n;
}

std::string percent(const nlohmann::json& v) {
  return v.is_number() ? fmt::format("{:.3g}%", 100.0 * v.get<double>()) : std::string("—");
}

// One line per term: channel, term, value, precision now / target, met,
// still needed; columns as wide as their widest cell.
std::string table_text(const nlohmann::json& j) {
  std::string out;
  std::vector<std::array<std::string, 7>> rows = {
      {"channel", "term", "value ± 1 sigma [interval at ci]", "precision", "target", "met", "still needed"}};
  std::vector<std::string> notes;
  for (const auto& ch : j.at("channels")) {
    const std::string name = printable_text(ch.value("name", ""));
    if (ch.at("terms").empty()) notes.push_back(name + ": " + printable_text(ch.value("why", "")));
    for (const auto& t : ch.at("terms")) {
      const bool target = t.at("target").is_number();
      const bool met = flag(t, "met");
      std::string needed;
      if (target) needed = t.at("remaining_s").is_number() ? hms(t.at("remaining_s").get<double>()) : "unknown";
      const std::string why = t.value("why", "");
      if (!met && !why.empty()) needed += (needed.empty() ? "" : ": ") + why;
      rows.push_back({name, t.value("term", "?"), value_text(t), percent(t.at("precision")),
                      target ? percent(t.at("target")) : "", target ? (met ? "yes" : "no") : "",
                      printable_text(needed)});
    }
  }
  std::array<std::size_t, 7> width{};
  for (const auto& r : rows)
    for (std::size_t k = 0; k < r.size(); ++k) width[k] = std::max(width[k], utf8_width(r[k]));
  for (const auto& r : rows) {
    std::string line;
    for (std::size_t k = 0; k < r.size(); ++k) {
      const std::size_t pad = width[k] - utf8_width(r[k]);
      const bool right = k == 3 || k == 4;
      if (k + 1 == r.size()) {
        line += r[k];
        break;
      }
      line += right ? std::string(pad, ' ') + r[k] : r[k] + std::string(pad, ' ');
      line += "  ";
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  for (const auto& n : notes) out += n + "\n";
  return out;
}

// The status for people: its age, the record so far, the recorder's state,
// the targets and the table.
std::string status_text(const nlohmann::json& j, const std::string& dir, const io::RecordingManifest& m) {
  const double written = j.value("written_unix_s", 0.0);
  std::string out =
      fmt::format("{}: status of {} ago{}; segment {}, {} samples at {} Hz ({} recorded); recorder {}\n",
                  printable_text(dir), age_text(now_unix() - written), flag(j, "final") ? " (the run's last)" : "",
                  j.value("segment", 0), j.value("samples", std::size_t{0}), number(j.at("rate_hz"), 9),
                  hms(j.value("record_s", 0.0)), recorder_state(dir, m, j.value("segment", 0)));
  std::string targets;
  for (const auto& t : j.at("targets"))
    targets += (targets.empty() ? "" : ",") + t.value("term", "?") + ":" + percent(t.at("precision"));
  out += fmt::format("targets {} at {:.3g}% confidence: {}\n", targets.empty() ? "none" : targets,
                     100.0 * j.value("ci", 0.683), flag(j, "all_met") ? "all met" : "not all met");
  const std::string why = j.value("why", "");
  if (!why.empty()) out += printable_text(why) + "\n";
  return out + table_text(j);
}

int run_status_command(const StatusCliOptions& o) {
  std::string dir = o.dir;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  struct stat st {};
  if (::stat((dir + "/" + std::string(io::kManifestName)).c_str(), &st) != 0)
    throw UsageError(printable_text(dir) +
                     " is not a recording directory (no manifest.json): give the --out DIR of "
                     "cubecal record");
  const io::RecordingManifest m = io::read_manifest(dir);
  const std::string path = dir + "/" + std::string(pipeline::kStatusName);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw UsageError(printable_text(dir) +
                     " has no status.json yet: cubecal record writes it with --target, at the first --status-every "
                     "of recorded time (and at the end of the run)");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
    if (j.value("format", "") != pipeline::kStatusFormat || !j.at("channels").is_array())
      throw std::runtime_error(std::string("not a status of the format ") + std::string(pipeline::kStatusFormat));
  } catch (const std::exception& e) {
    throw InputError(path, 0, 0, std::string("not a readable status: ") + e.what(),
                     "the file is written by cubecal record --target; wait for the next status");
  }
  if (o.format == "json") {
    fmt::print("{}", text);
    return 0;
  }
  std::string out;
  try {
    out = status_text(j, dir, m);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, 0, std::string("not a readable status: ") + e.what(),
                     "the file is written by cubecal record --target; wait for the next status");
  }
  fmt::print("{}", out);
  return 0;
}

}  // namespace

CLI::App* add_status_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<StatusCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "status",
      "The live status of a recording made with record --target (from another terminal): each channel's terms "
      "with their interval, the precision now against the target, the time still needed, and whether the "
      "recorder still runs");
  cmd->add_option("dir", opt->dir, "The recording directory (record --out DIR)")->required();
  cmd->add_option("--format", opt->format, "table, or json (the status file as written)")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->callback([opt, &run] { run = [opt] { return run_status_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
