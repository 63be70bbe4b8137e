// A measured Allan-deviation curve as the noise-term estimators take it:
// parallel arrays, tau ascending, with the confidence interval and the
// equivalent degrees of freedom of each point.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/core/stability.hpp"

namespace cubecal {

struct AllanCurve {
  std::vector<double> tau;  // s, ascending
  std::vector<double> dev;  // sigma(tau), data unit
  std::vector<double> lo;   // lower confidence bound of dev
  std::vector<double> hi;   // upper confidence bound of dev
  std::vector<double> edf;  // equivalent degrees of freedom (> 0)
  std::size_t size() const noexcept { return tau.size(); }
};

AllanCurve to_allan_curve(const std::vector<StabilityPoint>& points);

}  // namespace cubecal
