/// @file
/// Sensor units and the display units of noise terms, as the paper and the
/// inertial-sensor literature quote them.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"

namespace cubecal {

/// What a unit measures: a rate (gyroscope), a field (magnetometer), an acceleration, or anything else.
enum class SensorKind { rate, field, acceleration, generic };

/// A data unit: its name, what it measures and its factor to SI.
struct Unit {
  std::string name;  ///< as given: "deg/s", "mGauss", ...
  /// What the unit measures.
  SensorKind kind = SensorKind::generic;
  double to_si = 1.0;   ///< multiply a value in this unit to get SI (rad/s, T, m/s^2)
  std::string si_name;  ///< "rad/s", "T", "m/s^2", or the unit itself
};

/// deg/s (also dps), rad/s, deg/h (also dph), mGauss (also mG), uT, nT, g,
/// m/s^2, counts. Case-sensitive; the aliases report the canonical name.
/// nullopt for anything else.
std::optional<Unit> parse_unit(std::string_view s);
std::string known_units();  ///< "deg/s|rad/s|deg/h|mGauss|uT|nT|g|m/s^2|counts"

/// A number with its 1-sigma uncertainty and unit, for display.
struct Quantity {
  /// The value, in `unit`.
  double value = 0.0;
  /// 1-sigma uncertainty, in `unit`.
  double sigma = 0.0;
  /// The unit's name ("deg/sqrt(h)").
  std::string unit;
};

/// A noise term (value and sigma in the data unit and seconds, as
/// noise_terms.hpp defines them) in the unit people quote for this sensor:
/// rate sensors: Q deg, N deg/sqrt(h), B deg/h, K deg/h/sqrt(h), R deg/h^2
/// (rad/s and deg/h data are converted to deg/s first); other sensors, as the paper does for
/// its magnetometer: Q u*s, N u*sqrt(h), B u, K u/sqrt(h), R u/h.
enum class Term { Q, N, B, K, R };
/// The term `t` of kind `term` in the unit quoted for sensors of `unit`'s kind. Throws nothing beyond std::bad_alloc.
Quantity display(const TermEstimate& t, Term term, const Unit& unit);
std::string_view to_string(Term t) noexcept;  ///< "Q", "N", "B", "K", "R"

/// Spectral densities in the data unit: white noise u/sqrt(Hz) (= N in u*sqrt(s))
/// and random walk u/s/sqrt(Hz) (= K in u/sqrt(s)); in SI when `si`.
Quantity white_density(const TermEstimate& N, const Unit& unit, bool si);
/// The random-walk density of K (u/s/sqrt(Hz); SI when `si`). Throws nothing beyond std::bad_alloc.
Quantity random_walk_density(const TermEstimate& K, const Unit& unit, bool si);

/// The accelerometer terms in the units inertial navigation quotes them, for
/// acceleration data (g, m/s^2; 1 g = 9.80665 m/s^2); empty for other sensors:
///   N  velocity random walk      m/s/sqrt(h), ug/sqrt(Hz)
///   B  bias instability          ug, mg
///   K  acceleration random walk  m/s^2/sqrt(h), ug/sqrt(s)
/// and nothing for Q and R.
std::vector<Quantity> accelerometer_display(const TermEstimate& t, Term term, const Unit& unit);

/// "rate", "field", "acceleration", "generic". Throws nothing.
std::string_view to_string(SensorKind k) noexcept;

}  // namespace cubecal
