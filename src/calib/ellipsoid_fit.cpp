// Li & Griffiths (2004) ellipsoid-specific fit, k = 4 (docs/formulas/magnetometer.md §2.1-2.2).
#include "cubecal/calib/ellipsoid_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "detail/eigen_vec3.hpp"

namespace cubecal::mag {

namespace {

using M3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;
using M6 = Eigen::Matrix<double, 6, 6>;
using V6 = Eigen::Matrix<double, 6, 1>;
using M10 = Eigen::Matrix<double, 10, 10>;
using V10 = Eigen::Matrix<double, 10, 1>;
using calib::detail::to_array;
using calib::detail::to_eigen;

[[noreturn]] void degenerate(const std::string& why) {
  throw CalibrationError(CalibrationReason::degenerate, "degenerate ellipsoid fit: " + why);
}

// 4J - I^2 for k = 4.
double constraint(const std::array<double, 10>& v) {
  const double I = v[0] + v[1] + v[2];
  const double J = v[0] * v[1] + v[1] * v[2] + v[2] * v[0] - v[3] * v[3] - v[4] * v[4] - v[5] * v[5];
  return 4.0 * J - I * I;
}

}  // namespace

EllipsoidFit ellipsoid_from_quadric(const std::array<double, 10>& coeff_in, double field_norm) {
  if (!(field_norm > 0.0) || !std::isfinite(field_norm))
    throw CalibrationError(CalibrationReason::field_norm, "the field norm must be positive");
  std::array<double, 10> v = coeff_in;
  for (double x : v)
    if (!std::isfinite(x)) degenerate("non-finite quadric coefficients");
  M3 M;
  M << v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2];
  Eigen::SelfAdjointEigenSolver<M3> es(M);
  if (es.eigenvalues()(2) < 0.0) {  // negative definite: the same quadric times -1
    for (double& x : v) x = -x;
    M = -M;
    es.compute(M);
  }
  const V3 lam = es.eigenvalues();  // ascending
  if (!(lam(2) > 0.0) || !(lam(0) > 1e-12 * lam(2)))
    degenerate("the quadric is not an ellipsoid (M has eigenvalues " + std::to_string(lam(0)) + ", " +
               std::to_string(lam(1)) + ", " + std::to_string(lam(2)) +
               "): the points do not lie on a closed surface around the sensor");
  // Scale so that 4J - I^2 = 1 (it is positive for near-spherical M).
  const double cst = constraint(v);
  const double scale = cst > 0.0 ? 1.0 / std::sqrt(cst) : 1.0 / lam(2);
  for (double& x : v) x *= scale;
  M *= scale;
  const V3 ev = lam * scale;

  EllipsoidFit f;
  f.coeff = v;
  f.M = to_array(M);
  const V3 n(v[6], v[7], v[8]);
  f.n = to_array(n);
  f.d = v[9];
  f.field_norm = field_norm;
  const M3 U = es.eigenvectors();
  const V3 Minv_n = U * ev.cwiseInverse().asDiagonal() * U.transpose() * n;
  const V3 centre = -Minv_n;
  const double G = n.dot(Minv_n) - f.d;
  if (!(G > 0.0) || !std::isfinite(G))
    degenerate("the quadric has no real points (n^T M^-1 n - d = " + std::to_string(G) + ")");
  f.centre = to_array(centre);
  const M3 sqrtM = U * ev.cwiseSqrt().asDiagonal() * U.transpose();
  f.correction = to_array(M3((field_norm / std::sqrt(G)) * sqrtM));
  f.m_eigenvalues = to_array(ev);
  for (int i = 0; i < 3; ++i) f.semi_axes[static_cast<std::size_t>(i)] = std::sqrt(G / ev(i));
  f.axis_ratio = std::sqrt(ev(2) / ev(0));
  return f;
}

namespace {

// C^-1 Sch v = lambda v. The solution is the real eigenvector that
// satisfies the constraint (v^T C v > 0); for a PD Sch there is exactly
// one, with lambda > 0. Exact (noise-free) points make Sch singular and
// lambda ~ 0 of either sign, so the sign of v^T C v decides, and the
// smallest algebraic residual among several candidates. v1 is scaled to
// v^T C v = 1; `best` gets its residual.
V6 constrained_eigenvector(const M6& Sch, const M6& C, const M6& Cinv, double& best) {
  const Eigen::EigenSolver<M6> es(Cinv * Sch);
  if (es.info() != Eigen::Success) degenerate("the eigenproblem did not converge");
  const double lmax = es.eigenvalues().cwiseAbs().maxCoeff();
  best = std::numeric_limits<double>::infinity();
  V6 v1 = V6::Zero();
  bool found = false;
  for (int i = 0; i < 6; ++i) {
    const auto lam = es.eigenvalues()(i);
    if (std::abs(lam.imag()) > 1e-10 * lmax) continue;
    V6 v = es.eigenvectors().col(i).real();
    if (!(v.norm() > 0.0)) continue;
    v.normalize();
    const double c = v.dot(C * v);
    if (!(c > 1e-10)) continue;
    const double obj = v.dot(Sch * v) / c;
    if (obj < best) {
      best = obj;
      v1 = v / std::sqrt(c);
      found = true;
    }
  }
  if (!found) degenerate("no eigenvector satisfies the ellipsoid constraint 4J - I^2 > 0");
  return v1;
}

// Back to input units: centre m + sc c', correction A'^-1 / sc, and the
// quadric x^T M x + 2 n^T x + d with M = M', n = sc n' - M' m,
// d = m^T M' m - 2 sc n'^T m + sc^2 d' (multiplied by sc^2, which keeps
// 4J - I^2 = 1).
EllipsoidFit to_input_units(const EllipsoidFit& fn, const V3& m, double sc) {
  EllipsoidFit f = fn;
  const V3 cp(fn.centre[0], fn.centre[1], fn.centre[2]);
  f.centre = to_array(V3(m + sc * cp));
  for (auto& r : f.correction)
    for (double& x : r) x /= sc;
  for (double& a : f.semi_axes) a *= sc;
  M3 Mp;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Mp(i, j) = fn.M[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  const V3 np(fn.n[0], fn.n[1], fn.n[2]);
  const V3 nr = sc * np - Mp * m;
  const double dr = m.dot(Mp * m) - 2.0 * sc * np.dot(m) + sc * sc * fn.d;
  f.n = to_array(nr);
  f.d = dr;
  f.coeff[6] = nr(0);
  f.coeff[7] = nr(1);
  f.coeff[8] = nr(2);
  f.coeff[9] = dr;
  return f;
}

}  // namespace

EllipsoidFit fit_ellipsoid(std::span<const Vec3> h, double field_norm) {
  const std::size_t n = h.size();
  if (n < kMinPoints)
    throw CalibrationError(
        CalibrationReason::too_few_points,
        "the ellipsoid fit needs at least " + std::to_string(kMinPoints) + " points, got " + std::to_string(n));
  if (!(field_norm > 0.0) || !std::isfinite(field_norm))
    throw CalibrationError(CalibrationReason::field_norm, "the field norm must be positive");
  // Centre on the mean and scale to unit RMS radius: the fit is similarity
  // invariant and the scatter matrix is then well conditioned.
  V3 m = V3::Zero();
  for (const Vec3& p : h) m += V3(p[0], p[1], p[2]);
  m /= static_cast<double>(n);
  double rr = 0.0;
  for (const Vec3& p : h) rr += (V3(p[0], p[1], p[2]) - m).squaredNorm();
  const double sc = std::sqrt(rr / static_cast<double>(n));
  if (!(sc > 0.0) || !std::isfinite(sc)) degenerate("all points are equal");

  M10 S = M10::Zero();
  V10 row;
  for (const Vec3& p : h) {
    const V3 x = (V3(p[0], p[1], p[2]) - m) / sc;
    row << x(0) * x(0), x(1) * x(1), x(2) * x(2), 2.0 * x(1) * x(2), 2.0 * x(0) * x(2), 2.0 * x(0) * x(1), 2.0 * x(0),
        2.0 * x(1), 2.0 * x(2), 1.0;
    S.selfadjointView<Eigen::Lower>().rankUpdate(row);
  }
  S = S.selfadjointView<Eigen::Lower>();
  const M6 S11 = S.topLeftCorner<6, 6>();
  const Eigen::Matrix<double, 6, 4> S12 = S.topRightCorner<6, 4>();
  const Eigen::Matrix4d S22 = S.bottomRightCorner<4, 4>();
  // Coplanar points leave S22 singular (LDLT's rcond does not see an exactly
  // zero pivot, so look at the eigenvalues).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> e22(S22, Eigen::EigenvaluesOnly);
  if (!(e22.eigenvalues()(0) > 1e-10 * e22.eigenvalues()(3)))
    degenerate("the points are coplanar (rotate the sensor through all orientations)");
  const Eigen::LDLT<Eigen::Matrix4d> l22(S22);
  const Eigen::Matrix<double, 4, 6> S22inv_S21 = l22.solve(S12.transpose());
  M6 Sch = S11 - S12 * S22inv_S21;
  Sch = 0.5 * (Sch + Sch.transpose());

  M6 C = M6::Zero();
  C.topLeftCorner<3, 3>() << -1, 1, 1, 1, -1, 1, 1, 1, -1;
  C.bottomRightCorner<3, 3>() = -4.0 * Eigen::Matrix3d::Identity();
  const M6 Cinv = C.inverse();

  double best = 0.0;
  const V6 v1 = constrained_eigenvector(Sch, C, Cinv, best);
  const Eigen::Vector4d v2 = -S22inv_S21 * v1;

  // Coefficients in the normalised coordinates x' = (x - m)/sc.
  std::array<double, 10> u{};
  for (int i = 0; i < 6; ++i) u[static_cast<std::size_t>(i)] = v1(i);
  for (int i = 0; i < 4; ++i) u[static_cast<std::size_t>(6 + i)] = v2(i);
  EllipsoidFit fn = ellipsoid_from_quadric(u, field_norm);
  fn.eigenvalue = best;

  return to_input_units(fn, m, sc);
}

}  // namespace cubecal::mag
