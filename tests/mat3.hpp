// Test support: small 3x3 algebra on std::array, for tests that build
// calibration cases by hand (independent of the Eigen code under test).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "cubecal/math/vec3.hpp"

namespace cubecal::test {

using cubecal::Mat3;
using cubecal::Vec3;

inline Vec3 mul(const Mat3& m, const Vec3& v) {
  Vec3 r{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) r[i] += m[i][j] * v[j];
  return r;
}

inline Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 r{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}

inline Mat3 transpose(const Mat3& a) {
  Mat3 r{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) r[i][j] = a[j][i];
  return r;
}

// By cofactors: exact enough for the well-conditioned matrices of tests.
inline Mat3 inverse(const Mat3& a) {
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  Mat3 r{};
  r[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
  r[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
  r[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
  r[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
  r[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
  r[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
  r[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
  r[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
  r[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
  return r;
}

inline double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

inline double max_abs_diff(const Vec3& a, const Vec3& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < 3; ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

inline double max_abs_diff(const Mat3& a, const Mat3& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) m = std::max(m, std::abs(a[i][j] - b[i][j]));
  return m;
}

}  // namespace cubecal::test
