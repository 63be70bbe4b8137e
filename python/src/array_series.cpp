#include "array_series.hpp"

#include <cmath>
#include <span>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "errors.hpp"

namespace cubecal::python {

io::Series array_series(const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
                        const std::optional<Doubles>& temperature, const std::string& temp_name,
                        const std::string& label) {
  io::check_rate(rate);
  if (channels.empty()) throw ArgumentError("data", "no channel to analyze");
  if (names.size() != channels.size()) throw std::invalid_argument("names: one name per channel");
  io::Series s;
  s.file = label;
  s.rate_hz = rate;
  s.tau0 = 1.0 / rate;
  s.names = names;
  const auto take = [&](const Doubles& a, const std::string& keyword, const std::string& name, std::size_t column) {
    const std::span<const double> v = view(a, keyword);
    io::check_samples(v, label, column, name);
    return std::vector<double>(v.begin(), v.end());
  };
  for (std::size_t c = 0; c < channels.size(); ++c) {
    s.channels.push_back(take(channels[c], "data", names[c], c + 1));
    if (s.channels.back().size() != s.channels.front().size())
      throw ArgumentError("data", "every channel must have the same length (" + names[c] + " has " +
                                      std::to_string(s.channels.back().size()) + " samples, " + names[0] + " " +
                                      std::to_string(s.channels.front().size()) + ")");
  }
  if (temperature) {
    s.extra_names.push_back(temp_name);
    s.extra.push_back(take(*temperature, "temperature", temp_name, channels.size() + 1));
    if (s.extra[0].size() != s.channels[0].size())
      throw ArgumentError("temperature", "the temperature must have one value per sample (" +
                                             std::to_string(s.extra[0].size()) + " for " +
                                             std::to_string(s.channels[0].size()) + " samples)");
  }
  const std::size_t n = s.channels[0].size();
  if (n < 3) throw ArgumentError("data", "a record needs at least 3 samples");
  s.segments = {{0, n}};
  return s;
}

io::Series call_record(const std::optional<std::string>& path, const ReadArgs& read,
                       const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
                       bool missing_samples) {
  if (path) {
    io::SeriesOptions so = series_options(read, missing_samples);
    so.keep_time = false;
    return io::read_series(*path, so);
  }
  return array_series(channels, names, rate, std::nullopt, "", "<arrays>");
}

}  // namespace cubecal::python
