// json_text.hpp: JSON text whose strings are made UTF-8 before the dump.
#include "cubecal/pipeline/json_text.hpp"

#include <utility>

#include "cubecal/printable_text.hpp"

namespace cubecal::pipeline {

namespace {

// `j` with every string and key passed through utf8_text.
nlohmann::json utf8_copy(const nlohmann::json& j) {
  if (j.is_string()) return utf8_text(j.get_ref<const std::string&>());
  if (j.is_array()) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : j) a.push_back(utf8_copy(e));
    return a;
  }
  if (j.is_object()) {
    nlohmann::json o = nlohmann::json::object();
    for (const auto& [key, value] : j.items()) o[utf8_text(key)] = utf8_copy(value);
    return o;
  }
  return j;
}

}  // namespace

std::string json_text(const nlohmann::json& j, int indent) {
  try {
    return j.dump(indent);
  } catch (const nlohmann::json::type_error&) {
    // 316, a string that is not UTF-8: the rare case pays for the copy.
    return utf8_copy(j).dump(indent);
  }
}

}  // namespace cubecal::pipeline
