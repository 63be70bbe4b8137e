#include "temperature_regressor.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "cubecal/error.hpp"

namespace cubecal::noise::detail {

void throw_too_few_distinct(std::size_t order) {
  throw CalibrationError(
      CalibrationReason::degenerate,
      "temperature takes too few distinct values for a fit of order " + std::to_string(order) + " (lower the order)");
}

TemperatureRegressor temperature_regressor(std::span<const double> y, std::span<const double> temp, std::size_t order) {
  if (order < 1 || order > 5) throw CalibrationError(CalibrationReason::bad_option, "temperature order must be 1 to 5");
  if (y.size() != temp.size())
    throw CalibrationError(CalibrationReason::bad_data, "temperature and data lengths differ");
  const std::size_t n = y.size();
  const std::size_t p = order + 1;
  if (n <= p)
    throw CalibrationError(CalibrationReason::too_few_points,
                           "too few samples for a temperature fit of order " + std::to_string(order));
  double tmin = temp[0], tmax = temp[0], tsum = 0.0;
  for (double t : temp) {
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
    tsum += t;
  }
  TemperatureRegressor r;
  r.t_ref = tsum / static_cast<double>(n);
  r.half_span = 0.5 * (tmax - tmin);
  if (!(r.half_span > 0.0))
    throw CalibrationError(CalibrationReason::degenerate,
                           "temperature is constant over the record: no coefficient can be estimated");
  // Fewer distinct temperatures than coefficients: the normal matrix is
  // exactly singular, which LDLT would quietly solve as a pseudo-inverse.
  std::vector<double> distinct;
  for (double t : temp) {
    if (std::find(distinct.begin(), distinct.end(), t) == distinct.end()) distinct.push_back(t);
    if (distinct.size() >= p) break;
  }
  if (distinct.size() < p) throw_too_few_distinct(order);
  return r;
}

}  // namespace cubecal::noise::detail
