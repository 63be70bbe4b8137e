// The largest magnitude of a record, in one vectorised pass: the scale the
// deviations normalise by (stats/phase.hpp) and the check that squares of
// the values fit a double (io/series.cpp) both need it over every sample.
#pragma once
#include <span>

namespace cubecal {

struct Magnitude {
  double largest = 0.0;  // max |v| over the finite samples (0 for none)
  bool finite = true;    // no sample is infinite or NaN
};

Magnitude largest_magnitude(std::span<const double> v) noexcept;

}  // namespace cubecal
