/// @file
/// The small linear-algebra vocabulary every module shares: 3-vectors, 3x3
/// matrices (row-major, m[row][col]) and half-open index ranges. Plain
/// arrays, so results stay aggregates that serialise and copy trivially;
/// solvers convert to Eigen internally.
#pragma once
#include <array>
#include <cstddef>

namespace cubecal {

/// A 3-vector (x, y, z), in the unit of what it holds.
using Vec3 = std::array<double, 3>;
using Mat3 = std::array<std::array<double, 3>, 3>;  ///< m[row][col]

/// The 3x3 identity matrix.
///@{
inline constexpr Mat3 kIdentity3{{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
///@}

/// Half-open range of sample indices [begin, end).
struct IndexRange {
  /// First index.
  std::size_t begin = 0;
  /// One past the last index.
  std::size_t end = 0;
  /// Indices in the range. Throws nothing.
  std::size_t size() const noexcept { return end - begin; }
  friend bool operator==(const IndexRange&, const IndexRange&) = default;
};

}  // namespace cubecal
