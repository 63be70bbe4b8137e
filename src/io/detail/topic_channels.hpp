// The channels of the topics read from a bag or a flight log, turned into a
// Series' channels by the rules of a text file's columns: --columns by name,
// 1-based index or name in any case; the extra columns (time, temperature)
// asked for; by default every channel but the temperature. And the checks of
// their values a text column gets: no NaN or infinity, no magnitude whose
// square a variance cannot hold.
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/io/series.hpp"

namespace cubecal::io::detail {

struct TopicColumn {
  std::string name;   // "gx"
  std::string unit;   // "rad/s"
  std::string field;  // the message's field: "angular_velocity.x", "gyro_rad[0]"
  std::vector<double> values;
};

// The first value of `c` that no statistic can take, and what to say of it.
struct ValueFault {
  std::size_t index = 0;  // the message
  std::string what;
  std::string hint;
};
// nan_cause is said after "FIELD is NaN" (e.g. " (or the sample is marked
// invalid)"); nan_hint is the hint for a NaN.
std::optional<ValueFault> value_fault(const TopicColumn& c, std::string_view nan_cause, std::string nan_hint);

// The index of channel `spec` in `columns`; InputError naming `file` and
// listing the channels if none matches.
std::size_t resolve_channel(const std::string& file, const std::vector<TopicColumn>& columns, const std::string& spec);

// Moves the chosen columns of `all` into s (extra_names/extra, names/units/
// channels, left_out, default_columns); `check(i)` runs on each column taken
// before it is. With no columns named and nothing but the temperature left:
// InputError(file, none_what, none_hint).
void take_channels(Series& s, std::vector<TopicColumn>& all, const SeriesOptions& opt,
                   const std::function<void(std::size_t)>& check, const std::string& file, const std::string& none_what,
                   const std::string& none_hint);

// A number as the shortest text that reads back as it.
std::string shortest(double v);

}  // namespace cubecal::io::detail
