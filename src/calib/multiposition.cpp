// Multi-position calibration without a turntable (docs/formulas/multiposition.md): the
// triad model T K (x - B) and both calibrations in one call. Static
// detection: static_detection.cpp; the fits: multiposition_accelerometer.cpp
// and multiposition_gyroscope.cpp; the solver and the quaternion integration:
// detail/.
#include "cubecal/calib/multiposition.hpp"

namespace cubecal::multipos {

Mat3 TriadCalibration::misalignment() const noexcept {
  // 0.0 - x: no negative zeros in printed matrices.
  return Mat3{{{1.0, 0.0 - mis_yz, mis_zy}, {mis_xz, 1.0, 0.0 - mis_zx}, {0.0 - mis_xy, mis_yx, 1.0}}};
}

Mat3 TriadCalibration::matrix() const noexcept {
  Mat3 t = misalignment();
  for (auto& row : t)
    for (std::size_t j = 0; j < 3; ++j) row[j] *= scale[j];
  return t;
}

Vec3 TriadCalibration::apply(const Vec3& raw) const noexcept {
  const Mat3 m = matrix();
  Vec3 out{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) out[i] += m[i][j] * (raw[j] - bias[j]);
  return out;
}

Result calibrate(const TriadSeries& acc, const TriadSeries& gyro, const Options& opt) {
  Result r;
  r.acc = calibrate_accelerometer(acc, opt);
  r.gyro = calibrate_gyroscope(acc, r.acc, gyro, opt);
  return r;
}

}  // namespace cubecal::multipos
