#include "cubecal/noise/units.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace cubecal {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kStandardGravity = 9.80665;  // m/s^2 per g (CGPM 1901)

struct UnitRow {
  std::string_view name;
  SensorKind kind;
  double to_si;
  std::string_view si;
};

constexpr std::array<UnitRow, 13> kUnits{{
    {"deg/s", SensorKind::rate, kDeg, "rad/s"},
    {"dps", SensorKind::rate, kDeg, "rad/s"},
    {"rad/s", SensorKind::rate, 1.0, "rad/s"},
    {"deg/h", SensorKind::rate, kDeg / 3600.0, "rad/s"},
    {"dph", SensorKind::rate, kDeg / 3600.0, "rad/s"},
    {"mGauss", SensorKind::field, 1e-7, "T"},
    {"mG", SensorKind::field, 1e-7, "T"},
    {"uT", SensorKind::field, 1e-6, "T"},
    {"nT", SensorKind::field, 1e-9, "T"},
    {"T", SensorKind::field, 1.0, "T"},
    {"g", SensorKind::acceleration, kStandardGravity, "m/s^2"},
    {"m/s^2", SensorKind::acceleration, 1.0, "m/s^2"},
    {"counts", SensorKind::generic, 1.0, "counts"},
}};

}  // namespace

std::optional<Unit> parse_unit(std::string_view s) {
  for (const auto& r : kUnits)
    if (r.name == s) {
      // Aliases report the canonical spelling.
      std::string name(r.name == "dps" ? "deg/s" : r.name == "dph" ? "deg/h" : r.name == "mG" ? "mGauss" : r.name);
      return Unit{name, r.kind, r.to_si, std::string(r.si)};
    }
  return std::nullopt;
}

std::string known_units() { return "deg/s|rad/s|deg/h|mGauss|uT|nT|T|g|m/s^2|counts"; }

std::string_view to_string(SensorKind k) noexcept {
  switch (k) {
    case SensorKind::rate: return "rate";
    case SensorKind::field: return "field";
    case SensorKind::acceleration: return "acceleration";
    case SensorKind::generic: return "generic";
  }
  return "generic";
}

std::string_view to_string(Term t) noexcept {
  switch (t) {
    case Term::Q: return "Q";
    case Term::N: return "N";
    case Term::B: return "B";
    case Term::K: return "K";
    case Term::R: return "R";
  }
  return "?";
}

Quantity display(const TermEstimate& t, Term term, const Unit& unit) {
  Quantity q;
  if (unit.kind == SensorKind::rate) {
    // Work in deg/s whatever the input rate unit (rad/s, deg/h).
    const double to_deg = unit.to_si / kDeg;
    double f = 1.0;
    switch (term) {
      case Term::Q:
        f = 1.0;
        q.unit = "deg";
        break;  // deg/s * s
      case Term::N:
        f = 60.0;
        q.unit = "deg/sqrt(h)";
        break;  // deg/s*sqrt(s) -> deg/sqrt(h)
      case Term::B:
        f = 3600.0;
        q.unit = "deg/h";
        break;
      case Term::K:
        f = 3600.0 * 60.0;
        q.unit = "deg/h/sqrt(h)";
        break;  // deg/s/sqrt(s)
      case Term::R:
        f = 3600.0 * 3600.0;
        q.unit = "deg/h^2";
        break;  // deg/s^2
    }
    q.value = t.value * f * to_deg;
    q.sigma = t.sigma * f * to_deg;
    return q;
  }
  const std::string& u = unit.name;
  double f = 1.0;
  switch (term) {
    case Term::Q:
      f = 1.0;
      q.unit = u + "*s";
      break;
    case Term::N:
      f = 1.0 / 60.0;
      q.unit = u + "*sqrt(h)";
      break;  // u*sqrt(s) -> u*sqrt(h)
    case Term::B:
      f = 1.0;
      q.unit = u;
      break;
    case Term::K:
      f = 60.0;
      q.unit = u + "/sqrt(h)";
      break;  // u/sqrt(s) -> u/sqrt(h)
    case Term::R:
      f = 3600.0;
      q.unit = u + "/h";
      break;  // u/s -> u/h
  }
  q.value = t.value * f;
  q.sigma = t.sigma * f;
  return q;
}

Quantity white_density(const TermEstimate& N, const Unit& unit, bool si) {
  const double f = si ? unit.to_si : 1.0;
  return {N.value * f, N.sigma * f, (si ? unit.si_name : unit.name) + "/sqrt(Hz)"};
}

Quantity random_walk_density(const TermEstimate& K, const Unit& unit, bool si) {
  const double f = si ? unit.to_si : 1.0;
  return {K.value * f, K.sigma * f, (si ? unit.si_name : unit.name) + "/s/sqrt(Hz)"};
}

std::vector<Quantity> accelerometer_display(const TermEstimate& t, Term term, const Unit& unit) {
  if (unit.kind != SensorKind::acceleration) return {};
  const double si = unit.to_si;                        // m/s^2 per data unit
  const double micro_g = si / kStandardGravity * 1e6;  // ug per data unit
  const auto q = [&](double f, const char* name) { return Quantity{t.value * f, t.sigma * f, name}; };
  switch (term) {
    // u*sqrt(s) = u/sqrt(Hz); (m/s^2)*sqrt(s) = m/s/sqrt(s) = 60 m/s/sqrt(h)
    case Term::N: return {q(si * 60.0, "m/s/sqrt(h)"), q(micro_g, "ug/sqrt(Hz)")};
    case Term::B: return {q(micro_g, "ug"), q(micro_g * 1e-3, "mg")};
    // u/sqrt(s) = 60 u/sqrt(h)
    case Term::K: return {q(si * 60.0, "m/s^2/sqrt(h)"), q(micro_g, "ug/sqrt(s)")};
    case Term::Q:
    case Term::R: break;
  }
  return {};
}

}  // namespace cubecal
