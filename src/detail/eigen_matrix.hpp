// Conversions between Matrix (math/matrix.hpp) and Eigen's dynamic and
// fixed-size matrices, for the solvers that work in Eigen inside their .cpp
// files. Not an installed header.
#pragma once
#include <Eigen/Core>
#include <cstddef>

#include "cubecal/math/matrix.hpp"

namespace cubecal::detail {

template <class Derived>
Matrix to_matrix(const Eigen::MatrixBase<Derived>& m) {
  Matrix r(static_cast<std::size_t>(m.rows()), static_cast<std::size_t>(m.cols()));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) r(static_cast<std::size_t>(i), static_cast<std::size_t>(j)) = m(i, j);
  return r;
}

inline Eigen::MatrixXd to_eigen(const Matrix& m) {
  Eigen::MatrixXd r(static_cast<Eigen::Index>(m.rows()), static_cast<Eigen::Index>(m.cols()));
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t j = 0; j < m.cols(); ++j) r(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m(i, j);
  return r;
}

}  // namespace cubecal::detail
