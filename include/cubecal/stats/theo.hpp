/// @file
/// The Theo family (NIST SP 1065 sec. 5.2.15-16, docs/formulas/stability.md):
/// Theo1, its bias-removed TheoBR, and the hybrid TheoH. The averaging
/// factor m of Theo1 is even and Theo1 at m averages over tau = 0.75 m tau0.
#pragma once
#include <cstddef>
#include <span>

#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {

/// Theo1 variance of phase x at even factor m (2 <= m <= N - 1):
/// {Theo1^2, (N - m) m / 2}, the number of squared terms (Stable32's "#").
VarianceTerm theo1var(std::span<const double> x, std::size_t m, double tau0);

/// TheoBR's bias ratio of a record of N phase points: the mean over
/// i = 0 .. floor(N/6 - 3) of AVAR(9 + 3i) / Theo1(12 + 4i), the overlapping
/// Allan variance and Theo1 at the same tau (Howe, Taylor & Tassett 2006).
/// TheoBR(m) = ratio * Theo1(m). 0 when the record is shorter than 30 points
/// or a Theo1 term vanishes (constant phase).
double theobr_ratio(std::span<const double> x);

/// TheoH at factor m (statistic.hpp, theoh_stat_at): the overlapping AVAR
/// at m below the switch factor, `ratio` * Theo1(m) (TheoBR, ratio from
/// theobr_ratio) at even m from the first Theo factor on; {} in between, at
/// odd m beyond, or when ratio is not positive on the TheoBR side.
VarianceTerm theohvar(std::span<const double> x, std::size_t m, double tau0, double ratio);

/// `grid` with the listed taus TheoH puts on its TheoBR side (tau >= k, the
/// switch tau, on n_phase points at interval tau0) divided by 0.75, so that
/// averaging_factors(grid, max_m, tau0) gives TheoH's factor of every listed
/// tau (m = round(tau / tau0) below k, round(tau / (0.75 tau0)) from k on).
/// Generated grids are returned as they are (their factors are TheoH's).
TauGrid theoh_factor_grid(const TauGrid& grid, std::size_t n_phase, double tau0);

}  // namespace cubecal
