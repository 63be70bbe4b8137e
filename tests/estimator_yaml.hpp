// Test support: a key scan of the estimator files (flat "key: value" lines,
// any indentation, "# ..." comments dropped), enough to read them back.
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <sstream>
#include <string>

namespace cubecal::test {

// key -> value text of every uncommented "key: value" line (last one wins).
inline std::map<std::string, std::string> yaml_keys(const std::string& text) {
  std::map<std::string, std::string> keys;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    const auto start = line.find_first_not_of(' ');
    if (start == std::string::npos || line[start] == '-' || line[start] == '%') continue;
    const auto colon = line.find(':', start);
    if (colon == std::string::npos) continue;
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(' '));
    value.erase(value.find_last_not_of(' ') + 1);
    keys[line.substr(start, colon - start)] = value;
  }
  return keys;
}

// The value of `key` as a number (NaN, and a test failure, when absent).
inline double number(const std::map<std::string, std::string>& keys, const std::string& key) {
  const auto it = keys.find(key);
  if (it == keys.end()) {
    ADD_FAILURE() << "no key " << key;
    return NAN;
  }
  return std::stod(it->second);
}

// "[a, b, c]" of `key`.
inline std::array<double, 3> triple(const std::map<std::string, std::string>& keys, const std::string& key) {
  std::array<double, 3> v{NAN, NAN, NAN};
  const auto it = keys.find(key);
  if (it == keys.end() || it->second.size() < 2 || it->second.front() != '[') {
    ADD_FAILURE() << "no list " << key;
    return v;
  }
  std::istringstream in(it->second.substr(1));
  char sep = 0;
  for (auto& x : v) in >> x >> sep;
  return v;
}

}  // namespace cubecal::test
