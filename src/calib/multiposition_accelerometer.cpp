// Multi-position accelerometer calibration (docs/formulas/multiposition.md §2-3, §6.1):
// for each threshold multiplier, the static intervals and the 9-parameter fit
// of g - |T K (a - B)|; the multiplier with the smallest cost is kept.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/calib/multiposition.hpp"
#include "cubecal/calib/static_detection.hpp"
#include "cubecal/error.hpp"
#include "../detail/levenberg_marquardt.hpp"
#include "../detail/eigen_matrix.hpp"
#include "detail/multiposition_common.hpp"

namespace cubecal::multipos {

namespace {

using cubecal::detail::EvalFn;
using cubecal::detail::levenberg_marquardt;
using cubecal::detail::LmOutcome;
using detail::acc_model;
using detail::acc_params;
using detail::ei;
using detail::fail;
using detail::fmt_g;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const char* kNonFiniteGuess =
    "the initial guess gives non-finite residuals (check the bias and scale guesses)";

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

// The initial guess: the bias guess, and the scale guess or, without one,
// g over the mean |a - bias guess| of the initial static period.
TriadCalibration initial_guess(std::span<const Vec3> init, const Options& opt) {
  using R = CalibrationReason;
  TriadCalibration init_model;
  init_model.bias = opt.acc_bias_guess;
  double s0 = opt.acc_scale_guess;
  if (s0 == 0.0) {
    double mean_norm = 0.0;
    for (const Vec3& a : init)
      mean_norm += std::hypot(a[0] - init_model.bias[0], a[1] - init_model.bias[1], a[2] - init_model.bias[2]);
    mean_norm /= static_cast<double>(init.size());
    if (!(mean_norm > 0.0))
      fail(R::scale_guess, "the initial static period reads the bias guess exactly: give a scale guess");
    s0 = opt.g / mean_norm;
  }
  init_model.scale = {s0, s0, s0};
  return init_model;
}

}  // namespace

AccResult calibrate_accelerometer(const TriadSeries& acc, const Options& opt) {
  using R = CalibrationReason;
  detail::check_options(opt);
  const std::size_t window = normalised_window(opt.window);
  const std::vector<double> t = detail::sample_times(acc, "accelerometer");
  const std::size_t n = acc.x.size();
  AccResult res;
  res.init_samples = detail::init_count(t, opt.init_static_s);
  if (res.init_samples >= n)
    fail(R::initial_static, "the record (" + fmt_g(t.back() - t.front()) +
                                " s) is not longer than the initial static period (" + fmt_g(opt.init_static_s) +
                                " s)");
  if (res.init_samples < window)
    fail(R::initial_static, "the initial static period holds " + std::to_string(res.init_samples) +
                                " samples, fewer than the variance window (" + std::to_string(window) + ")");
  const std::span<const Vec3> init = acc.x.first(res.init_samples);
  res.init_variance_norm = block_variance_norm(init);
  if (!(res.init_variance_norm > 0.0))
    fail(R::initial_static,
         "the accelerometer does not vary at all over the initial static period: no noise level to set the "
         "static threshold");

  const TriadCalibration init_model = initial_guess(init, opt);
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
      if (!lm.initial_finite) fail(R::scale_guess, kNonFiniteGuess);
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
    fail(R::too_few_intervals,
         "fewer than " + std::to_string(opt.min_intervals) + " static intervals: at most " + std::to_string(most) +
             " found (intervals of at least " + std::to_string(opt.interval_samples) + " samples, thresholds " +
             std::to_string(opt.th_mult_min) + ".." + std::to_string(opt.th_mult_max) +
             " x the variance of the initial " + fmt_g(opt.init_static_s) + " s, window " + std::to_string(window) +
             "); hold the sensor still in at least " + std::to_string(opt.min_intervals) +
             " different orientations, each for more than " + fmt_g(hold_s) + " s, after a still initial period");
  }
  if (res.th_mult == 0)
    fail(R::degenerate,
         "the static poses do not determine the accelerometer parameters (too few distinct orientations, or "
         "the fit diverged: check the bias and scale guesses; use orientations spread over the sphere)");

  res.model = acc_model(best.p);
  res.names = {"mis_yz", "mis_zy", "mis_zx", "s_x", "s_y", "s_z", "b_x", "b_y", "b_z"};
  res.values.assign(best.p.data(), best.p.data() + best.p.size());
  const double m = static_cast<double>(best.r.size());
  res.sigma0 = m > 9 ? std::sqrt(best.cost / (m - 9)) : std::numeric_limits<double>::quiet_NaN();
  const MatrixXd cov = res.sigma0 * res.sigma0 * best.inv_jtj;
  res.covariance = cubecal::detail::to_matrix(cov);
  for (Eigen::Index i = 0; i < 9; ++i) res.sigma.push_back(std::sqrt(cov(i, i)));
  VectorXd r0;
  acc_eval(best_samples, opt.g)(p0, r0, nullptr);
  res.before = detail::residual_stats(r0);
  res.after = detail::residual_stats(best.r);
  res.iterations = best.iterations;
  res.converged = best.converged;
  return res;
}

}  // namespace cubecal::multipos
