/// @file
/// A dense matrix of any size as results carry it (a covariance, a Jacobian,
/// a hat matrix): rows x cols doubles, row-major, m(i, j). The fixed 3x3 of
/// a triad stays Mat3 (vec3.hpp); every other matrix of the API is a Matrix.
/// Solvers convert to Eigen internally; the pipeline writes it in JSON as an
/// array of rows (src/pipeline/detail/matrix_json.hpp).
#pragma once
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace cubecal {

/// A dense rows x cols matrix of doubles, row-major, indexed m(i, j).
class Matrix {
 public:
  Matrix() = default;
  /// A rows x cols matrix with every entry `fill`.
  Matrix(std::size_t rows, std::size_t cols, double fill = 0.0) : rows_(rows), cols_(cols), data_(rows * cols, fill) {}

  /// The number of rows.
  std::size_t rows() const noexcept { return rows_; }
  /// The number of columns.
  std::size_t cols() const noexcept { return cols_; }
  /// True when the matrix has no rows or no columns.
  bool empty() const noexcept { return rows_ == 0 || cols_ == 0; }

  /// The entry at row `i`, column `j` (0-based, unchecked).
  double& operator()(std::size_t i, std::size_t j) noexcept { return data_[i * cols_ + j]; }
  /// The entry at row `i`, column `j` (0-based, unchecked).
  double operator()(std::size_t i, std::size_t j) const noexcept { return data_[i * cols_ + j]; }
  /// Row `i` (0-based, unchecked), cols() entries.
  std::span<double> row(std::size_t i) noexcept { return {data_.data() + i * cols_, cols_}; }
  /// Row `i` (0-based, unchecked), cols() entries.
  std::span<const double> row(std::size_t i) const noexcept { return {data_.data() + i * cols_, cols_}; }
  /// Every entry, row after row.
  std::span<double> values() noexcept { return data_; }
  /// Every entry, row after row.
  std::span<const double> values() const noexcept { return data_; }

  friend bool operator==(const Matrix&, const Matrix&) = default;

 private:
  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  std::vector<double> data_;
};

}  // namespace cubecal
