// The units of a record's channels as the CLI finds them when none is
// given: those its format states (ROS messages), else those its channel
// names announce (gx_dps, mag_x_uT, ...).
#pragma once
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/units.hpp"

namespace cubecal::python {

// UsageError("unit") naming the channels that announce none.
std::vector<Unit> announced_units(const io::Series& s);

}  // namespace cubecal::python
