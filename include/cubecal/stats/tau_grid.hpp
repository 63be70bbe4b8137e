/// @file
/// Averaging-factor grids: octave, decade, all, log:K, explicit taus.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal {

/// Which taus a deviation is evaluated at.
struct TauGrid {
  /// Octave, decade, all factors, log with per_decade taus per decade, or the listed taus.
  enum class Kind { octave, decade, all, log, list } kind = Kind::octave;  ///< the grid's kind
  unsigned per_decade = 10;                                                ///< for log:K
  std::vector<double> taus;                                                ///< for an explicit list, seconds
};

/// "octave", "decade", "all", "log:K" or a comma-separated list of taus in
/// seconds ("1,10,100"). Throws std::invalid_argument with a readable message.
TauGrid parse_tau_grid(std::string_view spec);

/// Averaging factors m (1 <= m <= max_m), ascending, without duplicates.
/// octave: 1,2,4,..; decade: 1,2,4,10,20,40,..; all: every m;
/// log:K: round(10^(j/K)); list: listed_factor(tau, tau0) of each tau. Listed
/// taus beyond max_m, and listed taus that share a factor, are left out and
/// merged here; tau_list_outcome (stats/tau_exclusions.hpp) says which.
std::vector<std::size_t> averaging_factors(const TauGrid& grid, std::size_t max_m, double tau0);

/// The averaging factor of a listed tau: the nearest whole multiple of tau0,
/// at least 1 (a double: a listed tau may be any size).
double listed_factor(double tau, double tau0) noexcept;

}  // namespace cubecal
