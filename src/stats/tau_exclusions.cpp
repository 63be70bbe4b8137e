#include "cubecal/stats/tau_exclusions.hpp"

#include <cmath>
#include <cstdio>
#include <map>

namespace cubecal {

namespace {

// Up to 15 significant digits: a whole number below 1e15 prints exactly.
std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.15g", v);
  return b;
}

}  // namespace

TauListOutcome tau_list_outcome(const TauGrid& grid, Stat stat, DataType type, std::size_t samples, double tau0,
                                const std::string& record) {
  TauListOutcome out;
  if (grid.kind != TauGrid::Kind::list || !(tau0 > 0.0)) return out;
  const std::size_t n_phase = type == DataType::freq ? samples + 1 : samples;
  const std::size_t max_m = max_averaging_factor(stat, n_phase);
  const double per = static_cast<double>(points_per_factor(stat));
  std::map<double, double> first_tau;  // evaluated factor -> the first listed tau on it
  for (double tau : grid.taus) {
    double m = listed_factor(tau, tau0 * tau_per_factor(stat));
    // TheoH: from the switch tau on, the TheoBR factor (tau = 0.75 m tau0).
    if (stat == Stat::theoh && tau >= static_cast<double>(theoh_switch_factor(n_phase)) * tau0)
      m = listed_factor(tau, 0.75 * tau0);
    if (m > static_cast<double>(max_m)) {
      // Frequency data: N samples are N + 1 phase points, so the limit
      // N + 1 >= per * m + 1 reads N >= per * m.
      const bool freq = type == DataType::freq;
      ExcludedTau e;
      e.tau = tau;
      e.m = m;
      e.needs = per * m + (freq ? 0.0 : 1.0);
      e.has = samples;
      e.reason = std::isfinite(e.needs)
                     ? std::string(to_string(stat)) + " needs at least " + number(per) + "m" + (freq ? "" : "+1") +
                           " = " + number(e.needs) + (freq ? " samples" : " phase samples") + " for m = " + number(m) +
                           ", " + record + " has " + std::to_string(samples)
                     // A tau so long that its factor overflows: no "m = inf".
                     : std::string(to_string(stat)) + " at " + number(tau) + " s: more sample periods of " +
                           number(tau0) + " s than a number holds, " + record + " has " + std::to_string(samples);
      out.excluded.push_back(std::move(e));
      continue;
    }
    const auto [it, fresh] = first_tau.emplace(m, tau);
    if (!fresh) out.merged.push_back({tau, it->second, static_cast<std::size_t>(m)});
  }
  return out;
}

}  // namespace cubecal
