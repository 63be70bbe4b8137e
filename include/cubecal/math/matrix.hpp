// A dense matrix of any size as results carry it (a covariance, a Jacobian,
// a hat matrix): rows x cols doubles, row-major, m(i, j). The fixed 3x3 of
// a triad stays Mat3 (vec3.hpp); every other matrix of the API is a Matrix.
// Solvers convert to Eigen internally. JSON (nlohmann) takes and gives it as
// an array of rows, found by argument-dependent lookup.
#pragma once
#include <cstddef>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace cubecal {

class Matrix {
 public:
  Matrix() = default;
  Matrix(std::size_t rows, std::size_t cols, double fill = 0.0) : rows_(rows), cols_(cols), data_(rows * cols, fill) {}

  std::size_t rows() const noexcept { return rows_; }
  std::size_t cols() const noexcept { return cols_; }
  bool empty() const noexcept { return rows_ == 0 || cols_ == 0; }

  double& operator()(std::size_t i, std::size_t j) noexcept { return data_[i * cols_ + j]; }
  double operator()(std::size_t i, std::size_t j) const noexcept { return data_[i * cols_ + j]; }
  std::span<double> row(std::size_t i) noexcept { return {data_.data() + i * cols_, cols_}; }
  std::span<const double> row(std::size_t i) const noexcept { return {data_.data() + i * cols_, cols_}; }
  // Every entry, row after row.
  std::span<double> values() noexcept { return data_; }
  std::span<const double> values() const noexcept { return data_; }

  friend bool operator==(const Matrix&, const Matrix&) = default;

 private:
  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  std::vector<double> data_;
};

// nlohmann::json: [[row 0], [row 1], ...]; no rows is [].
template <class Json>
void to_json(Json& j, const Matrix& m) {
  j = Json::array();
  for (std::size_t i = 0; i < m.rows(); ++i) {
    Json row = Json::array();
    for (double v : m.row(i)) row.push_back(v);
    j.push_back(std::move(row));
  }
}

// From an array of rows of equal length (std::invalid_argument for a ragged
// one).
template <class Json>
void from_json(const Json& j, Matrix& m) {
  const auto rows = j.template get<std::vector<std::vector<double>>>();
  const std::size_t cols = rows.empty() ? 0 : rows[0].size();
  m = Matrix(rows.size(), cols);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != cols) throw std::invalid_argument("matrix rows of different lengths");
    for (std::size_t k = 0; k < cols; ++k) m(i, k) = rows[i][k];
  }
}

}  // namespace cubecal
