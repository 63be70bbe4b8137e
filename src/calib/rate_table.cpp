#include "cubecal/calib/rate_table.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "../detail/eigen_matrix.hpp"
#include "detail/eigen_vec3.hpp"

namespace cubecal {

namespace {

using Eigen::Index;
using Mat = Eigen::MatrixXd;
using calib::detail::to_array;
using calib::detail::to_eigen;
using cubecal::detail::to_matrix;

const char* const kNeed = "need rates about at least 3 independent axes plus one more (4 affinely independent)";

// Rank of [w 1] with the rate columns scaled to the largest rate, so that
// the test does not depend on the unit.
Index affine_rank(const Mat& X) {
  Mat Xs = X;
  const double scale = X.leftCols(3).cwiseAbs().maxCoeff();
  if (scale > 0.0) Xs.leftCols(3) /= scale;
  const Eigen::JacobiSVD<Mat> svd(Xs);
  const auto& sv = svd.singularValues();
  Index rank = 0;
  for (Index i = 0; i < sv.size(); ++i)
    if (sv(i) > 1e-9 * sv(0)) ++rank;
  return rank;
}

std::string degenerate_message(std::size_t plateaus, Index rank) {
  static const char* const kShape[] = {"all at the same rate", "on one line (e.g. all about one axis)",
                                       "in one plane (e.g. about two axes only)"};
  const Index dim = std::max<Index>(rank - 1, 0);
  return "the " + std::to_string(plateaus) + " plateau rates are degenerate: they lie " +
         kShape[std::min<Index>(dim, 2)] + ", the rank of [w 1] is " + std::to_string(rank) + "; " + kNeed;
}

ResidualStats stats(const Mat& E) {
  ResidualStats s;
  s.max_abs = E.cwiseAbs().maxCoeff();
  s.rms = std::sqrt(E.squaredNorm() / static_cast<double>(E.size()));
  return s;
}

// Enough plateaus, each with a reference rate and finite means.
void check_plateaus(std::span<const Plateau> plateaus) {
  const std::size_t P = plateaus.size();
  if (P < 4)
    throw CalibrationError(CalibrationReason::too_few_points,
                           std::to_string(P) + " plateau" + (P == 1 ? " is" : "s are") + " not enough: " + kNeed);
  for (std::size_t j = 0; j < P; ++j) {
    const Plateau& p = plateaus[j];
    if (!p.has_ref)
      throw CalibrationError(CalibrationReason::bad_data,
                             "plateau " + std::to_string(j + 1) + " has no reference rate (label it from a schedule)");
    bool finite = p.n > 0;
    for (int a = 0; a < 3; ++a) finite = finite && std::isfinite(p.mean[a]) && std::isfinite(p.ref[a]);
    if (!finite)
      throw CalibrationError(CalibrationReason::bad_data,
                             "plateau " + std::to_string(j + 1) + " has a non-finite rate or no samples");
  }
}

// Delta method: dA = -A dS A, dbeta = -A dS beta - A db_g.
Eigen::Matrix<double, 12, 12> inverse_jacobian(const Eigen::Matrix3d& A, const Eigen::Vector3d& beta) {
  Eigen::Matrix<double, 12, 12> J = Eigen::Matrix<double, 12, 12>::Zero();
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) {
      for (int m = 0; m < 3; ++m) {
        for (int b = 0; b < 3; ++b) J(4 * a + b, 4 * k + m) = -A(a, k) * A(m, b);
        J(4 * a + 3, 4 * k + m) = -A(a, k) * beta(m);
      }
      J(4 * a + 3, 4 * k + 3) = -A(a, k);
    }
  return J;
}

// Datasheet form: scale-factor errors S_ii - 1 and misalignment angles
// atan(S_ij / S_ii), with their sigmas from F.
void set_datasheet_form(const Eigen::Matrix3d& S, const Eigen::Matrix<double, 12, 12>& F, RateTableCalibration& c) {
  for (int i = 0; i < 3; ++i) {
    c.scale_factor_error[i] = S(i, i) - 1.0;
    c.scale_factor_error_sigma[i] = c.S_sigma[i][i];
    for (int j = 0; j < 3; ++j) {
      if (i == j) continue;
      c.misalignment[i][j] = std::atan(S(i, j) / S(i, i));
      // Gradient of atan(S_ij / S_ii) with respect to S_ij and S_ii.
      const double r2 = S(i, i) * S(i, i) + S(i, j) * S(i, j);
      const double gij = S(i, i) / r2, gii = -S(i, j) / r2;
      const int ij = 4 * i + j, ii = 4 * i + i;
      c.misalignment_sigma[i][j] =
          std::sqrt(std::max(0.0, gij * gij * F(ij, ij) + gii * gii * F(ii, ii) + 2.0 * gij * gii * F(ij, ii)));
    }
  }
}

// Eq. (12) over all plateau samples: within-plateau scatter mapped by A,
// plus the spread of the plateau residuals (law of total covariance).
Eigen::Matrix3d error_covariance(std::span<const Plateau> plateaus, const Mat& after, const Eigen::Matrix3d& A) {
  const Index p = static_cast<Index>(plateaus.size());
  double total = 0.0;
  Eigen::Vector3d mean_error = Eigen::Vector3d::Zero();
  for (Index j = 0; j < p; ++j) {
    const double n = static_cast<double>(plateaus[static_cast<std::size_t>(j)].n);
    total += n;
    mean_error += n * after.row(j).transpose();
  }
  mean_error /= total;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (Index j = 0; j < p; ++j) {
    const Plateau& pl = plateaus[static_cast<std::size_t>(j)];
    const double n = static_cast<double>(pl.n);
    Eigen::Matrix3d within;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) within(a, b) = pl.cov[a][b];
    const Eigen::Vector3d d = after.row(j).transpose() - mean_error;
    C += (n - 1.0) * A * within * A.transpose() + n * d * d.transpose();
  }
  if (total > 1.0) C /= total - 1.0;
  return C;
}

}  // namespace

std::array<double, 3> earth_rate_along(const std::array<double, 3>& axis, double unit_per_rad_s) {
  return {kEarthRateRadPerS * unit_per_rad_s * axis[0], kEarthRateRadPerS * unit_per_rad_s * axis[1],
          kEarthRateRadPerS * unit_per_rad_s * axis[2]};
}

RateTableCalibration calibrate_rate_table(std::span<const Plateau> plateaus, const RateTableOptions& opt) {
  const std::size_t P = plateaus.size();
  check_plateaus(plateaus);

  // Y = X Theta, row j: [w_j^T 1] -> w_g,j^T.
  const Index p = static_cast<Index>(P);
  Mat X(p, 4), Y(p, 3);
  for (Index j = 0; j < p; ++j) {
    const Plateau& pl = plateaus[static_cast<std::size_t>(j)];
    for (int a = 0; a < 3; ++a) {
      X(j, a) = pl.ref[a] + opt.earth_rate[a];
      Y(j, a) = pl.mean[a];
    }
    X(j, 3) = 1.0;
  }
  if (const Index rank = affine_rank(X); rank < 4)
    throw CalibrationError(CalibrationReason::degenerate, degenerate_message(P, rank));

  const Eigen::HouseholderQR<Mat> qr(X);
  const Mat theta = qr.solve(Y);  // 4x3: [S^T; b_g^T]
  // (X^T X)^-1 = R^-1 R^-T from the triangular factor: no normal equations.
  const Eigen::Matrix4d Rf = qr.matrixQR().topRows(4).triangularView<Eigen::Upper>();
  const Eigen::Matrix4d Rinv = Rf.triangularView<Eigen::Upper>().solve(Eigen::Matrix4d::Identity());
  const Eigen::Matrix4d G = Rinv * Rinv.transpose();

  RateTableCalibration c;
  c.plateaus = P;
  c.dof = P - 4;
  const Mat E = Y - X * theta;
  Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
  if (c.dof > 0) {
    R = E.transpose() * E / static_cast<double>(c.dof);
  } else {
    // No residual freedom: the white-noise error of each mean, averaged.
    c.noise_from_residuals = false;
    for (const Plateau& pl : plateaus)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) R(a, b) += pl.cov[a][b] / static_cast<double>(pl.n) / static_cast<double>(P);
  }
  c.noise_cov = to_array(R);

  Eigen::Matrix3d S;
  Eigen::Vector3d bg;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) S(k, m) = theta(m, k);
    bg(k) = theta(3, k);
  }
  // Cov(vec Theta) = R (x) (X^T X)^-1; vec Theta stacks Theta's columns,
  // i.e. per output axis k its S row and bias: index 4k + m.
  Eigen::Matrix<double, 12, 12> F;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) F.block<4, 4>(4 * k, 4 * l) = R(k, l) * G;

  const Eigen::FullPivLU<Eigen::Matrix3d> lu(S);
  if (!lu.isInvertible())
    throw CalibrationError(CalibrationReason::degenerate,
                           "the fitted scale-factor matrix S is singular: the gyro does not sense every axis");
  const Eigen::Matrix3d A = lu.inverse();
  const Eigen::Vector3d beta = -A * bg;

  const Eigen::Matrix<double, 12, 12> J = inverse_jacobian(A, beta);
  const Eigen::Matrix<double, 12, 12> V = J * F * J.transpose();

  c.S = to_array(S);
  c.A = to_array(A);
  c.forward_cov = to_matrix(F);
  c.inverse_cov = to_matrix(V);
  for (int k = 0; k < 3; ++k) {
    c.bias[k] = bg(k);
    c.beta[k] = beta(k);
    c.bias_sigma[k] = std::sqrt(F(4 * k + 3, 4 * k + 3));
    c.beta_sigma[k] = std::sqrt(V(4 * k + 3, 4 * k + 3));
    for (int m = 0; m < 3; ++m) {
      c.S_sigma[k][m] = std::sqrt(F(4 * k + m, 4 * k + m));
      c.A_sigma[k][m] = std::sqrt(V(4 * k + m, 4 * k + m));
    }
  }

  set_datasheet_form(S, F, c);

  // Residuals of the plateau means, before and after calibration.
  const Mat W = X.leftCols(3);
  c.residual_before = stats(Y - W);
  const Mat after = (Y * A.transpose()).rowwise() + beta.transpose() - W;
  c.residual_after = stats(after);
  c.residuals_after.resize(P);
  for (Index j = 0; j < p; ++j)
    for (int a = 0; a < 3; ++a) c.residuals_after[static_cast<std::size_t>(j)][a] = after(j, a);

  const Eigen::Matrix3d C = error_covariance(plateaus, after, A);
  c.error_covariance = to_array(C);
  return c;
}

}  // namespace cubecal
