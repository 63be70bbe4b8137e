/// @file
/// The text of a JSON document that cubecal writes, which never fails on text
/// that is not UTF-8.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace cubecal::pipeline {

/// `j` serialized as nlohmann::json::dump(indent) does, with the bytes of its
/// strings and keys that are not well-formed UTF-8 written as `\xNN`
/// (utf8_text, the rule of printable_text): a column name or a path from
/// the file system cannot make the writer throw.
std::string json_text(const nlohmann::json& j, int indent = -1);

}  // namespace cubecal::pipeline
