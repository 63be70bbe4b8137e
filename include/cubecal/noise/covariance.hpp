/// @file
/// Sample covariance matrix of several channels (the paper's eq. 12;
/// docs/formulas/drift-covariance-temperature.md §2).
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/math/matrix.hpp"

namespace cubecal {

/// channels[c] holds one channel; the first `count` samples of each are used
/// (0: all). Unbiased (n-1) normalization. k x k result.
Matrix covariance_matrix(const std::vector<std::span<const double>>& channels, std::size_t count = 0);

}  // namespace cubecal
