// docs/formulas/spectral.md §1.
#include "cubecal/spectral/density_unit.hpp"

#include <numbers>

namespace cubecal {

namespace {

std::string squared(const Unit& u) { return u.name.empty() ? "u^2" : "(" + u.name + ")^2"; }

}  // namespace

DensityUnit density_unit(const Unit& unit) { return {squared(unit) + "/Hz", 1.0}; }

std::optional<DensityUnit> rate_density_unit(const Unit& unit) {
  if (unit.kind != SensorKind::rate) return std::nullopt;
  const double to_deg_h = unit.to_si / (std::numbers::pi / 180.0) * 3600.0;
  return DensityUnit{"(deg/h)^2/Hz", to_deg_h * to_deg_h};
}

std::string power_law_unit(const Unit& unit, int alpha) {
  // u^2 Hz^-(1 + alpha)
  const int hz = -(1 + alpha);
  const std::string u2 = squared(unit);
  if (hz == 0) return u2;
  if (hz == 1) return u2 + "*Hz";
  if (hz == -1) return u2 + "/Hz";
  if (hz > 0) return u2 + "*Hz^" + std::to_string(hz);
  return u2 + "/Hz^" + std::to_string(-hz);
}

}  // namespace cubecal
