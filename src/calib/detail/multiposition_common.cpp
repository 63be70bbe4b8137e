// Shared by the multi-position accelerometer and gyroscope calibrations: the
// checks of a triad record and of the options, and the accelerometer's
// parameter vector.
#include "multiposition_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cubecal::multipos::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

std::string fmt_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

void fail(CalibrationReason reason, const std::string& what) { throw CalibrationError(reason, what); }

// ---------------------------------------------------------------------------
// Data checks.

std::vector<double> sample_times(const TriadSeries& s, const char* what) {
  using R = CalibrationReason;
  if (s.x.empty()) fail(R::too_few_points, std::string(what) + ": no samples");
  for (std::size_t i = 0; i < s.x.size(); ++i)
    for (double v : s.x[i])
      if (!std::isfinite(v)) fail(R::bad_data, std::string(what) + ": non-finite value at sample " + std::to_string(i));
  std::vector<double> t(s.x.size());
  if (s.t.empty()) {
    if (!(s.rate_hz > 0.0) || !std::isfinite(s.rate_hz))
      fail(R::bad_option, std::string(what) + ": give time stamps or a positive sampling rate");
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) / s.rate_hz;
    return t;
  }
  if (s.t.size() != s.x.size())
    fail(R::bad_data, std::string(what) + ": " + std::to_string(s.t.size()) + " time stamps for " +
                          std::to_string(s.x.size()) + " samples");
  for (std::size_t i = 0; i < t.size(); ++i) {
    t[i] = s.t[i];
    if (!std::isfinite(t[i]))
      fail(R::bad_data, std::string(what) + ": non-finite time stamp at sample " + std::to_string(i));
    if (i > 0 && !(t[i] > t[i - 1]))
      fail(R::bad_data, std::string(what) + ": time stamps not increasing at sample " + std::to_string(i) + " (" +
                            fmt_g(t[i - 1]) + " s then " + fmt_g(t[i]) + " s)");
  }
  return t;
}

// Samples with t < t_0 + init_static_s.
std::size_t init_count(const std::vector<double>& t, double init_static_s) {
  const double end = t.front() + init_static_s;
  return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), end) - t.begin());
}

void check_options(const Options& o) {
  using R = CalibrationReason;
  if (!(o.g > 0.0) || !std::isfinite(o.g)) fail(R::bad_option, "gravity magnitude g must be positive");
  if (!(o.init_static_s > 0.0) || !std::isfinite(o.init_static_s))
    fail(R::bad_option, "initial static period must be a positive number of seconds");
  if (o.interval_samples < 1) fail(R::bad_option, "samples per interval must be at least 1");
  if (o.min_intervals < 2) fail(R::bad_option, "at least 2 static intervals must be required");
  if (o.th_mult_min < 1 || o.th_mult_max < o.th_mult_min) fail(R::bad_option, "th_mult range must be 1 <= min <= max");
  if (!(o.acc_scale_guess >= 0.0) || !std::isfinite(o.acc_scale_guess))
    fail(R::bad_option, "accelerometer scale guess must be positive (or 0 for automatic)");
  if (!(o.gyro_scale_guess > 0.0) || !std::isfinite(o.gyro_scale_guess))
    fail(R::bad_option, "gyroscope scale guess must be positive");
  for (double b : o.acc_bias_guess)
    if (!std::isfinite(b)) fail(R::bad_option, "accelerometer bias guess must be finite");
  if (o.max_iterations < 1) fail(R::bad_option, "max_iterations must be at least 1");
}

Residuals residual_stats(const VectorXd& r) {
  Residuals s;
  s.count = static_cast<std::size_t>(r.size());
  s.cost = r.squaredNorm();
  s.rms = s.count ? std::sqrt(s.cost / static_cast<double>(s.count)) : 0.0;
  s.max = r.size() ? r.cwiseAbs().maxCoeff() : 0.0;
  return s;
}

// ---------------------------------------------------------------------------
// The accelerometer parameter vector.

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

}  // namespace cubecal::multipos::detail
