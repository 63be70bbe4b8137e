// A rosbag2 directory: metadata.yaml (rosbag2_bagfile_information, whose
// relative_file_paths list the storage files in order) and the .db3 or
// .mcap files. Only that list is read from the YAML, line by line: the
// storage files say everything else themselves.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "detail/file_buffer.hpp"
#include "cubecal/io/mcap.hpp"
#include "cubecal/io/ros2_bag.hpp"
#include "detail/message_source.hpp"

namespace cubecal::io {

namespace {

namespace fs = std::filesystem;

std::string trimmed(std::string s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(s.back())) s.pop_back();
  std::size_t b = 0;
  while (b < s.size() && space(s[b])) ++b;
  s.erase(0, b);
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front()) s = s.substr(1, s.size() - 2);
  return s;
}

std::size_t indent_of(const std::string& line) {
  std::size_t i = 0;
  while (i < line.size() && line[i] == ' ') ++i;
  return i;
}

// The relative_file_paths of a metadata.yaml, in block ("- a.db3" lines)
// or flow ("[a.db3, b.db3]") style.
std::vector<std::string> listed_files(const std::string& yaml_path) {
  std::ifstream in(yaml_path);
  if (!in) throw InputError(yaml_path, 0, 0, "cannot read the bag's metadata");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  constexpr std::string_view kKey = "relative_file_paths:";
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t indent = indent_of(lines[i]);
    if (std::string_view(lines[i]).substr(indent).rfind(kKey, 0) != 0) continue;
    std::vector<std::string> files;
    const std::string rest = trimmed(lines[i].substr(indent + kKey.size()));
    if (!rest.empty()) {
      if (rest.front() != '[' || rest.back() != ']')
        throw InputError(yaml_path, i + 1, 0, "relative_file_paths is not a list",
                         "list the bag's files, or give a .db3 or .mcap file");
      std::string item;
      for (const char c : rest.substr(1, rest.size() - 2) + ",") {
        if (c != ',') {
          item += c;
          continue;
        }
        if (!trimmed(item).empty()) files.push_back(trimmed(item));
        item.clear();
      }
      return files;
    }
    for (std::size_t j = i + 1; j < lines.size(); ++j) {
      const std::size_t k = indent_of(lines[j]);
      if (k == lines[j].size() || lines[j][k] == '#') continue;
      if (lines[j][k] != '-' || k < indent) break;
      files.push_back(trimmed(lines[j].substr(k + 1)));
    }
    return files;
  }
  return {};
}

MessageLog read_storage_file(const std::string& path) {
  if (is_sqlite_file(path)) return read_db3(path);
  const FileBuffer buf = FileBuffer::open(path, Content::series);
  if (looks_like_mcap(buf.view())) return parse_mcap(buf.view(), path);
  throw InputError(path, 0, 0, "neither an SQLite (.db3) nor an MCAP file",
                   "a bag directory holds .db3 or .mcap files");
}

// The storage files of bag directory `dir`, in order.
std::vector<std::string> storage_files(const std::string& dir) {
  const fs::path root(dir);
  std::vector<std::string> names;
  const fs::path yaml = root / "metadata.yaml";
  std::error_code ec;
  if (fs::is_regular_file(yaml, ec)) {
    names = listed_files(yaml.string());
    if (names.empty())
      throw InputError(yaml.string(), 0, 0, "lists no files (relative_file_paths)",
                       "give the bag's .db3 or .mcap file instead");
    for (const auto& n : names)
      if (!fs::is_regular_file(root / n, ec))
        throw InputError(yaml.string(), 0, 0, "lists " + n + ", which is not a file in " + dir,
                         "copy the whole bag directory");
  } else {
    for (const auto& e : fs::directory_iterator(root, ec)) {
      const std::string ext = e.path().extension().string();
      if ((ext == ".db3" || ext == ".mcap") && e.is_regular_file(ec)) names.push_back(e.path().filename().string());
    }
    if (ec) throw InputError(dir, 0, 0, "cannot list the directory: " + ec.message());
    std::sort(names.begin(), names.end());
    if (names.empty())
      throw InputError(dir, 0, 0, "a directory without metadata.yaml and without .db3 or .mcap files",
                       "give a file, or a ROS 2 bag directory");
  }
  return names;
}

// The directory's files in turn, their topics merged by name.
class DirectorySource final : public detail::MessageSource {
 public:
  explicit DirectorySource(const std::string& dir) : dir_(dir), names_(storage_files(dir)) {
    merged_.file = dir;
    merged_.parts = names_;
    std::error_code ec;
    for (const auto& n : names_) total_bytes += static_cast<std::size_t>(fs::file_size(fs::path(dir) / n, ec));
  }

  bool next(MessageLog& batch) override {
    for (;;) {
      if (!part_) {
        if (next_part_ == names_.size()) return false;
        const std::string path = (fs::path(dir_) / names_[next_part_++]).string();
        part_ = is_sqlite_file(path) ? detail::open_db3_source(path) : detail::open_mcap_source(path);
        done_bytes_ = bytes_read;
      }
      MessageLog got;
      if (!part_->next(got)) {
        part_.reset();
        continue;
      }
      bytes_read = done_bytes_ + part_->bytes_read;
      std::vector<std::uint32_t> to(got.topics.size());
      for (std::size_t i = 0; i < got.topics.size(); ++i)
        to[i] = merged_.topic(got.topics[i].name, got.topics[i].type, got.topics[i].encoding);
      for (LogMessage& m : got.messages) {
        m.topic = to[m.topic];
        m.part = static_cast<std::uint32_t>(next_part_ - 1);
        ++merged_.topics[m.topic].messages;
      }
      batch.file = dir_;
      batch.parts = names_;
      batch.topics = merged_.topics;
      batch.messages = std::move(got.messages);
      batch.payload = std::move(got.payload);
      return true;
    }
  }

 private:
  std::string dir_;
  std::vector<std::string> names_;
  MessageLog merged_;
  std::unique_ptr<detail::MessageSource> part_;
  std::size_t next_part_ = 0, done_bytes_ = 0;
};

}  // namespace

std::unique_ptr<detail::MessageSource> detail::open_bag_directory_source(const std::string& dir) {
  return std::make_unique<DirectorySource>(dir);
}

MessageLog read_ros2_bag_directory(const std::string& dir) {
  const fs::path root(dir);
  const std::vector<std::string> names = storage_files(dir);
  MessageLog log;
  log.file = dir;
  for (const auto& n : names) log.append(read_storage_file((root / n).string()), n);
  return log;
}

}  // namespace cubecal::io
