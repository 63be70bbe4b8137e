/// @file
/// The front door to the statistics: one call per statistic in the shape
/// AllanTools users know, `oadev(data, rate, data_type, taus)`, returning one
/// point per tau with the deviation, the number of terms, and (unless
/// options.intervals is off) the identified noise type, the EDF and the
/// confidence interval, as Stable32 computes them. See
/// docs/formulas/stability.md for the definitions.
///
///   std::vector<double> y = ...;                      // rate samples at 100 Hz
///   for (const auto& p : cubecal::oadev(y, 100.0))    // octave taus, 68.3 % intervals
///     std::printf("%g %g [%g, %g]\n", p.tau, p.dev, p.lo, p.hi);
///
/// Single-threaded and allocation-light; pipeline::run_dev does several
/// channels, segments split at gaps and taus in parallel.
#pragma once
#include <span>
#include <vector>

#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {

/// `data`: frequency samples (rate-like: deg/s, fractional frequency, ...) or
/// phase samples (their integral: deg, s), one every 1/rate_hz seconds.
/// `grid`: the taus (default octave: 1, 2, 4, ... times 1/rate_hz), up to the
/// largest averaging factor Stable32 evaluates for the statistic (listed taus
/// beyond it are left out: tau_list_outcome in stats/tau_exclusions.hpp says
/// which and why).
/// Throws UsageError when rate_hz is not a positive finite number or no tau of
/// the grid fits the record, std::invalid_argument for a NaN or infinite sample.
std::vector<StabilityPoint> deviation(Stat stat, std::span<const double> data, double rate_hz,
                                      DataType type = DataType::freq, const TauGrid& grid = {},
                                      const StabilityOptions& options = {});

/// The (non-overlapping) Allan deviation; deviation(Stat::adev, ...).
inline std::vector<StabilityPoint> adev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                        const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::adev, data, rate_hz, type, grid, options);
}
/// The overlapping Allan deviation; deviation(Stat::oadev, ...).
inline std::vector<StabilityPoint> oadev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                         const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::oadev, data, rate_hz, type, grid, options);
}
/// The modified Allan deviation; deviation(Stat::mdev, ...).
inline std::vector<StabilityPoint> mdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                        const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::mdev, data, rate_hz, type, grid, options);
}
/// The time deviation (s for fractional-frequency data); deviation(Stat::tdev, ...).
inline std::vector<StabilityPoint> tdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                        const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::tdev, data, rate_hz, type, grid, options);
}
/// The (non-overlapping) Hadamard deviation; deviation(Stat::hdev, ...).
inline std::vector<StabilityPoint> hdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                        const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::hdev, data, rate_hz, type, grid, options);
}
/// The overlapping Hadamard deviation; deviation(Stat::ohdev, ...).
inline std::vector<StabilityPoint> ohdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                         const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::ohdev, data, rate_hz, type, grid, options);
}
/// The total deviation; deviation(Stat::totdev, ...).
inline std::vector<StabilityPoint> totdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                          const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::totdev, data, rate_hz, type, grid, options);
}

/// TIE rms (phase unit; no interval); deviation(Stat::tierms, ...).
inline std::vector<StabilityPoint> tierms(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                          const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::tierms, data, rate_hz, type, grid, options);
}
/// MTIE (phase unit; no interval); deviation(Stat::mtie, ...).
inline std::vector<StabilityPoint> mtie(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                        const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::mtie, data, rate_hz, type, grid, options);
}
/// The modified total deviation; deviation(Stat::mtotdev, ...).
inline std::vector<StabilityPoint> mtotdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                           const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::mtotdev, data, rate_hz, type, grid, options);
}
/// The time total deviation (s for fractional-frequency data); deviation(Stat::ttotdev, ...).
inline std::vector<StabilityPoint> ttotdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                           const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::ttotdev, data, rate_hz, type, grid, options);
}
/// The Hadamard total deviation; deviation(Stat::htotdev, ...).
inline std::vector<StabilityPoint> htotdev(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                           const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::htotdev, data, rate_hz, type, grid, options);
}
/// Theo1 and TheoBR: even averaging factors only, tau = 0.75 m / rate_hz.
inline std::vector<StabilityPoint> theo1(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                         const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::theo1, data, rate_hz, type, grid, options);
}
/// TheoBR, Theo1 corrected by its bias ratio; deviation(Stat::theobr, ...). Throws std::invalid_argument beyond
/// StabilityRecord::kTheobrMaxPoints phase points.
inline std::vector<StabilityPoint> theobr(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                          const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::theobr, data, rate_hz, type, grid, options);
}
/// TheoH: OADEV below 20 % of the record (tau = m / rate_hz), TheoBR beyond
/// (even m, tau = 0.75 m / rate_hz); statistic.hpp, theoh_stat_at.
inline std::vector<StabilityPoint> theoh(std::span<const double> data, double rate_hz, DataType type = DataType::freq,
                                         const TauGrid& grid = {}, const StabilityOptions& options = {}) {
  return deviation(Stat::theoh, data, rate_hz, type, grid, options);
}

}  // namespace cubecal
