/// @file
/// Kernels beyond Stable32's statistics that AllanTools' API exposes
/// (python/cubecal/_allantools.py): the parabolic variance PVAR (Vernotte et
/// al. 2016), the Groslambert covariance of two phase records (the Allan
/// covariance behind a three-cornered hat free of the counters' noise), and
/// the Hadamard total variance of frequency data at any factor, m = 1
/// included (StabilityRecord takes OHVAR there, as Stable32 does).
#pragma once
#include <cstddef>
#include <span>

#include "cubecal/stats/kernels.hpp"

namespace cubecal {

/// Parabolic variance of phase x (N points, spacing tau0) at factor m:
///   PVAR(m tau0) = 72 / (M m^4 (m tau0)^2) sum_{i=0}^{M-1} [ sum_{k=0}^{m-1} ((m-1)/2 - k) (x[i+k] - x[i+k+m]) ]^2
/// with M = N - 2m terms (Vernotte et al. 2016); at m = 1 it is the
/// overlapping Allan variance, {OAVAR, N - 2}. {0, 0} when M < 1. Linear in
/// N for every m (running sums, refreshed every m terms). Throws nothing.
VarianceTerm pvar(std::span<const double> x, std::size_t m, double tau0);

/// Groslambert covariance of phase records x1 and x2 (same length N) at
/// factor m: the mean of the products of their overlapping second
/// differences over 2 (m tau0)^2, {covariance, N - 2m}. It may be negative.
/// {0, 0} when N < 2m + 1 or the lengths differ. Throws nothing.
VarianceTerm allan_covariance(std::span<const double> x1, std::span<const double> x2, std::size_t m, double tau0);

/// Hadamard total variance of fractional frequency y (L points) at factor m
/// >= 1 in units of y^2: every subsequence of 3m points, its linear trend
/// removed, extended to 9m by uninverted even reflection, and the mean
/// square of the 6m second differences of its m-point averages over 6;
/// {HTOT^2, L - 3m + 1}, {0, 0} when L < 3m. Throws nothing.
VarianceTerm htotvar_frequency(std::span<const double> y, std::size_t m);

}  // namespace cubecal
