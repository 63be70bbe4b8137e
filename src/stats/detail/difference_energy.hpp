// The inner loops of the overlapping Allan and Hadamard kernels
// (stats/kernels.hpp) over raw phase points, for the kernels, the dynamic
// Allan deviation's block sums, the streamed deviations and the benchmarks.
#pragma once
#include <cstddef>

namespace cubecal {

// Sum over i of (x[i+2m] - 2x[i+m] + x[i])^2 for i in [0, count): the
// overlapping Allan kernel, exposed for benchmarks.
double second_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept;
// Sum over i of (x[i+3m] - 3x[i+2m] + 3x[i+m] - x[i])^2 for i in [0, count):
// the overlapping Hadamard kernel.
double third_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept;

}  // namespace cubecal
