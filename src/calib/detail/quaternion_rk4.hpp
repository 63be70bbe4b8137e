// Attitude integration for the multi-position gyroscope fit
// (docs/formulas/multiposition.md §4.2): one RK4 step of q' = q (x) (0, w) / 2
// with the rates at both ends of the step and their mean at the midpoint, as
// imu_tk integrates. Not an installed header.
#pragma once
#include <Eigen/Dense>
#include <cmath>

#include "cubecal/math/vec3.hpp"

namespace cubecal::calib::detail {

struct Quat {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};

// q' = Omega(w) q / 2 (imu_tk's computeOmegaSkew): q (x) (0, w) / 2.
inline Quat omega_times(const Vec3& w, const Quat& q) {
  return {0.5 * (-w[0] * q.x - w[1] * q.y - w[2] * q.z), 0.5 * (w[0] * q.w + w[2] * q.y - w[1] * q.z),
          0.5 * (w[1] * q.w - w[2] * q.x + w[0] * q.z), 0.5 * (w[2] * q.w + w[1] * q.x - w[0] * q.y)};
}

inline Quat axpy(const Quat& q, double a, const Quat& k) {
  return {q.w + a * k.w, q.x + a * k.x, q.y + a * k.y, q.z + a * k.z};
}

inline Quat rk4_step(const Quat& q, const Vec3& w0, const Vec3& w1, double dt) {
  const Vec3 wm{0.5 * (w0[0] + w1[0]), 0.5 * (w0[1] + w1[1]), 0.5 * (w0[2] + w1[2])};
  const Quat k1 = omega_times(w0, q);
  const Quat k2 = omega_times(wm, axpy(q, 0.5 * dt, k1));
  const Quat k3 = omega_times(wm, axpy(q, 0.5 * dt, k2));
  const Quat k4 = omega_times(w1, axpy(q, dt, k3));
  Quat r{q.w + dt / 6.0 * (k1.w + 2.0 * k2.w + 2.0 * k3.w + k4.w),
         q.x + dt / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x),
         q.y + dt / 6.0 * (k1.y + 2.0 * k2.y + 2.0 * k3.y + k4.y),
         q.z + dt / 6.0 * (k1.z + 2.0 * k2.z + 2.0 * k3.z + k4.z)};
  const double n = std::sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
  r.w /= n;
  r.x /= n;
  r.y /= n;
  r.z /= n;
  return r;
}

// R(q)^T v: the vector v given in the start frame, expressed in the end frame.
inline Eigen::Vector3d rotate_inverse(const Quat& q, const Eigen::Vector3d& v) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  Eigen::Matrix3d R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return R.transpose() * v;
}

}  // namespace cubecal::calib::detail
