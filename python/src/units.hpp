// The units of a record's channels as the CLI finds them when none is
// given: those its format states (ROS messages), else those its channel
// names announce (gx_dps, mag_x_uT, ...).
#pragma once
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/units.hpp"

namespace cubecal::python {

// UsageError(Field::unit) naming the channels that announce none.
std::vector<Unit> announced_units(const io::Series& s);

// The units a call names (unit=), parsed; UsageError(Field::unit) for one it
// does not know.
std::vector<Unit> named_units(const std::vector<std::string>& names);

// The units the record announces, else none (an unnamed unit: the results
// in u), as the CLI's psd and model take them.
std::vector<Unit> announced_units_or_none(const io::Series& s);

}  // namespace cubecal::python
