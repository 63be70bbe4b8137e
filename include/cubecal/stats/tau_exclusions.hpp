/// @file
/// What became of the taus a user listed (`--taus 1,10,1e6`): the ones the
/// statistic cannot evaluate on the record (beyond its largest averaging
/// factor, max_averaging_factor) and the ones that land on the same averaging
/// factor as an earlier tau of the list. A run reports both instead of
/// dropping them silently. Generated grids (octave, decade, all, log:K) end at
/// the largest factor by construction and have nothing to report.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {

/// A listed tau beyond what the record supports.
struct ExcludedTau {
  double tau = 0.0;  ///< as listed, seconds
  /// Whole numbers, kept as doubles: a listed tau may be any size (1e300 s).
  double m = 0.0;       ///< the averaging factor it maps to, round(tau / tau0)
  double needs = 0.0;   ///< samples (of the user's type) the statistic needs for m
  std::size_t has = 0;  ///< samples the record has (its longest contiguous run)
  std::string reason;   ///< "oadev needs at least 4m = 40000 samples for m = 10000, the
                        ///< record has 1000"
};

/// A listed tau that maps to the averaging factor of an earlier listed tau:
/// the two are one point (at tau = m * tau0), evaluated once.
struct MergedTau {
  double tau = 0.0;       ///< as listed, seconds
  double kept_tau = 0.0;  ///< the earlier listed tau it was merged with
  /// The averaging factor both map to.
  std::size_t m = 0;
};

/// What a listed tau grid lost on a record: the taus left out and the taus merged.
struct TauListOutcome {
  std::vector<ExcludedTau> excluded;  ///< in the order listed
  std::vector<MergedTau> merged;      ///< in the order listed; excluded taus are not merged
  /// True when every listed tau is its own point. Throws nothing.
  bool empty() const noexcept { return excluded.empty() && merged.empty(); }
};

/// For an explicit list (TauGrid::Kind::list), the outcome of each tau on a
/// record of `samples` samples of `type` (frequency: N + 1 phase points;
/// phase: N) at interval tau0, for `stat`. Empty for the generated grids.
/// `record` names what `samples` counts in the reasons ("the record", "the
/// longest segment").
TauListOutcome tau_list_outcome(const TauGrid& grid, Stat stat, DataType type, std::size_t samples, double tau0,
                                const std::string& record = "the record");

}  // namespace cubecal
