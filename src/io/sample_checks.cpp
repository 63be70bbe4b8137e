// The readers' rate and magnitude rules on records held in memory.
#include "cubecal/io/sample_checks.hpp"

#include <cmath>

#include "../detail/magnitude.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "detail/shortest_text.hpp"

namespace cubecal::io {

void check_rate(double rate_hz) {
  const auto& stamp = detail::shortest_text;
  if (!std::isfinite(rate_hz) || !(rate_hz > 0.0))
    throw UsageError(Field::rate, "the sampling rate must be a positive finite number of Hz, got " + stamp(rate_hz));
  if (!(rate_hz >= kMinRateHz && rate_hz <= kMaxRateHz))
    throw UsageError(Field::rate, "the sampling rate " + stamp(rate_hz) + " Hz is outside the range " +
                                      stamp(kMinRateHz) + " to " + stamp(kMaxRateHz) + " Hz");
}

void check_samples(std::span<const double> v, const std::string& label, std::size_t column, const std::string& name,
                   bool missing) {
  const auto& stamp = detail::shortest_text;
  const Magnitude m = largest_magnitude(v);
  const auto fail = [&](std::size_t i, const std::string& what, const std::string& hint) {
    throw InputError(label, i + 1, column,
                     "value " + stamp(v[i]) + " of " + name + " at sample " + std::to_string(i) + what, hint);
  };
  if (!m.finite || m.largest > kMaxMagnitude) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (std::isnan(v[i]) && !missing) fail(i, " is not a number", "remove the sample or split the record there");
      if (std::isinf(v[i])) fail(i, " is not finite", "remove the sample or split the record there");
      if (std::fabs(v[i]) > kMaxMagnitude)
        fail(i, " exceeds the magnitude " + stamp(kMaxMagnitude) + " whose square a variance can hold",
             "rescale the data, e.g. to other units");
    }
  }
  if (m.largest != 0.0 && m.largest < kMinMagnitude) {
    std::size_t i = 0;
    while (i + 1 < v.size() && std::fabs(v[i]) != m.largest) ++i;
    fail(i,
         " is the largest of its channel, below the magnitude " + stamp(kMinMagnitude) +
             " whose square a variance can hold",
         "rescale the data, e.g. to other units");
  }
}

}  // namespace cubecal::io
