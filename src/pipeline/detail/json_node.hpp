// Reading a JSON document that cubecal wrote (analysis.json, a `model
// --format json` result): a node that knows its place in the document, so
// that every error names it ("analysis.json: channels[0].noise: no key
// 'fit' (not an analysis result written by cubecal)"). Not an installed header.
#pragma once
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/error.hpp"

namespace cubecal::pipeline::detail {

using json = nlohmann::json;

class JsonNode {
 public:
  // `what`: what a document that fails is not, e.g. "an analysis result
  // written by cubecal".
  JsonNode(const json& j, std::string path, const std::string& label,
           const char* what = "an analysis result written by cubecal")
      : j_(j), path_(std::move(path)), label_(label), what_(what) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw UsageError(label_ + ": " + (path_.empty() ? std::string() : path_ + ": ") + what + " (not " + what_ + ")");
  }
  bool has(const char* key) const { return j_.is_object() && j_.contains(key) && !j_[key].is_null(); }
  JsonNode at(const char* key) const {
    if (!j_.is_object()) fail("not an object");
    const auto it = j_.find(key);
    if (it == j_.end()) fail(std::string("no key '") + key + "'");
    return JsonNode(*it, path_.empty() ? std::string(key) : path_ + "." + key, label_, what_);
  }
  JsonNode at(std::size_t i) const {
    if (!j_.is_array() || i >= j_.size()) fail("no element " + std::to_string(i));
    return JsonNode(j_[i], path_ + "[" + std::to_string(i) + "]", label_, what_);
  }
  std::size_t size() const {
    if (!j_.is_array()) fail("not an array");
    return j_.size();
  }
  // A number; null (how JSON writes a NaN) reads as NaN.
  double num() const {
    if (j_.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!j_.is_number()) fail("not a number");
    return j_.get<double>();
  }
  std::size_t count() const {
    if (!j_.is_number_unsigned() && !(j_.is_number_integer() && j_.get<long long>() >= 0)) fail("not a count");
    return j_.get<std::size_t>();
  }
  // An integer in [lo, hi]: a number out of range, or with a fraction, is
  // refused (casting it would be undefined).
  int integer(int lo, int hi) const {
    const double v = num();
    if (!(v >= lo && v <= hi) || v != std::floor(v))
      fail("not a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
    return static_cast<int>(v);
  }
  bool boolean() const {
    if (!j_.is_boolean()) fail("not true or false");
    return j_.get<bool>();
  }
  std::string str() const {
    if (!j_.is_string()) fail("not a string");
    return j_.get<std::string>();
  }
  std::vector<double> nums() const {
    std::vector<double> v(size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = at(i).num();
    return v;
  }
  double num(const char* key) const { return at(key).num(); }
  double num_or(const char* key, double fallback) const { return has(key) ? at(key).num() : fallback; }
  std::string str_or(const char* key, const std::string& fallback) const { return has(key) ? at(key).str() : fallback; }
  const json& raw() const { return j_; }

 private:
  const json& j_;
  std::string path_;
  const std::string& label_;
  const char* what_;
};

}  // namespace cubecal::pipeline::detail
