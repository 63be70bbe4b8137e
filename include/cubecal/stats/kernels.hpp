/// @file
/// Variance kernels on phase data x (N points, spacing tau0). Each returns the
/// variance at averaging factor m and the number of terms it averaged (the
/// "#" column of Stable32). A result with n == 0 means m is too large.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

namespace cubecal {

/// A variance at one averaging factor and the number of terms it averaged.
struct VarianceTerm {
  /// The variance, in the phase's unit^2 over tau0's unit^2 (the frequency's unit^2).
  double var = 0.0;
  /// Terms averaged; 0 when m is too large for the record.
  std::size_t n = 0;
};

/// Normal (non-overlapping) Allan variance.
VarianceTerm avar(std::span<const double> x, std::size_t m, double tau0);
/// Overlapping Allan variance.
VarianceTerm oavar(std::span<const double> x, std::size_t m, double tau0);
/// Modified Allan variance (TVAR = tau^2/3 * MVAR).
VarianceTerm mvar(std::span<const double> x, std::size_t m, double tau0);
/// Normal (non-overlapping) Hadamard variance.
VarianceTerm hvar(std::span<const double> x, std::size_t m, double tau0);
/// Overlapping Hadamard variance.
VarianceTerm ohvar(std::span<const double> x, std::size_t m, double tau0);

/// Total variance works on the phase record extended by reflection at both
/// ends (SP 1065 eq. 25): build the extension once, then evaluate many m.
struct TotvarExtension {
  std::vector<double> xs;  ///< x*[-(N-2) .. 2N-3]
  std::size_t offset = 0;  ///< index of x[0] in xs
  std::size_t n = 0;       ///< N
};
/// The reflected extension of phase record x (N >= 2 points). Throws nothing beyond std::bad_alloc.
TotvarExtension totvar_extend(std::span<const double> x);
/// Total variance at factor m from the extension. Throws nothing.
VarianceTerm totvar(const TotvarExtension& ext, std::size_t m, double tau0);

/// The overlapping kernels at several averaging factors at once, out[j] for
/// ms[j] (out.size() == ms.size()). Groups of eight consecutive factors
/// 8q+1 .. 8q+8 (the `all` grid) share their loads and run about twice as
/// fast as one call per factor; the results equal the single-factor calls up
/// to rounding, and do not depend on how a grid is cut into calls as long as
/// no cut falls inside a group.
inline constexpr std::size_t kKernelGroup = 8;
/// True when ms[j .. j+8) is one group: the factors 8q+1 .. 8q+8 in order.
bool kernel_group_at(std::span<const std::size_t> ms, std::size_t j) noexcept;
/// The overlapping Allan variance at every factor of ms (see above). Throws nothing.
void oavar(std::span<const double> x, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out);
/// The overlapping Hadamard variance at every factor of ms (see above). Throws nothing.
void ohvar(std::span<const double> x, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out);
/// The total variance at every factor of ms (see above). Throws nothing.
void totvar(const TotvarExtension& ext, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out);

// Kernels beyond Stable32's statistics that AllanTools' API exposes
// (python/cubecal/_allantools.py): the parabolic variance, the Groslambert
// covariance of two phase records (the Allan covariance behind a
// three-cornered hat free of the counters' noise), and the Hadamard total
// variance of frequency data at any factor, m = 1 included (StabilityRecord
// takes OHVAR there, as Stable32 does).

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
