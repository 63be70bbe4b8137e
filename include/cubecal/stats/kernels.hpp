// Variance kernels on phase data x (N points, spacing tau0). Each returns the
// variance at averaging factor m and the number of terms it averaged (the
// "#" column of Stable32). A result with n == 0 means m is too large.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

namespace cubecal {

struct VarianceTerm {
  double var = 0.0;
  std::size_t n = 0;
};

// Normal (non-overlapping) Allan variance.
VarianceTerm avar(std::span<const double> x, std::size_t m, double tau0);
// Overlapping Allan variance.
VarianceTerm oavar(std::span<const double> x, std::size_t m, double tau0);
// Modified Allan variance (TVAR = tau^2/3 * MVAR).
VarianceTerm mvar(std::span<const double> x, std::size_t m, double tau0);
// Normal (non-overlapping) Hadamard variance.
VarianceTerm hvar(std::span<const double> x, std::size_t m, double tau0);
// Overlapping Hadamard variance.
VarianceTerm ohvar(std::span<const double> x, std::size_t m, double tau0);

// Total variance works on the phase record extended by reflection at both
// ends (SP 1065 eq. 25): build the extension once, then evaluate many m.
struct TotvarExtension {
  std::vector<double> xs;  // x*[-(N-2) .. 2N-3]
  std::size_t offset = 0;  // index of x[0] in xs
  std::size_t n = 0;       // N
};
TotvarExtension totvar_extend(std::span<const double> x);
VarianceTerm totvar(const TotvarExtension& ext, std::size_t m, double tau0);

// The overlapping kernels at several averaging factors at once, out[j] for
// ms[j] (out.size() == ms.size()). Groups of eight consecutive factors
// 8q+1 .. 8q+8 (the `all` grid) share their loads and run about twice as
// fast as one call per factor; the results equal the single-factor calls up
// to rounding, and do not depend on how a grid is cut into calls as long as
// no cut falls inside a group.
inline constexpr std::size_t kKernelGroup = 8;
// True when ms[j .. j+8) is one group: the factors 8q+1 .. 8q+8 in order.
bool kernel_group_at(std::span<const std::size_t> ms, std::size_t j) noexcept;
void oavar(std::span<const double> x, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out);
void ohvar(std::span<const double> x, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out);
void totvar(const TotvarExtension& ext, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out);

// Sum over i of (x[i+2m] - 2x[i+m] + x[i])^2 for i in [0, count): the
// overlapping Allan kernel, exposed for benchmarks.
double second_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept;
// Sum over i of (x[i+3m] - 3x[i+2m] + 3x[i+m] - x[i])^2 for i in [0, count):
// the overlapping Hadamard kernel.
double third_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept;

}  // namespace cubecal
