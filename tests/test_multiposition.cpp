// Multi-position calibration without a turntable (docs/formulas/multiposition.md): the
// model layout, static detection on planted poses, recovery of known
// accelerometer and gyroscope parameters from synthetic sequences (exact and
// noisy), the error paths, the real imu_tk xsens sequence, the MPU-6050
// example, and the `calibrate multiposition` command.
#include <gtest/gtest.h>

#include "mat3.hpp"
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/calib/multiposition.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "reason_of.hpp"

namespace {

using namespace cubecal::multipos;
using cubecal::IndexRange;
using cubecal::kIdentity3;
using cubecal::Mat3;
using cubecal::Vec3;

constexpr double kPi = 3.14159265358979323846;

using cubecal::test::inverse;
using cubecal::test::mul;
using cubecal::test::norm;
using cubecal::test::transpose;

// ---------------------------------------------------------------------------
// Small 3x3 algebra (the rest in mat3.hpp).

// exp([n]x theta), n a unit vector (Rodrigues).
Mat3 rotation(const Vec3& n, double theta) {
  const double c = std::cos(theta), s = std::sin(theta), v = 1.0 - c;
  const double x = n[0], y = n[1], z = n[2];
  return Mat3{{{c + x * x * v, x * y * v - z * s, x * z * v + y * s},
               {y * x * v + z * s, c + y * y * v, y * z * v - x * s},
               {z * x * v - y * s, z * y * v + x * s, c + z * z * v}}};
}

// Axis and angle (0 < angle < pi) of a rotation matrix.
void axis_angle(const Mat3& r, Vec3& n, double& theta) {
  theta = std::acos(std::clamp((r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0, -1.0, 1.0));
  const Vec3 w{r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]};
  const double s = norm(w);
  n = {w[0] / s, w[1] / s, w[2] / s};
}

// ---------------------------------------------------------------------------
// Synthetic multi-position sequence.
//
// Pose 0 is held for init_s (the initial static period), every other pose for
// static_s. Between poses the body turns about a fixed body axis n by Theta
// with theta(tau) = Theta (tau/T - sin(2 pi tau/T)/(2 pi)), so the body rate
// is n Theta/T (1 - cos(2 pi tau/T)) and the attitude C_k exp([n]x theta(tau))
// is exact at every sample. Poses are random rotations (fixed seed).
// Specific force in the body frame f = C^T (0, 0, g); raw readings
// (T K)^-1 f + B and (T_g K_g)^-1 w + b_g, plus white noise in counts.

struct Truth {
  TriadCalibration acc;
  TriadCalibration gyro;
  double g = 9.80665;
};

Truth make_truth() {
  Truth t;
  t.acc.mis_yz = 0.012;
  t.acc.mis_zy = -0.008;
  t.acc.mis_zx = 0.005;
  t.acc.scale = {9.80665 / 4000.0 * 1.02, 9.80665 / 4000.0 * 0.97, 9.80665 / 4000.0 * 1.005};
  t.acc.bias = {32768.0 + 150.0, 32768.0 - 220.0, 32768.0 + 90.0};
  t.gyro.mis_yz = 0.010;
  t.gyro.mis_zy = -0.015;
  t.gyro.mis_zx = 0.007;
  t.gyro.mis_xz = -0.004;
  t.gyro.mis_xy = 0.011;
  t.gyro.mis_yx = -0.006;
  t.gyro.scale = {1.0 / 6000.0 * 1.03, 1.0 / 6000.0 * 0.98, 1.0 / 6000.0 * 1.01};
  t.gyro.bias = {32768.0 + 40.0, 32768.0 - 25.0, 32768.0 + 12.0};
  return t;
}

struct Synthetic {
  std::vector<double> t;
  std::vector<Vec3> acc, gyro;
  std::vector<IndexRange> planted;  // static segments [begin, end), pose 0 first
};

Synthetic make_sequence(const Truth& tr, std::size_t poses, double acc_noise, double gyro_noise, unsigned seed,
                        double init_s = 10.0, double static_s = 2.0, double motion_s = 2.0) {
  const double dt = 0.01;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> unif(0.0, 1.0);
  // Attitudes: pose 0 level, then random rotations whose step from the
  // previous pose stays below 170 degrees.
  std::vector<Mat3> C{rotation({1.0, 0.0, 0.0}, 0.0)};
  while (C.size() < poses) {
    Vec3 n{gauss(rng), gauss(rng), gauss(rng)};
    const double s = norm(n);
    n = {n[0] / s, n[1] / s, n[2] / s};
    const Mat3 cand = rotation(n, kPi * unif(rng));
    Vec3 axis;
    double theta;
    axis_angle(mul(transpose(C.back()), cand), axis, theta);
    if (theta < 0.5 || theta > 170.0 * kPi / 180.0) continue;
    C.push_back(cand);
  }
  const Mat3 acc_inv = inverse(tr.acc.matrix());
  const Mat3 gyro_inv = inverse(tr.gyro.matrix());
  Synthetic s;
  auto emit = [&](const Mat3& att, const Vec3& w) {
    const Vec3 f = mul(transpose(att), Vec3{0.0, 0.0, tr.g});
    Vec3 a = mul(acc_inv, f), r = mul(gyro_inv, w);
    for (std::size_t c = 0; c < 3; ++c) {
      a[c] += tr.acc.bias[c] + acc_noise * gauss(rng);
      r[c] += tr.gyro.bias[c] + gyro_noise * gauss(rng);
    }
    s.t.push_back(static_cast<double>(s.t.size()) * dt);
    s.acc.push_back(a);
    s.gyro.push_back(r);
  };
  const auto n_motion = static_cast<std::size_t>(std::lround(motion_s / dt));
  for (std::size_t k = 0; k < poses; ++k) {
    const auto n_static = static_cast<std::size_t>(std::lround((k == 0 ? init_s : static_s) / dt));
    const std::size_t begin = s.t.size();
    for (std::size_t j = 0; j < n_static; ++j) emit(C[k], {0.0, 0.0, 0.0});
    s.planted.push_back({begin, s.t.size()});
    if (k + 1 == poses) break;
    Vec3 n;
    double theta_total;
    axis_angle(mul(transpose(C[k]), C[k + 1]), n, theta_total);
    const double T = static_cast<double>(n_motion) * dt;
    for (std::size_t j = 0; j < n_motion; ++j) {
      const double tau = static_cast<double>(j) * dt;
      const double th = theta_total * (tau / T - std::sin(2.0 * kPi * tau / T) / (2.0 * kPi));
      const double rate = theta_total / T * (1.0 - std::cos(2.0 * kPi * tau / T));
      emit(mul(C[k], rotation(n, th)), {n[0] * rate, n[1] * rate, n[2] * rate});
    }
  }
  return s;
}

Options synthetic_options(const Truth& tr) {
  Options o;
  o.g = tr.g;
  o.init_static_s = 10.0;
  o.acc_bias_guess = {32768.0, 32768.0, 32768.0};
  o.gyro_scale_guess = 1.0 / 6000.0;
  return o;
}

TriadSeries series(const Synthetic& s, bool gyro) { return {gyro ? s.gyro : s.acc, s.t, 0.0}; }

std::vector<double> acc_truth_vector(const TriadCalibration& m) {
  return {m.mis_yz, m.mis_zy, m.mis_zx, m.scale[0], m.scale[1], m.scale[2], m.bias[0], m.bias[1], m.bias[2]};
}
std::vector<double> gyro_truth_vector(const TriadCalibration& m) {
  return {m.mis_yz, m.mis_zy, m.mis_zx, m.mis_xz, m.mis_xy, m.mis_yx, m.scale[0], m.scale[1], m.scale[2]};
}

// Error of each parameter in the unit of the check: misalignment in rad,
// scale relative, bias in counts.
double param_error(const std::string& name, double est, double truth) {
  if (name[0] == 's') return std::abs(est / truth - 1.0);
  return std::abs(est - truth);
}

void print_params(const char* what, const std::vector<std::string>& names, const std::vector<double>& est,
                  const std::vector<double>& sigma, const std::vector<double>& truth) {
  std::printf("  %s\n", what);
  for (std::size_t i = 0; i < names.size(); ++i)
    std::printf("    %-7s true %14.8g  est %14.8g  sigma %10.3g  (est-true)/sigma %+7.2f\n", names[i].c_str(), truth[i],
                est[i], sigma[i], (est[i] - truth[i]) / sigma[i]);
}

// ---------------------------------------------------------------------------

TEST(MultiPosition, ModelLayoutFollowsImuTk) {
  TriadCalibration m;
  m.mis_yz = 0.1;
  m.mis_zy = 0.2;
  m.mis_zx = 0.3;
  m.mis_xz = 0.4;
  m.mis_xy = 0.5;
  m.mis_yx = 0.6;
  m.scale = {2.0, 3.0, 4.0};
  m.bias = {1.0, 1.0, 1.0};
  const Mat3 T = m.misalignment();
  EXPECT_EQ(T[0][1], -0.1);
  EXPECT_EQ(T[0][2], 0.2);
  EXPECT_EQ(T[1][2], -0.3);
  EXPECT_EQ(T[1][0], 0.4);
  EXPECT_EQ(T[2][0], -0.5);
  EXPECT_EQ(T[2][1], 0.6);
  const Vec3 y = m.apply({2.0, 2.0, 2.0});  // T K (1, 1, 1) = T (2, 3, 4)
  EXPECT_NEAR(y[0], 2.0 - 0.3 + 0.8, 1e-15);
  EXPECT_NEAR(y[1], 0.8 + 3.0 - 1.2, 1e-15);
  EXPECT_NEAR(y[2], -1.0 + 1.8 + 4.0, 1e-15);
}

TEST(MultiPosition, WindowRule) {
  EXPECT_EQ(normalised_window(101), 101u);
  EXPECT_EQ(normalised_window(100), 101u);
  EXPECT_EQ(normalised_window(11), 11u);
  EXPECT_THROW(normalised_window(10), cubecal::CalibrationError);
}

TEST(MultiPosition, StaticDetectionFindsPlantedIntervals) {
  const Truth tr = make_truth();
  const Synthetic s = make_sequence(tr, 16, 1.0, 2.0, 7);
  const std::vector<double> v = variance_norm(s.acc, 101);
  const double init = block_variance_norm(std::span<const Vec3>(s.acc).first(1000));
  for (int th : {2, 5, 10}) {
    const std::vector<IndexRange> iv = static_intervals(v, th * init);
    ASSERT_EQ(iv.size(), s.planted.size()) << "th_mult " << th;
    for (std::size_t k = 0; k < iv.size(); ++k) {
      // The centred window fits inside the static segment from begin + 50 to
      // end - 50; the slow start and end of each turn may add a few centres.
      const IndexRange& p = s.planted[k];
      EXPECT_LE(iv[k].begin, p.begin + 50) << k;
      EXPECT_GE(iv[k].begin + 40, p.begin + 50) << k;
      EXPECT_GE(iv[k].end, p.end - 50) << k;
      EXPECT_LE(iv[k].end, p.end - 50 + 40) << k;
      EXPECT_GE(iv[k].size(), kIntervalSamples) << k;
    }
  }
  // The edges, whose window does not fit, are never static.
  EXPECT_TRUE(std::isinf(v[0]));
  EXPECT_TRUE(std::isinf(v[49]));
  EXPECT_FALSE(std::isinf(v[50]));
  EXPECT_TRUE(std::isinf(v.back()));
}

TEST(MultiPosition, RecoversKnownParametersWithoutNoise) {
  const Truth tr = make_truth();
  // Noise 1e-6 counts: only so that the initial period has a variance.
  const Synthetic s = make_sequence(tr, 16, 1e-6, 1e-6, 11);
  const Result r = calibrate(series(s, false), series(s, true), synthetic_options(tr));
  EXPECT_EQ(r.acc.intervals.size(), 16u);
  EXPECT_TRUE(r.acc.converged);
  EXPECT_TRUE(r.gyro.converged);
  const auto at = acc_truth_vector(tr.acc);
  const auto gt = gyro_truth_vector(tr.gyro);
  std::printf(
      "noise-free: acc rms |g| error %.3g -> %.3g m/s^2 (th_mult %d, %zu intervals, %zu iterations); "
      "gyro angle rms %.3g -> %.3g deg\n",
      r.acc.before.rms, r.acc.after.rms, r.acc.th_mult, r.acc.intervals.size(), r.acc.iterations,
      r.gyro.angle_rms_before_deg, r.gyro.angle_rms_after_deg);
  print_params("accelerometer", r.acc.names, r.acc.values, r.acc.sigma, at);
  print_params("gyroscope", r.gyro.names, r.gyro.values, r.gyro.sigma, gt);
  // Accelerometer: exact but for the 1e-6 counts of noise (misalignment
  // 1e-8 rad, scale 1e-8 relative, bias 1e-5 counts).
  for (std::size_t i = 0; i < 9; ++i)
    EXPECT_LT(param_error(r.acc.names[i], r.acc.values[i], at[i]), r.acc.names[i][0] == 'b' ? 1e-5 : 1e-8)
        << r.acc.names[i];
  // Gyroscope: limited by the RK4 integration of sampled rates (100 Hz).
  for (std::size_t i = 0; i < 9; ++i)
    EXPECT_LT(param_error(r.gyro.names[i], r.gyro.values[i], gt[i]), 2e-6) << r.gyro.names[i];
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(r.gyro.model.bias[c], tr.gyro.bias[c], 1e-6);
  EXPECT_LT(r.acc.after.rms, 1e-8);
  EXPECT_GT(r.acc.before.rms, 0.05);
  EXPECT_LT(r.gyro.angle_rms_after_deg, 1e-4);
  EXPECT_GT(r.gyro.angle_rms_before_deg, 0.5);
}

TEST(MultiPosition, RecoversKnownParametersWithNoise) {
  const Truth tr = make_truth();
  // 1 count accelerometer noise (2.5 mm/s^2), 2 counts gyro (0.02 deg/s).
  const Synthetic s = make_sequence(tr, 18, 1.0, 2.0, 23);
  const Result r = calibrate(series(s, false), series(s, true), synthetic_options(tr));
  const auto at = acc_truth_vector(tr.acc);
  const auto gt = gyro_truth_vector(tr.gyro);
  std::printf(
      "noisy: acc rms |g| error %.4g -> %.4g m/s^2 (th_mult %d, %zu intervals); gyro angle rms %.4g -> "
      "%.4g deg over %zu pairs\n",
      r.acc.before.rms, r.acc.after.rms, r.acc.th_mult, r.acc.intervals.size(), r.gyro.angle_rms_before_deg,
      r.gyro.angle_rms_after_deg, r.gyro.pairs);
  print_params("accelerometer", r.acc.names, r.acc.values, r.acc.sigma, at);
  print_params("gyroscope", r.gyro.names, r.gyro.values, r.gyro.sigma, gt);
  EXPECT_EQ(r.acc.intervals.size(), 18u);
  // Stated tolerances: misalignment 5e-4 rad, scale 5e-4 relative, bias 2
  // counts (accelerometer); misalignment 2e-3 rad, scale 2e-3 (gyroscope);
  // and every estimate within 5 of its own sigmas.
  for (std::size_t i = 0; i < 9; ++i) {
    const double tol = r.acc.names[i][0] == 'b' ? 2.0 : 5e-4;
    EXPECT_LT(param_error(r.acc.names[i], r.acc.values[i], at[i]), tol) << r.acc.names[i];
    EXPECT_LT(std::abs(r.acc.values[i] - at[i]), 5.0 * r.acc.sigma[i]) << r.acc.names[i];
    EXPECT_LT(param_error(r.gyro.names[i], r.gyro.values[i], gt[i]), 2e-3) << r.gyro.names[i];
    EXPECT_LT(std::abs(r.gyro.values[i] - gt[i]), 5.0 * r.gyro.sigma[i]) << r.gyro.names[i];
  }
  // Residual |g| error down to the noise: 1 count x scale.
  EXPECT_LT(r.acc.after.rms, 1.5 * tr.acc.scale[0]);
  EXPECT_GT(r.acc.before.rms, 10.0 * r.acc.after.rms);
  EXPECT_NEAR(r.acc.sigma0, r.acc.after.rms, 0.01 * r.acc.after.rms);
  // Gyro bias from the initial period: its standard error is 2/sqrt(1000).
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.gyro.model.bias[c], tr.gyro.bias[c], 5.0 * r.gyro.bias_sigma[c]);
    EXPECT_NEAR(r.gyro.bias_sigma[c], 2.0 / std::sqrt(1000.0), 0.01);
  }
}

TEST(MultiPosition, RefinedGyroBiasStaysAtTheTruth) {
  const Truth tr = make_truth();
  const Synthetic s = make_sequence(tr, 16, 1e-6, 1e-6, 11);
  Options o = synthetic_options(tr);
  o.refine_gyro_bias = true;
  const GyroResult g = calibrate(series(s, false), series(s, true), o).gyro;
  ASSERT_EQ(g.values.size(), 12u);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(g.model.bias[c], tr.gyro.bias[c], 1e-3);
  EXPECT_LT(g.angle_rms_after_deg, 1e-4);
}

TEST(MultiPosition, FewerThanTwelveIntervalsIsAClearError) {
  const Truth tr = make_truth();
  const Synthetic s = make_sequence(tr, 10, 1.0, 2.0, 5);
  try {
    (void)calibrate_accelerometer(series(s, false), synthetic_options(tr));
    FAIL() << "no error";
  } catch (const cubecal::CalibrationError& e) {
    const std::string msg = e.what();
    std::printf("10 poses: %s\n", msg.c_str());
    EXPECT_NE(msg.find("fewer than 12 static intervals"), std::string::npos) << msg;
    EXPECT_NE(msg.find("at most 10"), std::string::npos) << msg;
  }
  // The same record passes when 10 are enough.
  Options o = synthetic_options(tr);
  o.min_intervals = 10;
  EXPECT_EQ(calibrate_accelerometer(series(s, false), o).intervals.size(), 10u);
}

TEST(MultiPosition, StaticTooShortIsAClearError) {
  // 16 poses held 1.5 s: the 101-sample window leaves fewer than 100 centres.
  const Truth tr = make_truth();
  const Synthetic s = make_sequence(tr, 16, 1.0, 2.0, 5, 10.0, 1.5);
  EXPECT_THROW((void)calibrate_accelerometer(series(s, false), synthetic_options(tr)), cubecal::CalibrationError);
}

TEST(MultiPosition, BadInputsAreRejected) {
  const Truth tr = make_truth();
  const Synthetic s = make_sequence(tr, 14, 1.0, 2.0, 3);
  const Options o = synthetic_options(tr);
  auto throws_with = [&](const TriadSeries& a, const Options& opt, const std::string& part) {
    try {
      (void)calibrate_accelerometer(a, opt);
      ADD_FAILURE() << "no error, expected: " << part;
    } catch (const cubecal::CalibrationError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  throws_with({s.acc, {}, 0.0}, o, "time stamps or a positive sampling rate");
  std::vector<double> t = s.t;
  t[100] = t[99];
  throws_with({s.acc, t, 0.0}, o, "not increasing at sample 100");
  throws_with({s.acc, std::span<const double>(s.t).first(10), 0.0}, o, "10 time stamps");
  Options long_init = o;
  long_init.init_static_s = 1e4;
  throws_with(series(s, false), long_init, "not longer than the initial static period");
  std::vector<Vec3> flat(s.acc.size(), Vec3{1.0, 2.0, 3.0});
  throws_with({flat, s.t, 0.0}, o, "does not vary at all");
  Options bad_g = o;
  bad_g.g = -1.0;
  throws_with(series(s, false), bad_g, "gravity");
  // A uniform rate gives the same result as the time stamps.
  const AccResult a = calibrate_accelerometer({s.acc, {}, 100.0}, o);
  const AccResult b = calibrate_accelerometer(series(s, false), o);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_NEAR(a.values[i], b.values[i], 1e-9 * std::abs(b.values[i]) + 1e-12);
}

using cubecal::test::reason_of;

TEST(MultiPosition, ErrorsCarryTheirReason) {
  const Truth tr = make_truth();
  const Synthetic s = make_sequence(tr, 14, 1.0, 2.0, 3);
  const Options o = synthetic_options(tr);
  auto acc_reason = [&](const TriadSeries& a, const Options& opt) {
    return reason_of([&] { (void)calibrate_accelerometer(a, opt); });
  };
  // bad_data: stamps not increasing, of the wrong count; a non-finite sample.
  std::vector<double> t = s.t;
  t[100] = t[99];
  EXPECT_EQ(acc_reason({s.acc, t, 0.0}, o), "bad_data");
  EXPECT_EQ(acc_reason({s.acc, std::span<const double>(s.t).first(10), 0.0}, o), "bad_data");
  std::vector<Vec3> nan_acc = s.acc;
  nan_acc[7][1] = std::nan("");
  EXPECT_EQ(acc_reason({nan_acc, s.t, 0.0}, o), "bad_data");
  // bad_option: no rate, g, window below 11.
  EXPECT_EQ(acc_reason({s.acc, {}, 0.0}, o), "bad_option");
  Options bad = o;
  bad.g = -1.0;
  EXPECT_EQ(acc_reason(series(s, false), bad), "bad_option");
  bad = o;
  bad.window = 5;
  EXPECT_EQ(acc_reason(series(s, false), bad), "bad_option");
  EXPECT_EQ(reason_of([] { (void)normalised_window(10); }), "bad_option");
  // too_few_points: no samples; one sample has no variance.
  EXPECT_EQ(acc_reason({std::span<const Vec3>(), {}, 100.0}, o), "too_few_points");
  EXPECT_EQ(reason_of([&] { (void)block_variance_norm(std::span<const Vec3>(s.acc).first(1)); }), "too_few_points");
  // initial_static: record not longer than the period, a period shorter than
  // the window, a constant period.
  bad = o;
  bad.init_static_s = 1e4;
  EXPECT_EQ(acc_reason(series(s, false), bad), "initial_static");
  bad = o;
  bad.init_static_s = 0.5;  // 50 samples < 101
  EXPECT_EQ(acc_reason(series(s, false), bad), "initial_static");
  const std::vector<Vec3> flat(s.acc.size(), Vec3{1.0, 2.0, 3.0});
  EXPECT_EQ(acc_reason({flat, s.t, 0.0}, o), "initial_static");
  // scale_guess: a scale guess whose residuals overflow.
  bad = o;
  bad.acc_scale_guess = 1e300;
  EXPECT_EQ(acc_reason(series(s, false), bad), "scale_guess");
  // too_few_intervals: 10 poses for the 12 required.
  const Synthetic ten = make_sequence(tr, 10, 1.0, 2.0, 5);
  EXPECT_EQ(acc_reason(series(ten, false), o), "too_few_intervals");
  // degenerate: 13 static poses, all in the same orientation (exact readings
  // between bursts of motion): the scales and misalignments are not
  // determined.
  {
    std::vector<Vec3> same;
    const Vec3 a0{32768.0 + 150.0, 32768.0 - 220.0, 32768.0 + 4090.0};
    std::mt19937_64 rng(9);
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (int k = 0; k < 1000; ++k) same.push_back({a0[0] + 1e-6 * gauss(rng), a0[1] + 1e-6 * gauss(rng), a0[2]});
    for (int pose = 0; pose < 13; ++pose) {
      for (int k = 0; k < 200; ++k)
        same.push_back({a0[0] + 2000.0 * std::sin(0.1 * k), a0[1] + 1500.0 * std::cos(0.13 * k), a0[2] - 300.0});
      for (int k = 0; k < 300; ++k) same.push_back(a0);
    }
    EXPECT_EQ(acc_reason({same, {}, 100.0}, o), "degenerate");
  }

  // The gyroscope, given a good accelerometer result.
  const AccResult ar = calibrate_accelerometer(series(s, false), o);
  auto gyro_reason = [&](const AccResult& a, const TriadSeries& g, const Options& opt) {
    return reason_of([&] { (void)calibrate_gyroscope(series(s, false), a, g, opt); });
  };
  EXPECT_EQ(gyro_reason(ar, series(s, true), o), "(none)");
  // too_few_intervals: one interval; intervals beyond the record.
  AccResult one = ar;
  one.intervals.resize(1);
  EXPECT_EQ(gyro_reason(one, series(s, true), o), "too_few_intervals");
  AccResult beyond = ar;
  beyond.intervals.back().end = s.acc.size() + 10;
  EXPECT_EQ(gyro_reason(beyond, series(s, true), o), "too_few_intervals");
  // initial_static: one gyro sample in the 10 s period (a sample every 20 s).
  EXPECT_EQ(gyro_reason(ar, {s.gyro, {}, 0.05}, o), "initial_static");
  // bad_data: the gyro record stops before the first motion ends.
  EXPECT_EQ(
      gyro_reason(ar, {std::span<const Vec3>(s.gyro).first(1100), std::span<const double>(s.t).first(1100), 0.0}, o),
      "bad_data");
  // scale_guess: a scale guess whose integration overflows.
  bad = o;
  bad.gyro_scale_guess = 1e300;
  EXPECT_EQ(gyro_reason(ar, series(s, true), bad), "scale_guess");
  // degenerate: a gyro that reads its bias throughout senses no rotation.
  const std::vector<Vec3> still(s.gyro.size(), Vec3{32768.0, 32768.0, 32768.0});
  std::vector<Vec3> still_noisy = still;
  for (std::size_t k = 0; k < 1000; ++k) still_noisy[k][k % 3] += (k % 2 ? 1.0 : -1.0);
  EXPECT_EQ(gyro_reason(ar, {still_noisy, s.t, 0.0}, o), "degenerate");
}

// ---------------------------------------------------------------------------
// Real data.

struct Loaded {
  std::vector<double> t;
  std::vector<Vec3> x;
};

Loaded load(const std::string& path, std::vector<std::string> cols, const std::string& time_col, std::size_t skip) {
  cubecal::io::TableOptions to;
  to.columns = std::move(cols);
  if (!time_col.empty()) to.extra_columns = {time_col};
  to.skip_rows = skip;
  const auto tab = cubecal::io::read_table(path, to);
  Loaded l;
  for (std::size_t i = 0; i < tab.rows(); ++i) l.x.push_back({tab.data[0][i], tab.data[1][i], tab.data[2][i]});
  if (!time_col.empty()) l.t = tab.extra[0];
  return l;
}

const std::string kXsens = std::string(CUBECAL_SHARED_DATA) + "/imu/xsens-multiposition/";
const std::string kMpu = std::string(CUBECAL_SHARED_DATA) + "/imu/mpu6050/example_data_calibration.csv";

TEST(MultiPosition, XsensSequence) {
  const Loaded acc = load(kXsens + "xsens_acc.txt", {"2", "3", "4"}, "1", 0);
  const Loaded gyro = load(kXsens + "xsens_gyro.txt", {"2", "3", "4"}, "1", 0);
  ASSERT_EQ(acc.x.size(), 51175u);
  Options o;
  o.g = 9.81744;
  o.init_static_s = 50.0;
  o.acc_bias_guess = {32768.0, 32768.0, 32768.0};
  o.gyro_scale_guess = 1.0 / 6258.0;  // test_imu_calib's guess
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = calibrate({acc.x, acc.t, 0.0}, {gyro.x, gyro.t, 0.0}, o);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("xsens (%.2f s): init %zu samples, |var| %.4g counts^2; th_mult %d, %zu static intervals\n", secs,
              r.acc.init_samples, r.acc.init_variance_norm, r.acc.th_mult, r.acc.intervals.size());
  for (const Trial& tr : r.acc.trials)
    std::printf("  th_mult %2d: %2zu intervals%s cost %.6g\n", tr.th_mult, tr.intervals,
                tr.fitted ? "," : " (not fitted)", tr.cost);
  std::printf("  acc |g| error rms %.5g -> %.5g m/s^2 (max %.4g -> %.4g), cost %.6g -> %.6g, %zu iterations\n",
              r.acc.before.rms, r.acc.after.rms, r.acc.before.max, r.acc.after.max, r.acc.before.cost, r.acc.after.cost,
              r.acc.iterations);
  for (std::size_t i = 0; i < 9; ++i)
    std::printf("    %-7s %14.8g +- %.3g\n", r.acc.names[i].c_str(), r.acc.values[i], r.acc.sigma[i]);
  std::printf("  gyro angle rms %.4g -> %.4g deg (max after %.4g), cost %.6g -> %.6g over %zu pairs, %zu iterations\n",
              r.gyro.angle_rms_before_deg, r.gyro.angle_rms_after_deg, r.gyro.angle_max_after_deg, r.gyro.before.cost,
              r.gyro.after.cost, r.gyro.pairs, r.gyro.iterations);
  for (std::size_t i = 0; i < 9; ++i)
    std::printf("    %-7s %14.8g +- %.3g\n", r.gyro.names[i].c_str(), r.gyro.values[i], r.gyro.sigma[i]);
  std::printf("    bias    %.2f %.2f %.2f counts (+- %.2g)\n", r.gyro.model.bias[0], r.gyro.model.bias[1],
              r.gyro.model.bias[2], r.gyro.bias_sigma[0]);
  EXPECT_TRUE(r.acc.converged);
  EXPECT_TRUE(r.gyro.converged);
  // |g| error down by more than 100x (1.27 -> 0.008 m/s^2), gravity-direction
  // error after integration by more than 50x (40 -> 0.5 deg).
  EXPECT_LT(r.acc.after.rms, 0.01 * r.acc.before.rms);
  EXPECT_LT(r.gyro.angle_rms_after_deg, 0.02 * r.gyro.angle_rms_before_deg);
  EXPECT_LT(r.gyro.angle_rms_after_deg, 1.0);

  // imu_tk (Ceres, autodiff) on the same files with test_imu_calib's settings,
  // as printed (6 digits): "threshold multiplier 6 with residual 0.120131"
  // (Ceres prints half the sum of squares), T_a = [[1, -0.0033593,
  // -0.00890639], [0, 1, -0.0213341], [0, 0, 1]], K_a = (0.00241278,
  // 0.00242712, 0.00241168), B_a = (33124.2, 33275.2, 32364.4); gyroscope
  // residual 0.00150696, T_g = [[1, 0.00593634, 0.00111101], [0.00808812, 1,
  // -0.0535569], [0.0253067, -0.0025513, 1]], K_g = (0.000209295, 0.000209899,
  // 0.000209483), B_g = (32777.1, 32459.8, 32511.8).
  EXPECT_EQ(r.acc.th_mult, 6);
  EXPECT_NEAR(r.acc.after.cost / 2.0, 0.120131, 1e-6);
  const std::vector<double> acc_ref{0.0033593,  -0.00890639, 0.0213341, 0.00241278, 0.00242712,
                                    0.00241168, 33124.2,     33275.2,   32364.4};
  for (std::size_t i = 0; i < 9; ++i) {
    const double tol = i < 3 ? 1e-7 : i < 6 ? 1e-5 * acc_ref[i] : 0.06;
    EXPECT_NEAR(r.acc.values[i], acc_ref[i], tol) << r.acc.names[i];
  }
  // Gyroscope: the same minimum to within what Ceres' stopping rule and the
  // interval bookkeeping leave (our cost is 0.3 % lower).
  EXPECT_NEAR(r.gyro.after.cost / 2.0, 0.00150696, 2e-5);
  const Mat3 Tg = r.gyro.model.misalignment();
  const Mat3 Tg_ref{{{1.0, 0.00593634, 0.00111101}, {0.00808812, 1.0, -0.0535569}, {0.0253067, -0.0025513, 1.0}}};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) EXPECT_NEAR(Tg[i][j], Tg_ref[i][j], 1e-4) << i << j;
  const Vec3 Kg_ref{0.000209295, 0.000209899, 0.000209483};
  const Vec3 Bg_ref{32777.1, 32459.8, 32511.8};
  for (std::size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.gyro.model.scale[c], Kg_ref[c], 5e-5 * Kg_ref[c]) << c;
    EXPECT_NEAR(r.gyro.model.bias[c], Bg_ref[c], 0.06) << c;
  }
  // The reported uncertainties cover the differences from imu_tk.
  for (std::size_t c = 0; c < 3; ++c) EXPECT_LT(std::abs(r.gyro.model.scale[c] - Kg_ref[c]), r.gyro.sigma[6 + c]);
}

// Samples [from, from + count) taken out of a record: a logger that lost them.
Loaded without(const Loaded& l, std::size_t from, std::size_t count) {
  Loaded o = l;
  o.x.erase(o.x.begin() + static_cast<std::ptrdiff_t>(from), o.x.begin() + static_cast<std::ptrdiff_t>(from + count));
  o.t.erase(o.t.begin() + static_cast<std::ptrdiff_t>(from), o.t.begin() + static_cast<std::ptrdiff_t>(from + count));
  return o;
}

// On the xsens sequence the first two static intervals are samples
// [50, 5191) and [5522, 6334); between them the board turns.
TEST(MultiPosition, GyroscopeGapDuringMotionIsRefusedGapWhileStaticIsNot) {
  const Loaded acc = load(kXsens + "xsens_acc.txt", {"2", "3", "4"}, "1", 0);
  const Loaded gyro = load(kXsens + "xsens_gyro.txt", {"2", "3", "4"}, "1", 0);
  Options o;
  o.g = 9.81744;
  o.init_static_s = 50.0;
  o.acc_bias_guess = {32768.0, 32768.0, 32768.0};
  o.gyro_scale_guess = 1.0 / 6258.0;
  const AccResult ar = calibrate_accelerometer({acc.x, acc.t, 0.0}, o);
  ASSERT_EQ(ar.intervals[0].end, 5191u);
  ASSERT_EQ(ar.intervals[1].begin, 5522u);

  const Loaded moving = without(gyro, 5300, 50);  // 0.5 s of the turn lost
  try {
    calibrate_gyroscope({acc.x, acc.t, 0.0}, ar, {moving.x, moving.t, 0.0}, o);
    ADD_FAILURE() << "a gap during a motion was integrated";
  } catch (const cubecal::CalibrationError& e) {
    EXPECT_EQ(e.reason(), cubecal::CalibrationReason::bad_data);
    EXPECT_NE(std::string(e.what()).find("gap of 0.51 s"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("between static intervals 1 and 2"), std::string::npos) << e.what();
  }
  // The same loss inside the second pose touches no integral: the result is
  // that of the whole record.
  const Loaded still = without(gyro, 5700, 50);
  const GyroResult whole = calibrate_gyroscope({acc.x, acc.t, 0.0}, ar, {gyro.x, gyro.t, 0.0}, o);
  const GyroResult cut = calibrate_gyroscope({acc.x, acc.t, 0.0}, ar, {still.x, still.t, 0.0}, o);
  ASSERT_EQ(cut.values.size(), whole.values.size());
  for (std::size_t i = 0; i < whole.values.size(); ++i)
    EXPECT_NEAR(cut.values[i], whole.values[i], 1e-9 * (1.0 + std::abs(whole.values[i]))) << whole.names[i];
}

TEST(MultiPosition, Mpu6050ExampleHasTooFewPoses) {
  // example_data_calibration.csv: still for 37 s, then 9 poses of 2-4 s: 10
  // static intervals, below the 12 the method requires.
  const Loaded acc = load(kMpu, {"ax", "ay", "az"}, "", 4);
  const Loaded gyro = load(kMpu, {"gx", "gy", "gz"}, "", 4);
  ASSERT_EQ(acc.x.size(), 10245u);
  Options o;
  o.g = 9.81;
  o.init_static_s = 30.0;
  o.gyro_scale_guess = kPi / 180.0 / 131.0;  // +-250 deg/s range
  const TriadSeries sa{acc.x, {}, 100.0}, sg{gyro.x, {}, 100.0};
  try {
    (void)calibrate(sa, sg, o);
    FAIL() << "expected the too-few-intervals error";
  } catch (const cubecal::CalibrationError& e) {
    std::printf("mpu6050: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("fewer than 12 static intervals: at most 10"), std::string::npos);
  }
  // Below the paper's rule, for information: 10 intervals.
  o.min_intervals = 10;
  const Result r = calibrate(sa, sg, o);
  std::printf(
      "mpu6050 with 10 intervals (below the rule): th_mult %d; acc |g| error rms %.4g -> %.4g m/s^2; "
      "scales %.5g %.5g %.5g m/s^2/count (1 g = %.0f %.0f %.0f counts); bias %.1f %.1f %.1f counts; "
      "gyro angle rms %.3g -> %.3g deg, scales %.4g %.4g %.4g rad/s/count (nominal %.4g)\n",
      r.acc.th_mult, r.acc.before.rms, r.acc.after.rms, r.acc.model.scale[0], r.acc.model.scale[1],
      r.acc.model.scale[2], 9.81 / r.acc.model.scale[0], 9.81 / r.acc.model.scale[1], 9.81 / r.acc.model.scale[2],
      r.acc.model.bias[0], r.acc.model.bias[1], r.acc.model.bias[2], r.gyro.angle_rms_before_deg,
      r.gyro.angle_rms_after_deg, r.gyro.model.scale[0], r.gyro.model.scale[1], r.gyro.model.scale[2],
      o.gyro_scale_guess);
  EXPECT_EQ(r.acc.intervals.size(), 10u);
  EXPECT_LT(r.acc.after.rms, 0.1 * r.acc.before.rms);
  EXPECT_LT(r.gyro.angle_rms_after_deg, r.gyro.angle_rms_before_deg);
  // +-2 g range: 16384 counts per g within the datasheet's 3 % (z is 2.1 % high).
  for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(9.81 / r.acc.model.scale[c], 16384.0, 0.03 * 16384.0) << c;
}

// ---------------------------------------------------------------------------
// The command.

using cubecal::test::CliRun;
using cubecal::test::one_error_line;
CliRun run_cli(const std::string& args) { return cubecal::test::run_cubecal(args); }

const std::string kXsensArgs = "calibrate multiposition " + kXsens + "xsens_acc.txt " + kXsens +
                               "xsens_gyro.txt --acc-columns 2,3,4 --time-col 1 --g 9.81744 --init-static 50 "
                               "--acc-bias 32768 --gyro-scale 1.598e-4";

TEST(MultiPositionCli, XsensJsonAndTable) {
  const CliRun j = run_cli(kXsensArgs + " --format json");
  ASSERT_EQ(j.code, 0) << j.err;
  for (const char* key : {"\"th_mult\": 6,", "\"static_intervals\": 38,", "\"accelerometer\": {", "\"gyroscope\": {",
                          "\"name\": \"mis_zx\"", "\"angle_rms_after_deg\"", "\"converged\": true"})
    EXPECT_NE(j.out.find(key), std::string::npos) << key;
  const CliRun t = run_cli(kXsensArgs);
  ASSERT_EQ(t.code, 0) << t.err;
  std::printf("%s", t.out.c_str());
  EXPECT_NE(t.out.find("static intervals: 38 (th_mult 6"), std::string::npos);
  EXPECT_NE(t.out.find("s_x        0.0024127846 ±"), std::string::npos);
}

// A copy of an xsens file with `count` samples from `from` taken out.
std::string xsens_without(const std::string& name, std::size_t from, std::size_t count, const std::string& dir) {
  std::ifstream in(kXsens + name);
  const std::string path = dir + "/" + name;
  std::ofstream out(path);
  std::string line;
  for (std::size_t i = 0; std::getline(in, line); ++i)
    if (i < from || i >= from + count) out << line << '\n';
  return path;
}

TEST(MultiPositionCli, GapInTheTimeColumnIsRefusedAtItsLineJitterIsSaid) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("cubecal_mpgap_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string acc = xsens_without("xsens_acc.txt", 5300, 50, dir.string());
  const std::string gyro = xsens_without("xsens_gyro.txt", 5300, 50, dir.string());
  const std::string opts =
      " --acc-columns 2,3,4 --time-col 1 --g 9.81744 --init-static 50 --acc-bias 32768 "
      "--gyro-scale 1.598e-4";
  const CliRun r = run_cli("calibrate multiposition " + acc + " " + gyro + opts);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  // Sample 5300 of the cut file (line 5301) follows 0.51 s after the last kept one.
  EXPECT_NE(r.err.find(acc + ":5301:4: gap of 0.51 s (51 periods of 0.01 s)"), std::string::npos) << r.err;
  // The real record's irregular intervals (up to 10 % off) are used and said.
  const CliRun ok = run_cli(kXsensArgs);
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.err.find("xsens_gyro.txt:6472: 53 of 51174 time intervals differ from the period 0.01 s by more "
                        "than 1 % (largest 10 %)"),
            std::string::npos)
      << ok.err;
  fs::remove_all(dir);
}

TEST(MultiPositionCli, OneFileWithBothTriadsAndTooFewPoses) {
  const CliRun r = run_cli("calibrate multiposition " + kMpu +
                           " --skip-rows 4 --acc-columns ax,ay,az --gyro-columns gx,gy,gz --rate 100 --g 9.81 "
                           "--init-static 30 --gyro-scale 1.3323e-4");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("fewer than 12 static intervals"), std::string::npos) << r.err;
  const CliRun ok = run_cli("calibrate multiposition " + kMpu +
                            " --skip-rows 4 --acc-columns ax,ay,az --gyro-columns gx,gy,gz --rate 100 --g 9.81 "
                            "--init-static 30 --gyro-scale 1.3323e-4 --min-intervals 10");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.out.find("gyroscope (same file)"), std::string::npos);
}

TEST(MultiPositionCli, UsageErrorsAndNoOverwrite) {
  const CliRun both = run_cli(kXsensArgs + " --rate 100");
  EXPECT_EQ(both.code, 2);
  EXPECT_TRUE(one_error_line(both)) << both.err;
  const CliRun none = run_cli("calibrate multiposition " + kXsens + "xsens_acc.txt --acc-columns 2,3,4");
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("--time-col"), std::string::npos) << none.err;
  const CliRun cols = run_cli("calibrate multiposition " + kXsens + "xsens_acc.txt --acc-columns 2,3 --time-col 1");
  EXPECT_EQ(cols.code, 2);
  EXPECT_TRUE(one_error_line(cols)) << cols.err;

  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("cubecal_mp_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "cal.json").string();
  std::ofstream(out) << "keep";
  const std::string acc_only = "calibrate multiposition " + kXsens +
                               "xsens_acc.txt --acc-columns 2,3,4 --time-col 1 --g 9.81744 --acc-bias 32768 "
                               "--format json --out " +
                               out;
  const CliRun refused = run_cli(acc_only);
  EXPECT_EQ(refused.code, 2);
  EXPECT_TRUE(one_error_line(refused)) << refused.err;
  std::ifstream in(out);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "keep");
  const CliRun forced = run_cli(acc_only + " --force");
  EXPECT_EQ(forced.code, 0) << forced.err;
  std::ifstream in2(out);
  std::stringstream ss;
  ss << in2.rdbuf();
  EXPECT_NE(ss.str().find("\"gyroscope\": null"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
