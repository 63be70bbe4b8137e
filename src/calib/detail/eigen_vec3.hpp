// Conversions between the shared Vec3/Mat3 vocabulary (math/vec3.hpp) and
// Eigen's fixed-size types, for the solvers that work in Eigen inside their
// .cpp files. Not an installed header.
#pragma once
#include <Eigen/Core>
#include <cstddef>

#include "cubecal/math/vec3.hpp"

namespace cubecal::calib::detail {

inline Eigen::Vector3d to_eigen(const Vec3& v) { return {v[0], v[1], v[2]}; }

inline Eigen::Matrix3d to_eigen(const Mat3& m) {
  Eigen::Matrix3d r;
  for (Eigen::Index i = 0; i < 3; ++i)
    for (Eigen::Index j = 0; j < 3; ++j) r(i, j) = m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  return r;
}

inline Vec3 to_array(const Eigen::Vector3d& v) { return {v(0), v(1), v(2)}; }

inline Mat3 to_array(const Eigen::Matrix3d& m) {
  Mat3 r{};
  for (Eigen::Index i = 0; i < 3; ++i)
    for (Eigen::Index j = 0; j < 3; ++j) r[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = m(i, j);
  return r;
}

}  // namespace cubecal::calib::detail
