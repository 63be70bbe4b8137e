#include "cubecal/stats/confidence.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>

namespace cubecal {

Interval chi2_interval(double dev, double edf, double ci) {
  if (!(edf > 0.0) || !(ci > 0.0 && ci < 1.0) || !std::isfinite(dev)) return {};
  const boost::math::chi_squared dist(edf);
  const double tail = (1.0 - ci) / 2.0;
  const double chi_lo = boost::math::quantile(dist, tail);
  const double chi_hi = boost::math::quantile(dist, 1.0 - tail);
  return {dev * std::sqrt(edf / chi_hi), dev * std::sqrt(edf / chi_lo)};
}

}  // namespace cubecal
