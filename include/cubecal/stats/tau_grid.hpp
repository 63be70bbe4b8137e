// Averaging-factor grids: octave, decade, all, log:K, explicit taus.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal {

struct TauGrid {
  enum class Kind { octave, decade, all, log, list } kind = Kind::octave;
  unsigned per_decade = 10;     // for log:K
  std::vector<double> taus;     // for an explicit list, seconds
};

// "octave", "decade", "all", "log:K" or a comma-separated list of taus in
// seconds ("1,10,100"). Throws std::invalid_argument with a readable message.
TauGrid parse_tau_grid(std::string_view spec);

// Averaging factors m (1 <= m <= max_m), ascending, without duplicates.
// octave: 1,2,4,..; decade: 1,2,4,10,20,40,..; all: every m;
// log:K: round(10^(j/K)); list: round(tau/tau0), each must land within 1e-6
// relative of an integer multiple of tau0... rounded to the nearest m >= 1.
std::vector<std::size_t> averaging_factors(const TauGrid& grid, std::size_t max_m, double tau0);

}  // namespace cubecal
