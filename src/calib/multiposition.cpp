// Multi-position accelerometer and gyroscope calibration without a turntable
// (Tedaldi, Pretto & Menegatti 2014; imu_tk): static detection, the
// 9-parameter accelerometer fit on g - |T K (a - B)|, and the gyroscope fit by
// integration between poses. A small dense Levenberg-Marquardt (Jacobi-scaled,
// Nielsen's damping update) stands in for Ceres.
#include "cubecal/calib/multiposition.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cubecal::multipos {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string fmt_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument(what); }

Eigen::Index ei(std::size_t i) { return static_cast<Eigen::Index>(i); }

// ---------------------------------------------------------------------------
// Levenberg-Marquardt on sum r^2.

// Fills r (and J when given) at p; returns false when the residuals are not
// finite there (the step is then rejected).
using EvalFn = std::function<bool(const VectorXd& p, VectorXd& r, MatrixXd* J)>;

struct LmOutcome {
  VectorXd p;
  double cost0 = 0.0;
  double cost = 0.0;
  std::size_t iterations = 0;
  bool converged = false;
  bool determined = false;  // J^T J well conditioned at the solution
  MatrixXd inv_jtj;         // (J^T J)^-1 at the solution (when determined)
  MatrixXd J;               // Jacobian at the solution
  VectorXd r;               // residuals at the solution
};

// Column norms of J (1 for a zero column), the Jacobi scaling.
VectorXd column_scale(const MatrixXd& J) {
  VectorXd d(J.cols());
  for (Eigen::Index j = 0; j < J.cols(); ++j) {
    const double n = J.col(j).norm();
    d(j) = n > 0.0 && std::isfinite(n) ? n : 1.0;
  }
  return d;
}

LmOutcome levenberg_marquardt(const EvalFn& eval, VectorXd p, std::size_t max_iterations) {
  LmOutcome out;
  VectorXd r;
  MatrixXd J;
  if (!eval(p, r, &J)) fail("the initial guess gives non-finite residuals (check the bias and scale guesses)");
  double cost = r.squaredNorm();
  out.cost0 = cost;
  double lambda = 1e-3;
  double nu = 2.0;
  VectorXd r_new;
  for (std::size_t it = 0; it < max_iterations; ++it) {
    out.iterations = it + 1;
    if (cost == 0.0) {
      out.converged = true;
      break;
    }
    const VectorXd d = column_scale(J);
    const MatrixXd Js = J * d.cwiseInverse().asDiagonal();
    const MatrixXd A = Js.transpose() * Js;
    const VectorXd grad = Js.transpose() * r;
    if (grad.lpNorm<Eigen::Infinity>() <= 1e-15 * std::sqrt(cost)) {
      out.converged = true;
      break;
    }
    bool accepted = false;
    bool stop = false;
    while (!accepted) {
      MatrixXd Ad = A;
      Ad.diagonal().array() += lambda;
      const VectorXd z = Ad.ldlt().solve(-grad);
      const VectorXd step = z.cwiseQuotient(d);
      const VectorXd p_new = p + step;
      const double predicted = -(2.0 * z.dot(grad) + z.dot(A * z));
      if (z.allFinite() && !(predicted > 1e-15 * cost)) {
        // No descent left at this precision: a minimum.
        out.converged = true;
        stop = true;
        break;
      }
      double cost_new = kInf;
      if (z.allFinite() && eval(p_new, r_new, nullptr)) cost_new = r_new.squaredNorm();
      const double rho = (cost - cost_new) / predicted;
      if (std::isfinite(cost_new) && rho > 0.0) {
        const double reduction = cost - cost_new;
        p = p_new;
        cost = cost_new;
        const double t = 2.0 * rho - 1.0;
        lambda *= std::max(1.0 / 3.0, 1.0 - t * t * t);
        nu = 2.0;
        accepted = true;
        if (!eval(p, r, &J)) fail("non-finite Jacobian during the fit");
        if (reduction <= 1e-12 * (cost + reduction)) {
          out.converged = true;
          stop = true;
        }
      } else {
        lambda *= nu;
        nu *= 2.0;
        if (lambda > 1e16) {
          out.converged = true;  // no step reduces the cost: at the minimum to precision
          stop = true;
          break;
        }
      }
    }
    if (stop) break;
  }
  out.p = p;
  out.cost = cost;
  out.r = r;
  out.J = J;
  // (J^T J)^-1 through the scaled normal matrix.
  const VectorXd d = column_scale(J);
  const MatrixXd Js = J * d.cwiseInverse().asDiagonal();
  const MatrixXd A = Js.transpose() * Js;
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(A);
  const double emax = es.eigenvalues().maxCoeff();
  const double emin = es.eigenvalues().minCoeff();
  out.determined = es.info() == Eigen::Success && emax > 0.0 && emin > 1e-12 * emax;
  if (out.determined) {
    const MatrixXd Ainv =
        es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    out.inv_jtj = d.cwiseInverse().asDiagonal() * Ainv * d.cwiseInverse().asDiagonal();
  }
  return out;
}

// Central-difference Jacobian around a residual function.
EvalFn with_numeric_jacobian(std::function<bool(const VectorXd&, VectorXd&)> f, VectorXd typical) {
  return [f = std::move(f), typical = std::move(typical)](const VectorXd& p, VectorXd& r, MatrixXd* J) {
    if (!f(p, r)) return false;
    if (!J) return true;
    J->resize(r.size(), p.size());
    VectorXd rp, rm;
    for (Eigen::Index j = 0; j < p.size(); ++j) {
      const double h = 1e-6 * std::max(std::abs(p(j)), typical(j));
      VectorXd pp = p, pm = p;
      pp(j) += h;
      pm(j) -= h;
      if (!f(pp, rp) || !f(pm, rm)) return false;
      J->col(j) = (rp - rm) / (pp(j) - pm(j));
    }
    return J->allFinite();
  };
}

// ---------------------------------------------------------------------------
// Data checks.

std::vector<double> sample_times(const TriadSeries& s, const char* what) {
  if (s.x.empty()) fail(std::string(what) + ": no samples");
  for (std::size_t i = 0; i < s.x.size(); ++i)
    for (double v : s.x[i])
      if (!std::isfinite(v)) fail(std::string(what) + ": non-finite value at sample " + std::to_string(i));
  std::vector<double> t(s.x.size());
  if (s.t.empty()) {
    if (!(s.rate_hz > 0.0) || !std::isfinite(s.rate_hz))
      fail(std::string(what) + ": give time stamps or a positive sampling rate");
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) / s.rate_hz;
    return t;
  }
  if (s.t.size() != s.x.size())
    fail(std::string(what) + ": " + std::to_string(s.t.size()) + " time stamps for " + std::to_string(s.x.size()) +
         " samples");
  for (std::size_t i = 0; i < t.size(); ++i) {
    t[i] = s.t[i];
    if (!std::isfinite(t[i])) fail(std::string(what) + ": non-finite time stamp at sample " + std::to_string(i));
    if (i > 0 && !(t[i] > t[i - 1]))
      fail(std::string(what) + ": time stamps not increasing at sample " + std::to_string(i) + " (" + fmt_g(t[i - 1]) +
           " s then " + fmt_g(t[i]) + " s)");
  }
  return t;
}

// Samples with t < t_0 + init_static_s.
std::size_t init_count(const std::vector<double>& t, double init_static_s) {
  const double end = t.front() + init_static_s;
  return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), end) - t.begin());
}

void check_options(const Options& o) {
  if (!(o.g > 0.0) || !std::isfinite(o.g)) fail("gravity magnitude g must be positive");
  if (!(o.init_static_s > 0.0) || !std::isfinite(o.init_static_s))
    fail("initial static period must be a positive number of seconds");
  if (o.interval_samples < 1) fail("samples per interval must be at least 1");
  if (o.min_intervals < 2) fail("at least 2 static intervals must be required");
  if (o.th_mult_min < 1 || o.th_mult_max < o.th_mult_min) fail("th_mult range must be 1 <= min <= max");
  if (!(o.acc_scale_guess >= 0.0) || !std::isfinite(o.acc_scale_guess))
    fail("accelerometer scale guess must be positive (or 0 for automatic)");
  if (!(o.gyro_scale_guess > 0.0) || !std::isfinite(o.gyro_scale_guess)) fail("gyroscope scale guess must be positive");
  for (double b : o.acc_bias_guess)
    if (!std::isfinite(b)) fail("accelerometer bias guess must be finite");
  if (o.max_iterations < 1) fail("max_iterations must be at least 1");
}

Residuals residual_stats(const VectorXd& r) {
  Residuals s;
  s.count = static_cast<std::size_t>(r.size());
  s.cost = r.squaredNorm();
  s.rms = s.count ? std::sqrt(s.cost / static_cast<double>(s.count)) : 0.0;
  s.max = r.size() ? r.cwiseAbs().maxCoeff() : 0.0;
  return s;
}

std::vector<std::vector<double>> to_rows(const MatrixXd& m) {
  std::vector<std::vector<double>> rows(static_cast<std::size_t>(m.rows()));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) rows[static_cast<std::size_t>(i)].push_back(m(i, j));
  return rows;
}

// ---------------------------------------------------------------------------
// Accelerometer.

TriadCalibration acc_model(const VectorXd& p) {
  TriadCalibration m;
  m.mis_yz = p(0);
  m.mis_zy = p(1);
  m.mis_zx = p(2);
  m.scale = {p(3), p(4), p(5)};
  m.bias = {p(6), p(7), p(8)};
  return m;
}

VectorXd acc_params(const TriadCalibration& m) {
  VectorXd p(9);
  p << m.mis_yz, m.mis_zy, m.mis_zx, m.scale[0], m.scale[1], m.scale[2], m.bias[0], m.bias[1], m.bias[2];
  return p;
}

// r = g - |T K (a - B)| and its analytic Jacobian.
EvalFn acc_eval(const std::vector<Vec3>& samples, double g) {
  return [&samples, g](const VectorXd& p, VectorXd& r, MatrixXd* J) {
    const Eigen::Index m = ei(samples.size());
    r.resize(m);
    if (J) J->resize(m, 9);
    const double a01 = -p(0), a02 = p(1), a12 = -p(2);  // T entries
    for (Eigen::Index k = 0; k < m; ++k) {
      const Vec3& a = samples[static_cast<std::size_t>(k)];
      const double d0 = a[0] - p(6), d1 = a[1] - p(7), d2 = a[2] - p(8);
      const double v0 = p(3) * d0, v1 = p(4) * d1, v2 = p(5) * d2;
      const double y0 = v0 + a01 * v1 + a02 * v2;
      const double y1 = v1 + a12 * v2;
      const double y2 = v2;
      const double n = std::sqrt(y0 * y0 + y1 * y1 + y2 * y2);
      r(k) = g - n;
      if (!J) continue;
      if (!(n > 0.0)) return false;
      const double e0 = y0 / n, e1 = y1 / n, e2 = y2 / n;  // d|y|/dy
      auto& Jm = *J;
      Jm(k, 0) = e0 * v1;   // dy0/dmis_yz = -v1; dr = -e.dy
      Jm(k, 1) = -e0 * v2;  // dy0/dmis_zy = v2
      Jm(k, 2) = e1 * v2;   // dy1/dmis_zx = -v2
      // dy/ds_i = T[:, i] d_i ; dy/dB_i = -T[:, i] s_i
      const double c0 = e0;                        // e . T[:,0]
      const double c1 = e0 * a01 + e1;             // e . T[:,1]
      const double c2 = e0 * a02 + e1 * a12 + e2;  // e . T[:,2]
      Jm(k, 3) = -c0 * d0;
      Jm(k, 4) = -c1 * d1;
      Jm(k, 5) = -c2 * d2;
      Jm(k, 6) = c0 * p(3);
      Jm(k, 7) = c1 * p(4);
      Jm(k, 8) = c2 * p(5);
    }
    return r.allFinite();
  };
}

std::vector<Vec3> fit_samples(std::span<const Vec3> x, const std::vector<IndexRange>& iv, std::size_t per_interval,
                              bool means) {
  std::vector<Vec3> out;
  for (const IndexRange& i : iv) {
    if (means) {
      Vec3 m{};
      for (std::size_t k = i.begin; k < i.end; ++k)
        for (int c = 0; c < 3; ++c) m[c] += x[k][c];
      for (double& v : m) v /= static_cast<double>(i.size());
      out.push_back(m);
    } else {
      for (std::size_t k = i.begin; k < i.begin + per_interval; ++k) out.push_back(x[k]);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------
// Gyroscope.

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

}  // namespace

// ---------------------------------------------------------------------------

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

std::size_t normalised_window(std::size_t window) {
  if (window < kMinWindow)
    fail("the variance window must be at least " + std::to_string(kMinWindow) + " samples (got " +
         std::to_string(window) + ")");
  return window % 2 == 0 ? window + 1 : window;
}

std::vector<double> variance_norm(std::span<const Vec3> x, std::size_t window) {
  const std::size_t w = normalised_window(window);
  const std::size_t h = w / 2;
  const std::size_t n = x.size();
  std::vector<double> v(n, kInf);
  if (n < w) return v;
  for (std::size_t i = h; i + h < n; ++i) {
    double var2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      double mean = 0.0;
      for (std::size_t k = i - h; k <= i + h; ++k) mean += x[k][c];
      mean /= static_cast<double>(w);
      double ss = 0.0;
      for (std::size_t k = i - h; k <= i + h; ++k) {
        const double d = x[k][c] - mean;
        ss += d * d;
      }
      const double var = ss / static_cast<double>(w - 1);
      var2 += var * var;
    }
    v[i] = std::sqrt(var2);
  }
  return v;
}

double block_variance_norm(std::span<const Vec3> x) {
  if (x.size() < 2) fail("a variance needs at least 2 samples");
  double var2 = 0.0;
  for (std::size_t c = 0; c < 3; ++c) {
    double mean = 0.0;
    for (const Vec3& s : x) mean += s[c];
    mean /= static_cast<double>(x.size());
    double ss = 0.0;
    for (const Vec3& s : x) ss += (s[c] - mean) * (s[c] - mean);
    const double var = ss / static_cast<double>(x.size() - 1);
    var2 += var * var;
  }
  return std::sqrt(var2);
}

std::vector<IndexRange> static_intervals(std::span<const double> v, double threshold) {
  std::vector<IndexRange> out;
  bool in = false;
  IndexRange cur;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const bool still = v[i] < threshold;
    if (!in && still) {
      cur.begin = i;
      in = true;
    } else if (in && !still) {
      cur.end = i;
      out.push_back(cur);
      in = false;
    }
  }
  if (in) {
    cur.end = v.size();
    out.push_back(cur);
  }
  return out;
}

AccResult calibrate_accelerometer(const TriadSeries& acc, const Options& opt) {
  check_options(opt);
  const std::size_t window = normalised_window(opt.window);
  const std::vector<double> t = sample_times(acc, "accelerometer");
  const std::size_t n = acc.x.size();
  AccResult res;
  res.init_samples = init_count(t, opt.init_static_s);
  if (res.init_samples >= n)
    fail("the record (" + fmt_g(t.back() - t.front()) + " s) is not longer than the initial static period (" +
         fmt_g(opt.init_static_s) + " s)");
  if (res.init_samples < window)
    fail("the initial static period holds " + std::to_string(res.init_samples) +
         " samples, fewer than the variance window (" + std::to_string(window) + ")");
  const std::span<const Vec3> init = acc.x.first(res.init_samples);
  res.init_variance_norm = block_variance_norm(init);
  if (!(res.init_variance_norm > 0.0))
    fail(
        "the accelerometer does not vary at all over the initial static period: no noise level to set the "
        "static threshold");

  // Initial guess.
  TriadCalibration init_model;
  init_model.bias = opt.acc_bias_guess;
  double s0 = opt.acc_scale_guess;
  if (s0 == 0.0) {
    double mean_norm = 0.0;
    for (const Vec3& a : init)
      mean_norm += std::hypot(a[0] - init_model.bias[0], a[1] - init_model.bias[1], a[2] - init_model.bias[2]);
    mean_norm /= static_cast<double>(init.size());
    if (!(mean_norm > 0.0)) fail("the initial static period reads the bias guess exactly: give a scale guess");
    s0 = opt.g / mean_norm;
  }
  init_model.scale = {s0, s0, s0};
  res.initial = init_model;
  const VectorXd p0 = acc_params(init_model);

  const std::vector<double> v = variance_norm(acc.x, window);
  std::size_t most = 0;
  double best_cost = kInf;
  LmOutcome best;
  std::vector<Vec3> best_samples;
  bool any_enough = false;
  for (int th = opt.th_mult_min; th <= opt.th_mult_max; ++th) {
    Trial trial;
    trial.th_mult = th;
    trial.threshold = th * res.init_variance_norm;
    std::vector<IndexRange> iv;
    for (const IndexRange& i : static_intervals(v, trial.threshold))
      if (i.size() >= opt.interval_samples) iv.push_back(i);
    trial.intervals = iv.size();
    most = std::max(most, iv.size());
    if (iv.size() >= opt.min_intervals) {
      any_enough = true;
      std::vector<Vec3> samples = fit_samples(acc.x, iv, opt.interval_samples, opt.acc_use_means);
      LmOutcome lm = levenberg_marquardt(acc_eval(samples, opt.g), p0, opt.max_iterations);
      trial.fitted = lm.determined && lm.p.allFinite() && lm.p.segment<3>(3).minCoeff() > 0.0;
      trial.cost = lm.cost;
      if (trial.fitted && lm.cost < best_cost) {
        best_cost = lm.cost;
        best = std::move(lm);
        best_samples = std::move(samples);
        res.th_mult = th;
        res.threshold = trial.threshold;
        res.intervals = std::move(iv);
      }
    }
    res.trials.push_back(trial);
  }
  if (!any_enough) {
    const double hold_s =
        static_cast<double>(window - 1 + opt.interval_samples) * ((t.back() - t.front()) / static_cast<double>(n - 1));
    fail("fewer than " + std::to_string(opt.min_intervals) + " static intervals: at most " + std::to_string(most) +
         " found (intervals of at least " + std::to_string(opt.interval_samples) + " samples, thresholds " +
         std::to_string(opt.th_mult_min) + ".." + std::to_string(opt.th_mult_max) + " x the variance of the initial " +
         fmt_g(opt.init_static_s) + " s, window " + std::to_string(window) + "); hold the sensor still in at least " +
         std::to_string(opt.min_intervals) + " different orientations, each for more than " + fmt_g(hold_s) +
         " s, after a still initial period");
  }
  if (res.th_mult == 0)
    fail(
        "the static poses do not determine the accelerometer parameters (too few distinct orientations, or "
        "the fit diverged: check the bias and scale guesses; use orientations spread over the sphere)");

  res.model = acc_model(best.p);
  res.names = {"mis_yz", "mis_zy", "mis_zx", "s_x", "s_y", "s_z", "b_x", "b_y", "b_z"};
  res.values.assign(best.p.data(), best.p.data() + best.p.size());
  const double m = static_cast<double>(best.r.size());
  res.sigma0 = m > 9 ? std::sqrt(best.cost / (m - 9)) : std::numeric_limits<double>::quiet_NaN();
  const MatrixXd cov = res.sigma0 * res.sigma0 * best.inv_jtj;
  res.covariance = to_rows(cov);
  for (Eigen::Index i = 0; i < 9; ++i) res.sigma.push_back(std::sqrt(cov(i, i)));
  VectorXd r0;
  acc_eval(best_samples, opt.g)(p0, r0, nullptr);
  res.before = residual_stats(r0);
  res.after = residual_stats(best.r);
  res.iterations = best.iterations;
  res.converged = best.converged;
  return res;
}

GyroResult calibrate_gyroscope(const TriadSeries& acc, const AccResult& ar, const TriadSeries& gyro,
                               const Options& opt) {
  check_options(opt);
  const std::vector<double> ta = sample_times(acc, "accelerometer");
  const std::vector<double> tg = sample_times(gyro, "gyroscope");
  if (ar.intervals.size() < 2) fail("the gyroscope fit needs at least 2 static intervals");
  for (const IndexRange& i : ar.intervals)
    if (i.end >= acc.x.size() || i.begin >= i.end) fail("static intervals do not match the accelerometer record");

  GyroResult res;
  res.init_samples = init_count(tg, opt.init_static_s);
  if (res.init_samples < 2) fail("the initial static period holds fewer than 2 gyroscope samples");
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

  // Gravity directions from the calibrated accelerometer: the calibration is
  // affine, so the direction of the calibrated mean is that of the raw mean.
  std::vector<Vec3> raw_means;
  for (const IndexRange& i : ar.intervals) {
    Vec3 m{};
    for (std::size_t k = i.begin; k < i.end; ++k)
      for (int c = 0; c < 3; ++c) m[c] += acc.x[k][c];
    for (double& v : m) v /= static_cast<double>(i.size());
    raw_means.push_back(m);
  }
  auto directions = [&raw_means](const TriadCalibration& am) {
    std::vector<Eigen::Vector3d> u;
    for (const Vec3& m : raw_means) {
      const Vec3 a = am.apply(m);
      u.push_back(Eigen::Vector3d(a[0], a[1], a[2]).normalized());
    }
    return u;
  };
  const std::vector<Eigen::Vector3d> u = directions(ar.model);

  std::vector<GyroPair> pairs;
  for (std::size_t k = 1; k < ar.intervals.size(); ++k) {
    const double ts0 = ta[ar.intervals[k - 1].end];
    const double ts1 = ta[ar.intervals[k].begin];
    const auto j0 = static_cast<std::size_t>(std::lower_bound(tg.begin(), tg.end(), ts0) - tg.begin());
    const auto j1e = static_cast<std::size_t>(std::lower_bound(tg.begin(), tg.end(), ts1) - tg.begin());
    if (j1e == tg.size() || j0 + 1 >= j1e)
      fail("the gyroscope record does not cover the motion between static intervals " + std::to_string(k) + " and " +
           std::to_string(k + 1) + " (" + fmt_g(ts0) + " s to " + fmt_g(ts1) + " s)");
    GyroPair p;
    for (std::size_t j = j0; j < j1e; ++j) {
      p.raw.push_back(
          {gyro.x[j][0] - res.init_bias[0], gyro.x[j][1] - res.init_bias[1], gyro.x[j][2] - res.init_bias[2]});
      if (j > j0) p.dt.push_back(tg[j] - tg[j - 1]);
    }
    pairs.push_back(std::move(p));
  }
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
  if (!lm.determined || !lm.p.allFinite())
    fail(
        "the motions between static poses do not determine the gyroscope parameters (rotate about all three "
        "axes between poses)");
  if (lm.p.segment<3>(6).minCoeff() <= 0.0)
    fail("the gyroscope fit converged to a non-positive scale: check the gyroscope scale guess (rad/s per count)");

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
  if (ar.covariance.size() == 9 && ar.values.size() == 9) {
    MatrixXd Sa(9, 9), D(lm.r.size(), 9);
    const VectorXd pa = acc_params(ar.model);
    for (Eigen::Index j = 0; j < 9; ++j) {
      for (Eigen::Index i = 0; i < 9; ++i)
        Sa(i, j) = ar.covariance[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      const double typ = j < 3 ? 1e-2 : j < 6 ? std::abs(pa(j)) : 1e-2 * opt.g / std::abs(pa(3 + (j - 6)));
      const double h = 1e-6 * std::max(std::abs(pa(j)), typ);
      VectorXd pp = pa, pm = pa;
      pp(j) += h;
      pm(j) -= h;
      VectorXd rp, rm;
      gyro_residuals(pairs, directions(acc_model(pp)), lm.p, rp);
      gyro_residuals(pairs, directions(acc_model(pm)), lm.p, rm);
      D.col(j) = (rp - rm) / (pp(j) - pm(j));
    }
    if (Sa.allFinite() && D.allFinite()) cov += (S * D) * Sa * (S * D).transpose();
  }
  if (np == 9) {
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
  res.covariance = to_rows(cov);
  for (Eigen::Index i = 0; i < np; ++i) {
    res.sigma.push_back(std::sqrt(cov(i, i)));
    res.sigma_fit.push_back(std::sqrt(cov_fit(i, i)));
  }
  res.bias_sigma = res.init_bias_sigma;
  if (np == 12)
    for (int c = 0; c < 3; ++c) res.bias_sigma[c] = std::sqrt(cov(9 + c, 9 + c));

  VectorXd r0;
  gyro_residuals(pairs, u, p0, r0);
  res.before = residual_stats(r0);
  res.after = residual_stats(lm.r);
  auto angles = [&](const VectorXd& r, double& rms, double* mx) {
    double s = 0.0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const Eigen::Vector3d a = r.segment<3>(ei(3 * k)) + u[k + 1];
      const double ang = angle_between_deg(a, u[k + 1]);
      s += ang * ang;
      if (mx) *mx = std::max(*mx, ang);
    }
    rms = std::sqrt(s / static_cast<double>(pairs.size()));
  };
  angles(r0, res.angle_rms_before_deg, nullptr);
  angles(lm.r, res.angle_rms_after_deg, &res.angle_max_after_deg);
  res.iterations = lm.iterations;
  res.converged = lm.converged;
  return res;
}

Result calibrate(const TriadSeries& acc, const TriadSeries& gyro, const Options& opt) {
  Result r;
  r.acc = calibrate_accelerometer(acc, opt);
  r.gyro = calibrate_gyroscope(acc, r.acc, gyro, opt);
  return r;
}

}  // namespace cubecal::multipos
