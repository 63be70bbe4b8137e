// deviation(): a StabilityRecord evaluated over the grid's averaging factors.
#include "cubecal/stats/deviation.hpp"

#include <cmath>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/stats/theo.hpp"

namespace cubecal {

std::vector<StabilityPoint> deviation(Stat stat, std::span<const double> data, double rate_hz, DataType type,
                                      const TauGrid& grid, const StabilityOptions& options) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz))
    throw UsageError("the sampling rate must be a positive number of samples per second");
  const double tau0 = 1.0 / rate_hz;
  const StabilityRecord record(data, type, tau0, stat);
  const std::vector<std::size_t> ms =
      averaging_factors(stat == Stat::theoh ? theoh_factor_grid(grid, record.phase_points(), tau0) : grid,
                        record.max_m(), tau0 * tau_per_factor(stat));
  if (ms.empty())
    throw UsageError(std::string(to_string(stat)) + " of " + std::to_string(data.size()) +
                     " samples: no tau of the grid fits the record (use more data or smaller taus)");
  std::vector<StabilityPoint> points = record.evaluate(ms, options);
  std::erase_if(points, [](const StabilityPoint& p) { return p.n == 0; });
  return points;
}

}  // namespace cubecal
