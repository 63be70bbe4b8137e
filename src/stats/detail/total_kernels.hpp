// The modified and Hadamard total variances (NIST SP 1065 sec. 5.2.12-14,
// docs/formulas/stability.md): every subsequence of 3m points, its linear
// trend removed by the means of its two halves, extended to 9m points by
// uninverted even reflection, and the 6m second differences of its m-point
// averages. MTOT works on phase, HTOT on frequency (the phase differences);
// TTOT is MTOT scaled by tau^2/3.
#pragma once
#include <cstddef>
#include <span>

#include "cubecal/stats/kernels.hpp"

namespace cubecal {

// Modified total variance of phase x at factor m: {MTOT^2, N - 3m + 1}.
VarianceTerm mtotvar(std::span<const double> x, std::size_t m, double tau0);

// Hadamard total variance at factor m >= 2 from the phase differences
// d[k] = x[k+1] - x[k] (N - 1 of them): {HTOT^2, N - 3m}. Stable32 (and
// Riley's definition) take the overlapping Hadamard variance at m = 1; so
// does StabilityRecord, not this kernel.
VarianceTerm htotvar(std::span<const double> d, std::size_t m, double tau0);

}  // namespace cubecal
