// Multi-position gyroscope calibration (docs/formulas/multiposition.md §4, §6.2): the
// calibrated gyro integrated between consecutive static intervals must turn
// one gravity direction into the next; 9 (or 12) parameters, with the
// accelerometer's and the initial bias's errors propagated.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/calib/multiposition.hpp"
#include "cubecal/error.hpp"
#include "cubecal/stats/sampling.hpp"
#include "../detail/levenberg_marquardt.hpp"
#include "../detail/eigen_matrix.hpp"
#include "detail/multiposition_common.hpp"
#include "detail/quaternion_rk4.hpp"

namespace cubecal::multipos {

namespace {

using calib::detail::Quat;
using calib::detail::rk4_step;
using calib::detail::rotate_inverse;
using cubecal::detail::levenberg_marquardt;
using cubecal::detail::LmOutcome;
using cubecal::detail::with_numeric_jacobian;
using detail::acc_model;
using detail::acc_params;
using detail::ei;
using detail::fail;
using detail::fmt_g;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// The motion from static interval k to k+1 (gravity directions u[k], u[k+1]).
struct GyroPair {
  std::vector<Vec3> raw;   // gyro samples minus the initial-period bias
  std::vector<double> dt;  // raw.size() - 1 steps
};

TriadCalibration gyro_model(const VectorXd& p, const Vec3& init_bias) {
  TriadCalibration m;
  m.mis_yz = p(0);
  m.mis_zy = p(1);
  m.mis_zx = p(2);
  m.mis_xz = p(3);
  m.mis_xy = p(4);
  m.mis_yx = p(5);
  m.scale = {p(6), p(7), p(8)};
  m.bias = init_bias;
  if (p.size() == 12)
    for (int c = 0; c < 3; ++c) m.bias[c] += p(9 + c);
  return m;
}

// Residuals R^-1 u_{k-1} - u_k for all pairs at parameters p, the raw gyro
// shifted by `shift` (a bias change; zero but for error propagation).
bool gyro_residuals(const std::vector<GyroPair>& pairs, const std::vector<Eigen::Vector3d>& u, const VectorXd& p,
                    VectorXd& r, const Vec3& shift = {}) {
  TriadCalibration m = gyro_model(p, shift);
  const Mat3 M = m.matrix();
  const Vec3 db = m.bias;
  auto cal = [&](const Vec3& x) {
    const double a = x[0] - db[0], b = x[1] - db[1], c = x[2] - db[2];
    return Vec3{M[0][0] * a + M[0][1] * b + M[0][2] * c, M[1][0] * a + M[1][1] * b + M[1][2] * c,
                M[2][0] * a + M[2][1] * b + M[2][2] * c};
  };
  r.resize(ei(3 * pairs.size()));
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const GyroPair& g = pairs[k];
    Quat q;
    Vec3 w0 = cal(g.raw[0]);
    for (std::size_t j = 0; j + 1 < g.raw.size(); ++j) {
      const Vec3 w1 = cal(g.raw[j + 1]);
      q = rk4_step(q, w0, w1, g.dt[j]);
      w0 = w1;
    }
    r.segment<3>(ei(3 * k)) = rotate_inverse(q, u[k]) - u[k + 1];
  }
  return r.allFinite();
}

double angle_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi;
}

// The mean and the standard error of the mean of each axis over the first
// res.init_samples gyroscope samples: the initial-period bias.
void set_init_bias(const TriadSeries& gyro, GyroResult& res) {
  for (int c = 0; c < 3; ++c) {
    double mean = 0.0;
    for (std::size_t k = 0; k < res.init_samples; ++k) mean += gyro.x[k][c];
    mean /= static_cast<double>(res.init_samples);
    double ss = 0.0;
    for (std::size_t k = 0; k < res.init_samples; ++k) ss += (gyro.x[k][c] - mean) * (gyro.x[k][c] - mean);
    res.init_bias[c] = mean;
    res.init_bias_sigma[c] =
        std::sqrt(ss / static_cast<double>(res.init_samples - 1) / static_cast<double>(res.init_samples));
  }
}

// The raw accelerometer mean of each static interval.
std::vector<Vec3> raw_interval_means(const TriadSeries& acc, const std::vector<IndexRange>& intervals) {
  std::vector<Vec3> raw_means;
  for (const IndexRange& i : intervals) {
    Vec3 m{};
    for (std::size_t k = i.begin; k < i.end; ++k)
      for (int c = 0; c < 3; ++c) m[c] += acc.x[k][c];
    for (double& v : m) v /= static_cast<double>(i.size());
    raw_means.push_back(m);
  }
  return raw_means;
}

// Gravity directions from the calibrated accelerometer: the calibration is
// affine, so the direction of the calibrated mean is that of the raw mean.
std::vector<Eigen::Vector3d> directions(const std::vector<Vec3>& raw_means, const TriadCalibration& am) {
  std::vector<Eigen::Vector3d> u;
  for (const Vec3& m : raw_means) {
    const Vec3 a = am.apply(m);
    u.push_back(Eigen::Vector3d(a[0], a[1], a[2]).normalized());
  }
  return u;
}

// The gyroscope samples (less the initial bias) of each motion between
// consecutive static intervals. A gap in the gyroscope record during a
// motion loses part of the rotation: the integral across it would be a guess.
std::vector<GyroPair> motion_pairs(const TriadSeries& gyro, const AccResult& ar, const std::vector<double>& ta,
                                   const std::vector<double>& tg, const GyroResult& res) {
  using R = CalibrationReason;
  const double gap_s = gyro.t.empty() ? 0.0 : kGapPeriods * check_sampling(tg).period_s;
  std::vector<GyroPair> pairs;
  for (std::size_t k = 1; k < ar.intervals.size(); ++k) {
    const double ts0 = ta[ar.intervals[k - 1].end];
    const double ts1 = ta[ar.intervals[k].begin];
    const auto j0 = static_cast<std::size_t>(std::lower_bound(tg.begin(), tg.end(), ts0) - tg.begin());
    const auto j1e = static_cast<std::size_t>(std::lower_bound(tg.begin(), tg.end(), ts1) - tg.begin());
    if (j1e == tg.size() || j0 + 1 >= j1e)
      fail(R::bad_data, "the gyroscope record does not cover the motion between static intervals " + std::to_string(k) +
                            " and " + std::to_string(k + 1) + " (" + fmt_g(ts0) + " s to " + fmt_g(ts1) + " s)");
    GyroPair p;
    for (std::size_t j = j0; j < j1e; ++j) {
      p.raw.push_back(
          {gyro.x[j][0] - res.init_bias[0], gyro.x[j][1] - res.init_bias[1], gyro.x[j][2] - res.init_bias[2]});
      if (j > j0) p.dt.push_back(tg[j] - tg[j - 1]);
      if (j > j0 && gap_s > 0.0 && p.dt.back() >= gap_s)
        fail(R::bad_data, "gap of " + fmt_g(p.dt.back()) + " s in the gyroscope record at sample " + std::to_string(j) +
                              " (t = " + fmt_g(tg[j - 1]) + " s) during the motion between static intervals " +
                              std::to_string(k) + " and " + std::to_string(k + 1) +
                              ": the rotation cannot be integrated across missing samples");
    }
    pairs.push_back(std::move(p));
  }
  return pairs;
}

// d r / d (accelerometer parameters) at the fit, and the accelerometer
// covariance: their part of the gyroscope covariance is S D Sa D^T S^T.
void add_accelerometer_errors(const std::vector<GyroPair>& pairs, const std::vector<Vec3>& raw_means,
                              const AccResult& ar, const Options& opt, const LmOutcome& lm, const MatrixXd& S,
                              MatrixXd& cov) {
  MatrixXd Sa(9, 9), D(lm.r.size(), 9);
  const VectorXd pa = acc_params(ar.model);
  for (Eigen::Index j = 0; j < 9; ++j) {
    for (Eigen::Index i = 0; i < 9; ++i)
      Sa(i, j) = ar.covariance(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
    const double typ = j < 3 ? 1e-2 : j < 6 ? std::abs(pa(j)) : 1e-2 * opt.g / std::abs(pa(3 + (j - 6)));
    const double h = 1e-6 * std::max(std::abs(pa(j)), typ);
    VectorXd pp = pa, pm = pa;
    pp(j) += h;
    pm(j) -= h;
    VectorXd rp, rm;
    gyro_residuals(pairs, directions(raw_means, acc_model(pp)), lm.p, rp);
    gyro_residuals(pairs, directions(raw_means, acc_model(pm)), lm.p, rm);
    D.col(j) = (rp - rm) / (pp(j) - pm(j));
  }
  if (Sa.allFinite() && D.allFinite()) cov += (S * D) * Sa * (S * D).transpose();
}

// The same for the initial-period bias, when the fit does not refine it.
void add_init_bias_errors(const std::vector<GyroPair>& pairs, const std::vector<Eigen::Vector3d>& u,
                          const GyroResult& res, double bias_typical, const LmOutcome& lm, const MatrixXd& S,
                          MatrixXd& cov) {
  MatrixXd D(lm.r.size(), 3);
  Eigen::Matrix3d Sb = Eigen::Matrix3d::Zero();
  for (int c = 0; c < 3; ++c) {
    Sb(c, c) = res.init_bias_sigma[c] * res.init_bias_sigma[c];
    const double h = 1e-3 * bias_typical;
    Vec3 sp{}, sm{};
    sp[c] = h;
    sm[c] = -h;
    VectorXd rp, rm;
    gyro_residuals(pairs, u, lm.p, rp, sp);
    gyro_residuals(pairs, u, lm.p, rm, sm);
    D.col(c) = (rp - rm) / (2.0 * h);
  }
  if (D.allFinite()) cov += (S * D) * Sb * (S * D).transpose();
}

// The rms (and the largest) angle between the predicted and the measured
// gravity direction over the pairs, degrees.
void angles(const std::vector<GyroPair>& pairs, const std::vector<Eigen::Vector3d>& u, const VectorXd& r, double& rms,
            double* mx) {
  double s = 0.0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Eigen::Vector3d a = r.segment<3>(ei(3 * k)) + u[k + 1];
    const double ang = angle_between_deg(a, u[k + 1]);
    s += ang * ang;
    if (mx) *mx = std::max(*mx, ang);
  }
  rms = std::sqrt(s / static_cast<double>(pairs.size()));
}

}  // namespace

GyroResult calibrate_gyroscope(const TriadSeries& acc, const AccResult& ar, const TriadSeries& gyro,
                               const Options& opt) {
  using R = CalibrationReason;
  detail::check_options(opt);
  const std::vector<double> ta = detail::sample_times(acc, "accelerometer");
  const std::vector<double> tg = detail::sample_times(gyro, "gyroscope");
  if (ar.intervals.size() < 2) fail(R::too_few_intervals, "the gyroscope fit needs at least 2 static intervals");
  for (const IndexRange& i : ar.intervals)
    if (i.end >= acc.x.size() || i.begin >= i.end)
      fail(R::too_few_intervals, "static intervals do not match the accelerometer record");

  GyroResult res;
  res.init_samples = detail::init_count(tg, opt.init_static_s);
  if (res.init_samples < 2) fail(R::initial_static, "the initial static period holds fewer than 2 gyroscope samples");
  set_init_bias(gyro, res);

  const std::vector<Vec3> raw_means = raw_interval_means(acc, ar.intervals);
  const std::vector<Eigen::Vector3d> u = directions(raw_means, ar.model);

  const std::vector<GyroPair> pairs = motion_pairs(gyro, ar, ta, tg, res);
  res.pairs = pairs.size();

  const Eigen::Index np = opt.refine_gyro_bias ? 12 : 9;
  VectorXd p0 = VectorXd::Zero(np);
  p0.segment<3>(6).setConstant(opt.gyro_scale_guess);
  const double bias_typical =
      std::max({res.init_bias_sigma[0], res.init_bias_sigma[1], res.init_bias_sigma[2], 1e-3 / opt.gyro_scale_guess});
  VectorXd typical(np);
  typical.setConstant(1e-2);
  typical.segment<3>(6).setConstant(opt.gyro_scale_guess);
  if (np == 12) typical.segment<3>(9).setConstant(bias_typical);
  auto f = [&pairs, &u](const VectorXd& p, VectorXd& r) { return gyro_residuals(pairs, u, p, r); };
  const LmOutcome lm = levenberg_marquardt(with_numeric_jacobian(f, typical), p0, opt.max_iterations);
  if (!lm.initial_finite)
    fail(R::scale_guess, "the initial guess gives non-finite residuals (check the bias and scale guesses)");
  if (!lm.determined || !lm.p.allFinite())
    fail(R::degenerate,
         "the motions between static poses do not determine the gyroscope parameters (rotate about all three "
         "axes between poses)");
  if (lm.p.segment<3>(6).minCoeff() <= 0.0)
    fail(R::scale_guess,
         "the gyroscope fit converged to a non-positive scale: check the gyroscope scale guess (rad/s per count)");

  res.model = gyro_model(lm.p, res.init_bias);
  res.initial = gyro_model(p0, res.init_bias);
  res.names = {"mis_yz", "mis_zy", "mis_zx", "mis_xz", "mis_xy", "mis_yx", "s_x", "s_y", "s_z"};
  if (np == 12) res.names.insert(res.names.end(), {"db_x", "db_y", "db_z"});
  res.values.assign(lm.p.data(), lm.p.data() + lm.p.size());
  const double m = static_cast<double>(lm.r.size());
  res.sigma0 = m > static_cast<double>(np) ? std::sqrt(lm.cost / (m - static_cast<double>(np)))
                                           : std::numeric_limits<double>::quiet_NaN();
  const MatrixXd cov_fit = res.sigma0 * res.sigma0 * lm.inv_jtj;

  // Errors the fit takes as known: the accelerometer calibration (through the
  // u_k) and, unless refined, the initial-period bias. p_hat moves by
  // G dx = -(J^T J)^-1 J^T (dr/dx) dx; their covariance adds G S_x G^T.
  const MatrixXd S = -lm.inv_jtj * lm.J.transpose();
  MatrixXd cov = cov_fit;
  if (ar.covariance.rows() == 9 && ar.values.size() == 9)
    add_accelerometer_errors(pairs, raw_means, ar, opt, lm, S, cov);
  if (np == 9) add_init_bias_errors(pairs, u, res, bias_typical, lm, S, cov);
  res.covariance = cubecal::detail::to_matrix(cov);
  for (Eigen::Index i = 0; i < np; ++i) {
    res.sigma.push_back(std::sqrt(cov(i, i)));
    res.sigma_fit.push_back(std::sqrt(cov_fit(i, i)));
  }
  res.bias_sigma = res.init_bias_sigma;
  if (np == 12)
    for (int c = 0; c < 3; ++c) res.bias_sigma[c] = std::sqrt(cov(9 + c, 9 + c));

  VectorXd r0;
  gyro_residuals(pairs, u, p0, r0);
  res.before = detail::residual_stats(r0);
  res.after = detail::residual_stats(lm.r);
  angles(pairs, u, r0, res.angle_rms_before_deg, nullptr);
  angles(pairs, u, lm.r, res.angle_rms_after_deg, &res.angle_max_after_deg);
  res.iterations = lm.iterations;
  res.converged = lm.converged;
  return res;
}

}  // namespace cubecal::multipos
