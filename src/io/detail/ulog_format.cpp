#include "ulog_format.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace cubecal::io::detail {

namespace {

// A ULog message holds at most 65535 bytes (a uint16 size): no format
// can be larger, which also bounds every product below.
constexpr std::size_t kMaxMessageBytes = 65535;

bool valid_name(std::string_view s) {
  if (s.empty()) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '/';
  });
}

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\0')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::size_t ulog_basic_size(std::string_view type) noexcept {
  if (type == "int8_t" || type == "uint8_t" || type == "bool" || type == "char") return 1;
  if (type == "int16_t" || type == "uint16_t") return 2;
  if (type == "int32_t" || type == "uint32_t" || type == "float") return 4;
  if (type == "int64_t" || type == "uint64_t" || type == "double") return 8;
  return 0;
}

ULogFormat parse_ulog_format(std::string_view text, std::string& error) {
  ULogFormat f;
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos) {
    error = "format definition without ':' after its name";
    return f;
  }
  const std::string_view name = text.substr(0, colon);
  if (!valid_name(name)) {
    error = "format name '" + std::string(name) + "' is not a name";
    return f;
  }
  f.name = std::string(name);
  std::string_view rest = text.substr(colon + 1);
  std::unordered_set<std::string_view> names;  // (views into `text`)
  while (!rest.empty()) {
    const std::size_t semi = rest.find(';');
    const std::string_view item = trimmed(rest.substr(0, semi));
    rest = semi == std::string_view::npos ? std::string_view() : rest.substr(semi + 1);
    if (item.empty()) continue;
    const std::size_t space = item.find(' ');
    if (space == std::string_view::npos) {
      error = "field '" + std::string(item) + "' of format " + f.name + " is not 'type name'";
      return f;
    }
    ULogField field;
    std::string_view type = item.substr(0, space);
    const std::string_view fname = trimmed(item.substr(space + 1));
    if (!valid_name(fname)) {
      error = "field name '" + std::string(fname) + "' of format " + f.name + " is not a name";
      return f;
    }
    if (const std::size_t open = type.find('['); open != std::string_view::npos) {
      const std::string_view n = type.substr(open + 1);
      std::size_t count = 0;
      const auto r = std::from_chars(n.data(), n.data() + n.size(), count);
      if (r.ec != std::errc() || r.ptr != n.data() + n.size() - 1 || *r.ptr != ']' || count == 0 ||
          count > kMaxMessageBytes) {
        error = "field '" + std::string(item) + "' of format " + f.name + " has no valid array length";
        return f;
      }
      field.count = count;
      field.array = true;
      type = type.substr(0, open);
    }
    if (!valid_name(type)) {
      error = "field type '" + std::string(type) + "' of format " + f.name + " is not a name";
      return f;
    }
    field.type = std::string(type);
    field.name = std::string(fname);
    if (!names.insert(fname).second) {
      error = "format " + f.name + " has two fields named " + field.name;
      return f;
    }
    f.fields.push_back(std::move(field));
  }
  return f;
}

std::size_t lay_out_ulog_formats(std::vector<ULogFormat>& formats, std::string& error) {
  // 0: not laid out, 1: being laid out (a nested type naming it is a
  // cycle), 2: done.
  std::vector<int> state(formats.size(), 0);
  std::unordered_map<std::string_view, std::size_t> by_name;
  for (std::size_t i = 0; i < formats.size(); ++i) by_name.emplace(formats[i].name, i);
  const auto index_of = [&](std::string_view name) {
    const auto it = by_name.find(name);
    return it == by_name.end() ? formats.size() : it->second;
  };
  // Depth-first, by an explicit stack (a hostile file may nest deeply);
  // a format resumes at the field where it met a nested type not yet laid out.
  std::vector<std::size_t> next(formats.size(), 0);
  std::vector<std::size_t> offset(formats.size(), 0);
  for (std::size_t root = 0; root < formats.size(); ++root) {
    if (state[root] == 2) continue;
    std::vector<std::size_t> stack{root};
    state[root] = 1;
    while (!stack.empty()) {
      const std::size_t fi = stack.back();
      ULogFormat& f = formats[fi];
      bool pushed = false;
      for (; next[fi] < f.fields.size(); ++next[fi]) {
        ULogField& field = f.fields[next[fi]];
        std::size_t size = ulog_basic_size(field.type);
        if (size == 0) {
          const std::size_t n = index_of(field.type);
          if (n == formats.size()) {
            error = "field " + field.name + " of format " + f.name + " is of type " + field.type +
                    ", which no format defines";
            return fi;
          }
          if (state[n] == 1) {
            error = "format " + f.name + " contains itself (through its field " + field.name + ")";
            return fi;
          }
          if (state[n] == 0) {
            state[n] = 1;
            stack.push_back(n);
            pushed = true;
            break;
          }
          size = formats[n].size;
        }
        field.offset = offset[fi];
        field.element_size = size;
        // size <= 65535 and count <= 65535: no overflow.
        offset[fi] += size * field.count;
        if (offset[fi] > kMaxMessageBytes) {
          error =
              "format " + f.name + " is larger than a message can be (" + std::to_string(kMaxMessageBytes) + " bytes)";
          return fi;
        }
      }
      if (pushed) continue;
      f.size = offset[fi];
      f.logged_size = 0;
      for (const auto& field : f.fields)
        if (!field.name.starts_with("_padding")) f.logged_size = field.offset + field.element_size * field.count;
      state[fi] = 2;
      stack.pop_back();
    }
  }
  return formats.size();
}

}  // namespace cubecal::io::detail
