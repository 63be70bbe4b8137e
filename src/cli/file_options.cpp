#include "file_options.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string_view>

#include "cubecal/error.hpp"

namespace cubecal::cli {

namespace {

constexpr std::array<std::string_view, 8> kKeys{"rate",     "skip-rows", "skip", "columns",
                                                "time-col", "lsb",       "unit", "gaps"};

bool known_key(std::string_view k) { return std::find(kKeys.begin(), kKeys.end(), k) != kKeys.end(); }

// "key=..." with a key made of letters, digits and '-', '_'.
std::string key_of(const std::string& item) {
  const auto eq = item.find('=');
  if (eq == std::string::npos || eq == 0) return {};
  const std::string k = item.substr(0, eq);
  const bool word = std::all_of(k.begin(), k.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  });
  return word ? k : std::string();
}

struct Pair {
  std::string key, value;
};

// "rate=100,columns=gx,gy,lsb=131" -> rate:100, columns:gx,gy, lsb:131.
std::vector<Pair> pairs_of(const std::string& text) {
  std::vector<Pair> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::string key = key_of(item);
    if (!key.empty())
      out.push_back({key, item.substr(key.size() + 1)});
    else if (!out.empty())
      out.back().value += "," + item;
    else
      out.push_back({{}, item});  // not key=value: the caller takes the text as part of the path
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string bad(const std::string& arg, const std::string& what) {
  return arg + ": " + what + " (per-file options: FILE:key=value,...; keys " + file_option_keys() + ")";
}

double number(const std::string& arg, const std::string& key, const std::string& v) {
  double x = 0.0;
  const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
  if (ec != std::errc() || p != v.data() + v.size() || !std::isfinite(x) || x < 0.0)
    throw UsageError(bad(arg, key + "=" + v + " is not a non-negative number"));
  return x;
}

}  // namespace

std::string file_option_keys() {
  std::string s;
  for (const auto k : kKeys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

FileSpec parse_file_spec(const std::string& arg, const InputOptions& defaults, const std::string& unit) {
  FileSpec f{arg, defaults, unit, false};
  f.input.file = arg;
  const auto colon = arg.rfind(':');
  std::error_code ec;
  if (colon == std::string::npos || std::filesystem::exists(arg, ec)) return f;
  const std::vector<Pair> pairs = pairs_of(arg.substr(colon + 1));
  if (pairs.empty() || pairs.front().key.empty()) return f;  // a ':' in a path

  f.path = f.input.file = arg.substr(0, colon);
  std::vector<std::string> seen;
  for (const auto& [key, value] : pairs) {
    if (!known_key(key)) throw UsageError(bad(arg, "unknown key '" + key + "'"));
    const std::string canonical = key == "skip" ? "skip-rows" : key;
    if (std::find(seen.begin(), seen.end(), canonical) != seen.end())
      throw UsageError(bad(arg, "'" + canonical + "' given twice"));
    seen.push_back(canonical);
    if (value.empty()) throw UsageError(bad(arg, "'" + key + "=' has no value"));
    if (canonical == "rate") {
      f.input.rate_hz = number(arg, key, value);
      if (!(f.input.rate_hz > 0.0)) throw UsageError(bad(arg, "rate=" + value + " is not a positive number of Hz"));
    } else if (canonical == "skip-rows") {
      const double n = number(arg, key, value);
      if (n != std::floor(n) || n > 1e9)
        throw UsageError(bad(arg, key + "=" + value + " is not a whole number of lines"));
      f.input.skip_rows = static_cast<std::size_t>(n);
    } else if (canonical == "columns") {
      f.input.columns = value;
    } else if (canonical == "time-col") {
      f.input.time_col = value;
    } else if (canonical == "lsb") {
      parse_lsb_list(value);  // a typo fails here, before any file is read
      f.input.lsb = value;
    } else if (canonical == "unit") {
      parse_units(value);
      f.unit = value;
      f.own_unit = true;
    } else if (canonical == "gaps") {
      if (value != "error" && value != "split") throw UsageError(bad(arg, "gaps=" + value + " is not error or split"));
      f.input.gaps = value;
    }
  }
  return f;
}

}  // namespace cubecal::cli
