// TWOSTEP (Alonso & Shuster 2002), bias only and bias + symmetric D, written
// as one estimator: z_k = L_k theta - phi(theta) + mu_k + v_k with
//   bias only: L_k = 2 B_k^T,                 theta = b,      phi = |b|^2
//   full:      L_k = [2B, -B1^2, -B2^2, -B3^2, -2B1B2, -2B1B3, -2B2B3],
//              theta = [c; E11 E22 E33 E12 E13 E23],   phi = c^T (I+E)^-1 c.
// The weighted cost splits exactly into a centred part, linear in theta, and
// one centre equation; step 1 solves the centred part, step 2 runs Fisher
// scoring on both (docs/formulas/magnetometer.md §1.3-1.6).
#include "cubecal/calib/twostep.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "../detail/eigen_matrix.hpp"
#include "detail/eigen_vec3.hpp"

namespace cubecal::mag {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using M3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;
using calib::detail::to_array;
using calib::detail::to_eigen;
using cubecal::detail::to_matrix;

// Symmetric matrix from the 6 entries E11 E22 E33 E12 E13 E23.
M3 sym(const double* e) {
  M3 m;
  m << e[0], e[3], e[4], e[3], e[1], e[5], e[4], e[5], e[2];
  return m;
}

// Index pairs of the 6 symmetric entries, in the order above.
constexpr int kSymI[6] = {0, 1, 2, 0, 0, 1};
constexpr int kSymJ[6] = {0, 1, 2, 1, 2, 2};

class Model {
 public:
  explicit Model(bool full) : full_(full), p_(full ? 9 : 3) {}
  Index params() const { return p_; }

  void row(const V3& B, double* L) const {
    L[0] = 2.0 * B(0);
    L[1] = 2.0 * B(1);
    L[2] = 2.0 * B(2);
    if (!full_) return;
    L[3] = -B(0) * B(0);
    L[4] = -B(1) * B(1);
    L[5] = -B(2) * B(2);
    L[6] = -2.0 * B(0) * B(1);
    L[7] = -2.0 * B(0) * B(2);
    L[8] = -2.0 * B(1) * B(2);
  }

  // phi(theta) and its gradient; false when I + E is singular.
  bool phi(const VectorXd& th, double& value, VectorXd& grad) const {
    grad.resize(p_);
    const V3 c(th(0), th(1), th(2));
    if (!full_) {
      value = c.squaredNorm();
      grad.head<3>() = 2.0 * c;
      return true;
    }
    const M3 IE = M3::Identity() + sym(th.data() + 3);
    const Eigen::FullPivLU<M3> lu(IE);
    if (!lu.isInvertible()) return false;
    const V3 x = lu.solve(c);
    if (!x.allFinite()) return false;
    value = c.dot(x);
    grad.head<3>() = 2.0 * x;
    grad(3) = -x(0) * x(0);
    grad(4) = -x(1) * x(1);
    grad(5) = -x(2) * x(2);
    grad(6) = -2.0 * x(0) * x(1);
    grad(7) = -2.0 * x(0) * x(2);
    grad(8) = -2.0 * x(1) * x(2);
    return true;
  }

 private:
  bool full_;
  Index p_;
};

// F^-1 for a symmetric positive semi-definite F; throws when F is singular
// (after equilibration by its diagonal, smallest / largest eigenvalue below
// 1e-13: LDLT alone would quietly treat zero pivots as a pseudo-inverse).
MatrixXd checked_inverse(const MatrixXd& F) {
  const Index p = F.rows();
  const VectorXd dg = F.diagonal().cwiseMax(1e-300).cwiseSqrt();
  const MatrixXd Fs = dg.asDiagonal().inverse() * F * dg.asDiagonal().inverse();
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(Fs);
  const VectorXd ev = es.eigenvalues();
  if (es.info() != Eigen::Success || !F.allFinite() || !(ev(0) > 1e-13 * ev(p - 1)))
    throw CalibrationError(
        CalibrationReason::degenerate,
        "TWOSTEP: singular information matrix (the points do not determine the parameters; rotate the sensor "
        "through all orientations)");
  MatrixXd inv = dg.asDiagonal().inverse() * es.eigenvectors() * ev.cwiseInverse().asDiagonal() *
                 es.eigenvectors().transpose() * dg.asDiagonal().inverse();
  return 0.5 * (inv + inv.transpose());
}

struct Problem {
  const Model& model;
  const std::vector<V3>& B;       // scaled
  const std::vector<double>& H2;  // scaled |H_k|^2
  std::vector<double> z;          // |B_k|^2 - |H_k|^2
};

struct Solution {
  VectorXd theta, centred;
  MatrixXd P;  // F^-1 at theta
  double chi2 = 0.0;
  double centred_condition = 0.0;
  bool centred_degenerate = false;
  std::size_t iterations = 0;
  double eta = 0.0;
  bool converged = false;
  std::vector<double> resid;  // z_k - mu_k - L_k theta + phi
};

// One estimate for a known (scaled) noise variance s2.
Solution solve(const Problem& pr, double s2, bool mean_correction, const TwostepOptions& opt) {
  const Index p = pr.model.params();
  const std::size_t n = pr.B.size();
  std::vector<double> w(n);
  double W = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    w[k] = 1.0 / (4.0 * s2 * pr.H2[k] + 6.0 * s2 * s2);
    W += w[k];
  }
  const double mu = mean_correction ? -3.0 * s2 : 0.0;  // the same for every k: mu~ = 0

  // Weighted centres (two passes: no cancellation in the centred sums).
  std::vector<double> Lk(static_cast<std::size_t>(p));
  VectorXd Lbar = VectorXd::Zero(p);
  double zbar = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    pr.model.row(pr.B[k], Lk.data());
    for (Index j = 0; j < p; ++j) Lbar(j) += w[k] * Lk[static_cast<std::size_t>(j)];
    zbar += w[k] * pr.z[k];
  }
  Lbar /= W;
  zbar /= W;
  MatrixXd Ft = MatrixXd::Zero(p, p);
  VectorXd yt = VectorXd::Zero(p);
  VectorXd Lc(p);
  for (std::size_t k = 0; k < n; ++k) {
    pr.model.row(pr.B[k], Lk.data());
    for (Index j = 0; j < p; ++j) Lc(j) = Lk[static_cast<std::size_t>(j)] - Lbar(j);
    Ft.noalias() += w[k] * Lc * Lc.transpose();
    yt.noalias() += (w[k] * (pr.z[k] - zbar)) * Lc;
  }

  Solution s;
  // Step 1: the centred estimate. The information matrix is equilibrated by
  // its diagonal; directions it does not determine (constant |H| in the full
  // model, points on one circle for bias only) are left at zero and fixed by
  // step 2.
  {
    // A diagonal entry negligible against the largest is a direction without
    // information: it is not scaled up (that would hide the degeneracy).
    const double dmax = Ft.diagonal().maxCoeff();
    if (!(dmax > 0.0))
      throw CalibrationError(CalibrationReason::degenerate,
                             "TWOSTEP: all points are equal (rotate the sensor through all orientations)");
    const VectorXd dg = Ft.diagonal().cwiseMax(1e-12 * dmax).cwiseSqrt();
    const MatrixXd Fs = dg.asDiagonal().inverse() * Ft * dg.asDiagonal().inverse();
    const Eigen::SelfAdjointEigenSolver<MatrixXd> es(Fs);
    const VectorXd ev = es.eigenvalues();
    const double lmax = ev(p - 1);
    s.centred_condition = lmax > 0.0 ? std::max(ev(0), 0.0) / lmax : 0.0;
    s.centred_degenerate = !(s.centred_condition > 1e-12);
    VectorXd inv = VectorXd::Zero(p);
    for (Index j = 0; j < p; ++j)
      if (ev(j) > 1e-12 * lmax) inv(j) = 1.0 / ev(j);
    const VectorXd ys = dg.asDiagonal().inverse() * yt;
    s.centred =
        dg.asDiagonal().inverse() * (es.eigenvectors() * (inv.asDiagonal() * (es.eigenvectors().transpose() * ys)));
  }

  // Step 2: Fisher scoring on the whole cost.
  VectorXd th = s.centred;
  VectorXd grad(p);
  MatrixXd F(p, p);
  double phi = 0.0;
  auto information = [&](const VectorXd& t, VectorXd& g) {
    if (!pr.model.phi(t, phi, grad))
      throw CalibrationError(CalibrationReason::degenerate,
                             "TWOSTEP: I + E became singular (the points do not fit a linear calibration)");
    const VectorXd a = Lbar - grad;
    const double e = zbar - mu - Lbar.dot(t) + phi;  // centre residual
    g = Ft * t - yt - (W * e) * a;
    F = Ft + W * a * a.transpose();
  };
  VectorXd g(p);
  for (s.iterations = 0; s.iterations < opt.max_iterations;) {
    information(th, g);
    const VectorXd dx = -(checked_inverse(F) * g);
    s.eta = dx.dot(F * dx);
    th += dx;
    ++s.iterations;
    if (s.eta < opt.eta_tol) {
      s.converged = true;
      break;
    }
  }
  information(th, g);
  s.theta = th;
  s.P = checked_inverse(F);

  s.resid.resize(n);
  s.chi2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    pr.model.row(pr.B[k], Lk.data());
    double lt = 0.0;
    for (Index j = 0; j < p; ++j) lt += Lk[static_cast<std::size_t>(j)] * th(j);
    s.resid[k] = pr.z[k] - mu - lt + phi;
    s.chi2 += w[k] * s.resid[k] * s.resid[k];
  }
  return s;
}

// The options and the measurements, as twostep.hpp's CalibrationErrors say.
void check_input(std::span<const Vec3> Bin, std::span<const double> Hin, const TwostepOptions& opt, std::size_t p) {
  const std::size_t n = Bin.size();
  if (n < p + 1)
    throw CalibrationError(CalibrationReason::too_few_points, "TWOSTEP" + std::string(opt.full ? " (full)" : "") +
                                                                  " needs at least " + std::to_string(p + 1) +
                                                                  " points, got " + std::to_string(n));
  if (Hin.size() != 1 && Hin.size() != n)
    throw CalibrationError(
        CalibrationReason::field_norm,
        "TWOSTEP: give one field norm or one per point (" + std::to_string(n) + "), got " + std::to_string(Hin.size()));
  for (double h : Hin)
    if (!(h > 0.0) || !std::isfinite(h))
      throw CalibrationError(CalibrationReason::field_norm, "TWOSTEP: field norms must be positive");
  if (!(opt.noise >= 0.0) || !std::isfinite(opt.noise))
    throw CalibrationError(CalibrationReason::bad_option, "TWOSTEP: the noise must be a positive standard deviation");
  if (!(opt.eta_tol > 0.0) || opt.max_iterations == 0)
    throw CalibrationError(CalibrationReason::bad_option, "TWOSTEP: eta_tol and max_iterations must be positive");
  for (const Vec3& b : Bin)
    for (double v : b)
      if (!std::isfinite(v)) throw CalibrationError(CalibrationReason::bad_data, "TWOSTEP: non-finite measurement");
}

// The solution for the noise given, or for the noise that makes chi2 = dof
// (then estimated into s2). Scaled units.
Solution solve_for_noise(const Problem& pr, const std::vector<double>& H2, std::size_t dof, double kappa,
                         const TwostepOptions& opt, double& s2) {
  const std::size_t n = H2.size();
  Solution sol;
  const bool estimate = opt.noise == 0.0;
  if (!estimate) {
    s2 = (opt.noise / kappa) * (opt.noise / kappa);
    sol = solve(pr, s2, opt.mean_correction, opt);
  } else {
    // Noise from the residuals: solve chi2(s) = dof, i.e. the fixed point
    // s^2 = sum r_k^2 / (4|H_k|^2 + 6 s^2) / dof, re-estimating theta with
    // the weights and mean of each s.
    constexpr double kFloor = 1e-30;   // noise-free data: s = 1e-15 |H|
    sol = solve(pr, 1.0, false, opt);  // weights ~ 1/|H_k|^2 (s^2 cancels)
    for (int round = 0; round < 4; ++round) {
      double acc = 0.0;
      for (std::size_t k = 0; k < n; ++k) acc += sol.resid[k] * sol.resid[k] / (4.0 * H2[k] + 6.0 * s2);
      s2 = std::max(acc / static_cast<double>(dof), kFloor);
      sol = solve(pr, s2, opt.mean_correction, opt);
    }
  }
  return sol;
}

// (c, E) -> (b, D): E = U diag(e) U^T, D = U diag(sqrt(1+e) - 1) U^T,
// b = (I+D)^-1 c. `clamp` only for the diagnostic step-1 values.
bool recover(const VectorXd& t, bool clamp, M3& Dm, V3& bv) {
  const Eigen::SelfAdjointEigenSolver<M3> es(sym(t.data() + 3));
  V3 root;
  for (int i = 0; i < 3; ++i) {
    const double one_e = 1.0 + es.eigenvalues()(i);
    if (!(one_e > 0.0) && !clamp) return false;
    root(i) = std::sqrt(std::max(one_e, 1e-300));
  }
  Dm = es.eigenvectors() * root.asDiagonal() * es.eigenvectors().transpose() - M3::Identity();
  bv = (M3::Identity() + Dm).ldlt().solve(V3(t.head<3>()));
  return true;
}

// The forward derivative d(c, E)/d(b, D) at (b, D): dc = (I+D) db + dD b,
// dE = dD (I+D) + (I+D) dD.
MatrixXd forward_derivative(const M3& D, const V3& b) {
  const M3 Wm = M3::Identity() + D;
  MatrixXd G(9, 9);
  for (int col = 0; col < 9; ++col) {
    V3 db = V3::Zero();
    M3 dD = M3::Zero();
    if (col < 3) {
      db(col) = 1.0;
    } else {
      const int e = col - 3;
      dD(kSymI[e], kSymJ[e]) = 1.0;
      dD(kSymJ[e], kSymI[e]) = 1.0;
    }
    const V3 dc = Wm * db + dD * b;
    const M3 dE = dD * Wm + Wm * dD;
    for (int i = 0; i < 3; ++i) G(i, col) = dc(i);
    for (int e = 0; e < 6; ++e) G(3 + e, col) = dE(kSymI[e], kSymJ[e]);
  }
  return G;
}

// The covariance of the hard-iron offset x = (I+E)^-1 c = (I+D)^-1 b and of
// W = I + D: dx = (I+E)^-1 (dc - dE x); W takes the D rows of J. Sets r.offset.
MatrixXd offset_covariance(const VectorXd& theta, const MatrixXd& J, const MatrixXd& P, TwostepResult& r) {
  const M3 IE = M3::Identity() + sym(theta.data() + 3);
  const M3 IEinv = IE.inverse();
  const V3 x = IEinv * V3(theta.head<3>());
  r.offset = to_array(x);
  MatrixXd K(9, 9);
  for (int col = 0; col < 9; ++col) {
    V3 dc = V3::Zero();
    M3 dE = M3::Zero();
    if (col < 3) {
      dc(col) = 1.0;
    } else {
      const int e = col - 3;
      dE(kSymI[e], kSymJ[e]) = 1.0;
      dE(kSymJ[e], kSymI[e]) = 1.0;
    }
    const V3 dx = IEinv * (dc - dE * x);
    for (int i = 0; i < 3; ++i) K(i, col) = dx(i);
  }
  K.bottomRows(6) = J.bottomRows(6);
  const MatrixXd C = K * P * K.transpose();
  return C;
}

}  // namespace

TwostepResult twostep(std::span<const Vec3> Bin, std::span<const double> Hin, const TwostepOptions& opt) {
  const Model model(opt.full);
  const auto p = static_cast<std::size_t>(model.params());
  const std::size_t n = Bin.size();
  check_input(Bin, Hin, opt, p);

  // Work in units of the mean field norm: c and E then have the same scale.
  double kappa = 0.0;
  for (double h : Hin) kappa += h;
  kappa /= static_cast<double>(Hin.size());
  std::vector<V3> B(n);
  std::vector<double> H2(n);
  Problem pr{model, B, H2, std::vector<double>(n)};
  for (std::size_t k = 0; k < n; ++k) {
    B[k] = to_eigen(Bin[k]) / kappa;
    const double h = (Hin.size() == 1 ? Hin[0] : Hin[k]) / kappa;
    H2[k] = h * h;
    pr.z[k] = B[k].squaredNorm() - H2[k];
  }

  const std::size_t dof = n - p;
  double s2 = 0.0;
  const Solution sol = solve_for_noise(pr, H2, dof, kappa, opt, s2);
  const bool estimate = opt.noise == 0.0;

  TwostepResult r;
  r.full = opt.full;
  r.noise = std::sqrt(s2) * kappa;
  r.noise_estimated = estimate;
  r.chi2 = sol.chi2;
  r.dof = dof;
  if (!estimate) {
    const boost::math::chi_squared_distribution<double> chi(static_cast<double>(dof));
    r.p_value = boost::math::cdf(boost::math::complement(chi, std::max(sol.chi2, 0.0)));
  }
  r.iterations = sol.iterations;
  r.eta = sol.eta;
  r.converged = sol.converged;
  r.centred_condition = sol.centred_condition;
  r.centred_degenerate = sol.centred_degenerate;

  const auto ip = static_cast<Index>(p);
  // Scale back: the c (or b) entries carry kappa, the E entries none.
  VectorXd T = VectorXd::Ones(ip);
  T.head<3>().setConstant(kappa);
  const VectorXd theta = T.asDiagonal() * sol.theta;
  const VectorXd centred = T.asDiagonal() * sol.centred;
  const MatrixXd P = T.asDiagonal() * sol.P * T.asDiagonal();
  r.theta.assign(theta.data(), theta.data() + ip);
  r.centred_theta.assign(centred.data(), centred.data() + ip);
  r.theta_cov = to_matrix(P);

  if (!opt.full) {
    r.b = to_array(V3(theta.head<3>()));
    r.centred_b = to_array(V3(centred.head<3>()));
    r.offset = r.b;
    r.cov = r.theta_cov;
    r.offset_cov = r.theta_cov;
    return r;
  }

  M3 D;
  V3 b;
  if (!recover(theta, false, D, b))
    throw CalibrationError(
        CalibrationReason::degenerate,
        "TWOSTEP (full): I + E is not positive definite (the points do not fit a linear calibration; "
        "check the field norms and the coverage)");
  M3 Dc;
  V3 bc;
  recover(centred, true, Dc, bc);
  r.D = to_array(D);
  r.b = to_array(b);
  r.centred_D = to_array(Dc);
  r.centred_b = to_array(bc);

  // Covariance of (b, D): J P J^T, J the inverse of the forward derivative
  // d(c, E)/d(b, D): dc = (I+D) db + dD b, dE = dD (I+D) + (I+D) dD.
  const MatrixXd G = forward_derivative(D, b);
  const MatrixXd J = G.fullPivLu().inverse();
  MatrixXd C = J * P * J.transpose();
  r.cov = to_matrix(0.5 * (C + C.transpose()));

  C = offset_covariance(theta, J, P, r);
  r.offset_cov = to_matrix(0.5 * (C + C.transpose()));
  return r;
}

}  // namespace cubecal::mag
