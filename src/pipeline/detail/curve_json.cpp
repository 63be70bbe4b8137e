#include "curve_json.hpp"

#include <cstddef>

namespace cubecal::pipeline::detail {

nlohmann::json curve_json(const std::vector<StabilityPoint>& pts, bool intervals, const char* factor_key) {
  std::vector<double> tau, dev, lo, hi, edf;
  std::vector<std::size_t> n, m;
  std::vector<int> alpha;
  for (const auto& p : pts) {
    m.push_back(p.m);
    tau.push_back(p.tau);
    dev.push_back(p.dev);
    n.push_back(p.n);
    if (!intervals) continue;
    lo.push_back(p.interval.lo);
    hi.push_back(p.interval.hi);
    edf.push_back(p.edf);
    alpha.push_back(p.alpha);
  }
  nlohmann::json j{{factor_key, m}, {"tau", tau}, {"dev", dev}, {"n", n}};
  if (intervals) {
    j["lo"] = lo;
    j["hi"] = hi;
    j["edf"] = edf;
    j["alpha"] = alpha;
  }
  return j;
}

}  // namespace cubecal::pipeline::detail
