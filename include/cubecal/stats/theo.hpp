// The Theo family (NIST SP 1065 sec. 5.2.15-16, docs/formulas/stability.md):
// Theo1 and its bias-removed TheoBR. The averaging
// factor m is even and Theo1 at m averages over tau = 0.75 m tau0.
#pragma once
#include <cstddef>
#include <span>

#include "cubecal/stats/kernels.hpp"

namespace cubecal {

// Theo1 variance of phase x at even factor m (2 <= m <= N - 1):
// {Theo1^2, (N - m) m / 2}, the number of squared terms (Stable32's "#").
VarianceTerm theo1var(std::span<const double> x, std::size_t m, double tau0);

// TheoBR's bias ratio of a record of N phase points: the mean over
// i = 0 .. floor(N/6 - 3) of AVAR(9 + 3i) / Theo1(12 + 4i), the overlapping
// Allan variance and Theo1 at the same tau (Howe, Taylor & Tassett 2006).
// TheoBR(m) = ratio * Theo1(m). 0 when the record is shorter than 30 points
// or a Theo1 term vanishes (constant phase).
double theobr_ratio(std::span<const double> x);

}  // namespace cubecal
