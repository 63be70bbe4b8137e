// The JSON form of a stability curve, shared by the result documents:
// parallel arrays tau, dev, n and the averaging factor (under `factor_key`:
// "af" in analysis.json and `dev --format json`, "m" in the turnon/compare
// runs), and lo, hi, edf, alpha when the intervals were computed. Not an
// installed header.
#pragma once
#include <nlohmann/json.hpp>
#include <vector>

#include "cubecal/stats/stability.hpp"

namespace cubecal::pipeline::detail {

nlohmann::json curve_json(const std::vector<StabilityPoint>& pts, bool intervals = true, const char* factor_key = "af");

}  // namespace cubecal::pipeline::detail
