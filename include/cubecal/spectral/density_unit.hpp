/// @file
/// The units of a power spectral density of a channel in unit u: u^2/Hz, and
/// for rate sensors also (deg/h)^2/Hz, the unit gyro data sheets quote
/// (through the Unit of noise/units.hpp). docs/formulas/spectral.md §1.
#pragma once
#include <optional>
#include <string>

#include "cubecal/noise/units.hpp"

namespace cubecal {

/// The unit of a power spectral density and its factor from the channel's unit^2/Hz.
struct DensityUnit {
  std::string name;     ///< "(deg/s)^2/Hz"
  double factor = 1.0;  ///< multiply a density in the channel's unit^2/Hz by this
};

/// The channel's own: (name)^2/Hz, factor 1; "u^2/Hz" for a unit without a
/// name (none given).
DensityUnit density_unit(const Unit& unit);
/// Rate sensors: (deg/h)^2/Hz; nullopt for other kinds.
std::optional<DensityUnit> rate_density_unit(const Unit& unit);
/// The unit of h_alpha (unit^2/Hz^(1+alpha)): "(deg/s)^2*Hz" for alpha -2.
std::string power_law_unit(const Unit& unit, int alpha);

}  // namespace cubecal
