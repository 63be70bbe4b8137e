#include "topic_channels.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>

#include "cubecal/error.hpp"
#include "series_timing.hpp"

namespace cubecal::io::detail {

std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::optional<ValueFault> value_fault(const TopicColumn& c, std::string_view nan_cause, std::string nan_hint) {
  double top = 0.0;
  for (std::size_t i = 0; i < c.values.size(); ++i) {
    const double v = c.values[i];
    if (std::isnan(v)) {
      const auto nans = std::count_if(c.values.begin(), c.values.end(), [](double x) { return std::isnan(x); });
      return ValueFault{i,
                        c.field + " is NaN" + std::string(nan_cause) + ", in " + std::to_string(nans) + " of " +
                            std::to_string(c.values.size()) + " messages",
                        std::move(nan_hint)};
    }
    if (!std::isfinite(v) || std::fabs(v) > kMaxMagnitude)
      return ValueFault{i, c.field + " is " + shortest(v) + ", which no variance can hold",
                        "cut the record before this message"};
    top = std::max(top, std::fabs(v));
  }
  if (top != 0.0 && top < kMinMagnitude) {
    std::size_t i = 0;
    while (std::fabs(c.values[i]) != top) ++i;
    return ValueFault{i,
                      c.field + " " + shortest(c.values[i]) + " is the largest of " + c.name +
                          ", below the magnitude " + shortest(kMinMagnitude) + " whose square a variance can hold",
                      "the topic holds no usable " + c.field};
  }
  return std::nullopt;
}

std::size_t resolve_channel(const std::string& file, const std::vector<TopicColumn>& columns, const std::string& spec) {
  const auto lower = [](std::string s) {
    for (char& ch : s)
      if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
    return s;
  };
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i].name == spec) return i;
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (spec == std::to_string(i + 1)) return i;
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (lower(columns[i].name) == lower(spec)) return i;
  std::string names;
  for (const auto& c : columns) names += (names.empty() ? "" : ", ") + c.name;
  throw InputError(file, 0, 0, "no channel '" + spec + "' in the topics read; channels are: " + names,
                   "choose among them, or read other topics with {topics} NAME");
}

void take_channels(Series& s, std::vector<TopicColumn>& all, const SeriesOptions& opt,
                   const std::function<void(std::size_t)>& check, const std::string& file, const std::string& none_what,
                   const std::string& none_hint) {
  std::vector<bool> taken(all.size(), false);
  for (const auto& e : opt.table.extra_columns) {
    const std::size_t i = resolve_channel(file, all, e);
    check(i);
    s.extra_names.push_back(all[i].name);
    s.extra.push_back(all[i].values);
    taken[i] = true;
  }
  std::vector<std::size_t> wanted;
  if (opt.table.columns.empty()) {
    s.default_columns = true;
    for (std::size_t i = 0; i < all.size(); ++i) {
      const bool out = taken[i] || (opt.skip_temperature && all[i].name == "temp");
      if (out)
        s.left_out.push_back(all[i].name);
      else
        wanted.push_back(i);
    }
    if (wanted.empty()) throw InputError(file, 0, 0, none_what, none_hint);
  } else {
    for (const auto& spec : opt.table.columns) wanted.push_back(resolve_channel(file, all, spec));
  }
  for (const std::size_t i : wanted) {
    check(i);
    s.names.push_back(all[i].name);
    s.units.push_back(all[i].unit);
    s.channels.push_back(all[i].values);
  }
}

}  // namespace cubecal::io::detail
