/// @file
/// A half-open range of sample indices [begin, end): a static interval, a
/// contiguous segment of a record between gaps.
#pragma once
#include <cstddef>

namespace cubecal {

/// A half-open range of sample indices [begin, end).
struct IndexRange {
  std::size_t begin = 0;  ///< first index
  std::size_t end = 0;    ///< one past the last index
  /// The number of indices in the range (samples).
  std::size_t size() const noexcept { return end - begin; }
  friend bool operator==(const IndexRange&, const IndexRange&) = default;
};

}  // namespace cubecal
