/// @file
/// The small linear-algebra vocabulary every module shares: 3-vectors and 3x3
/// matrices (row-major, m[row][col]) of a triad; matrices of any other size
/// are a Matrix (matrix.hpp), index ranges an IndexRange (index_range.hpp).
/// Plain arrays, so results stay aggregates that serialise and copy
/// trivially; solvers convert to Eigen internally.
#pragma once
#include <array>
#include <cstddef>

#include "cubecal/math/index_range.hpp"

namespace cubecal {

/// A 3-vector (x, y, z), in the unit of what it holds.
using Vec3 = std::array<double, 3>;
using Mat3 = std::array<std::array<double, 3>, 3>;  ///< m[row][col]

/// The 3x3 identity matrix.
///@{
inline constexpr Mat3 kIdentity3{{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
///@}

}  // namespace cubecal
