// The JSON form of every calibration and runs result (pipeline/*_json.hpp):
// <result>_from_json(to_json(r)) gives back every field of a result the pipeline
// computed on a record, through the text the CLI prints.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/pipeline/calibrate_mag.hpp"
#include "cubecal/pipeline/calibrate_mag_json.hpp"
#include "cubecal/pipeline/calibrate_multiposition.hpp"
#include "cubecal/pipeline/calibrate_multiposition_json.hpp"
#include "cubecal/pipeline/calibrate_rate_table.hpp"
#include "cubecal/pipeline/calibrate_rate_table_json.hpp"
#include "cubecal/pipeline/calibrate_temperature.hpp"
#include "cubecal/pipeline/calibrate_temperature_json.hpp"
#include "cubecal/pipeline/turnon.hpp"
#include "cubecal/pipeline/turnon_json.hpp"

namespace cubecal {
namespace {

// Each result's reader, by the result's type.
pipeline::RateTableResult read_back(const nlohmann::json& j, const pipeline::RateTableResult&) {
  return pipeline::rate_table_result_from_json(j);
}
pipeline::MagResult read_back(const nlohmann::json& j, const pipeline::MagResult&) {
  return pipeline::mag_result_from_json(j);
}
pipeline::MultipositionResult read_back(const nlohmann::json& j, const pipeline::MultipositionResult&) {
  return pipeline::multiposition_result_from_json(j);
}
pipeline::TemperatureResult read_back(const nlohmann::json& j, const pipeline::TemperatureResult&) {
  return pipeline::temperature_result_from_json(j);
}
pipeline::TurnOnResult read_back(const nlohmann::json& j, const pipeline::TurnOnResult&) {
  return pipeline::turn_on_result_from_json(j);
}

// Through the printed text, as a later run reads it.
template <class Result>
Result round_trip(const Result& r) {
  const nlohmann::json j = pipeline::to_json(r);
  return read_back(nlohmann::json::parse(j.dump(2)), r);
}

// ---------------------------------------------------------------------------
// calibrate rate-table

// 0, +-10, +-100 deg/s about each axis, 60 s plateaus at 10 Hz with 10 s
// ramps; the gyro sees S w + b + noise; reference columns as Series::extra.
io::Series rate_table_series() {
  const Mat3 S{{{1.002, 0.003, -0.001}, {0.002, 0.998, 0.004}, {-0.003, 0.001, 1.001}}};
  const Vec3 b{0.1, -0.05, 0.02};
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  io::Series s;
  s.file = "rate_table.csv";
  s.rate_hz = 10.0;
  s.tau0 = 0.1;
  s.names = {"gx", "gy", "gz"};
  s.channels.resize(3);
  s.extra_names = {"rx", "ry", "rz"};
  s.extra.resize(3);
  const auto add = [&](const Vec3& w, const Vec3& ref, int n) {
    for (int k = 0; k < n; ++k) {
      s.time.push_back(static_cast<double>(s.time.size()) * 0.1);
      for (int i = 0; i < 3; ++i) {
        s.channels[i].push_back(S[i][0] * w[0] + S[i][1] * w[1] + S[i][2] * w[2] + b[i] + noise(rng));
        s.extra[i].push_back(ref[i]);
      }
    }
  };
  for (int axis = 0; axis < 3; ++axis)
    for (double rate : {0.0, 10.0, -10.0, 100.0, -100.0}) {
      Vec3 w{};
      w[axis] = rate;
      add(w, w, 600);
      add({0.5 * w[0], 0.5 * w[1], 0.5 * w[2]}, {1000.0 + w[0], w[1], w[2]}, 100);
    }
  s.segments = {{0, s.time.size()}};
  return s;
}

TEST(CalibrationJson, RateTableRoundTrip) {
  pipeline::RateTableRequest req;
  req.earth_axis = std::array<double, 3>{0.0, 0.6, 0.8};
  const pipeline::RateTableResult r = pipeline::calibrate_rate_table(rate_table_series(), req);
  ASSERT_EQ(r.found.plateaus.size(), 15u);
  const pipeline::RateTableResult b = round_trip(r);
  EXPECT_EQ(b.file, r.file);
  EXPECT_EQ(b.unit, r.unit);
  EXPECT_EQ(b.source, r.source);
  EXPECT_EQ(b.earth_rate, r.earth_rate);
  EXPECT_NE(r.earth_rate[2], 0.0);
  ASSERT_EQ(b.found.plateaus.size(), r.found.plateaus.size());
  for (std::size_t k = 0; k < r.found.plateaus.size(); ++k) {
    const Plateau &p = r.found.plateaus[k], &q = b.found.plateaus[k];
    EXPECT_EQ(q.begin, p.begin);
    EXPECT_EQ(q.end, p.end);
    EXPECT_EQ(q.t_begin, p.t_begin);
    EXPECT_EQ(q.t_end, p.t_end);
    EXPECT_EQ(q.n, p.n);
    EXPECT_EQ(q.mean, p.mean);
    EXPECT_EQ(q.stddev, p.stddev);
    EXPECT_EQ(q.cov, p.cov);
    EXPECT_EQ(q.ref, p.ref);
    EXPECT_EQ(q.has_ref, p.has_ref);
  }
  EXPECT_EQ(b.found.dropped_short, r.found.dropped_short);
  EXPECT_EQ(b.found.unmatched, r.found.unmatched);
  EXPECT_EQ(b.found.skipped_rows, r.found.skipped_rows);
  EXPECT_EQ(b.found.noise, r.found.noise);
  const RateTableCalibration &c = r.calibration, &d = b.calibration;
  EXPECT_EQ(d.plateaus, c.plateaus);
  EXPECT_EQ(d.dof, c.dof);
  EXPECT_EQ(d.noise_from_residuals, c.noise_from_residuals);
  EXPECT_EQ(d.noise_cov, c.noise_cov);
  EXPECT_EQ(d.S, c.S);
  EXPECT_EQ(d.bias, c.bias);
  EXPECT_EQ(d.S_sigma, c.S_sigma);
  EXPECT_EQ(d.bias_sigma, c.bias_sigma);
  EXPECT_EQ(d.forward_cov, c.forward_cov);
  EXPECT_EQ(d.A, c.A);
  EXPECT_EQ(d.beta, c.beta);
  EXPECT_EQ(d.A_sigma, c.A_sigma);
  EXPECT_EQ(d.beta_sigma, c.beta_sigma);
  EXPECT_EQ(d.inverse_cov, c.inverse_cov);
  EXPECT_EQ(d.scale_factor_error, c.scale_factor_error);
  EXPECT_EQ(d.scale_factor_error_sigma, c.scale_factor_error_sigma);
  EXPECT_EQ(d.misalignment, c.misalignment);
  EXPECT_EQ(d.misalignment_sigma, c.misalignment_sigma);
  EXPECT_EQ(d.residual_before.max_abs, c.residual_before.max_abs);
  EXPECT_EQ(d.residual_before.rms, c.residual_before.rms);
  EXPECT_EQ(d.residual_after.max_abs, c.residual_after.max_abs);
  EXPECT_EQ(d.residual_after.rms, c.residual_after.rms);
  EXPECT_EQ(d.residuals_after, c.residuals_after);
  EXPECT_EQ(d.error_covariance, c.error_covariance);
}

TEST(CalibrationJson, RateTableErrorsByType) {
  io::Series s = rate_table_series();
  s.channels.pop_back();
  try {
    pipeline::calibrate_rate_table(s, {});
    ADD_FAILURE() << "2 gyro channels accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::columns);
  }
  pipeline::RateTableRequest req;
  req.plateaus.min_plateau_s = 1000.0;  // longer than every plateau
  try {
    pipeline::calibrate_rate_table(rate_table_series(), req);
    ADD_FAILURE() << "plateaus shorter than the minimum accepted";
  } catch (const CalibrationError& e) {
    EXPECT_EQ(e.reason(), CalibrationReason::no_plateaus);
  }
}

// ---------------------------------------------------------------------------
// calibrate mag

// Points on an ellipsoid (soft iron, offset, noise) over the whole sphere, in
// counts, as a table read with a field column; two outliers.
io::Table mag_table() {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01(0.0, 1.0);
  io::Table t;
  t.file = "mag.csv";
  t.names = {"mx", "my", "mz"};
  t.data.resize(3);
  t.extra_names = {"F"};
  t.extra.resize(1);
  t.first_data_line = 2;
  for (int k = 0; k < 400; ++k) {
    Vec3 u{n01(rng), n01(rng), n01(rng)};
    const double norm = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const double f = k == 17 || k == 301 ? 90.0 : 45.0;
    const Vec3 h{1.05 * f * u[0] / norm + 0.02 * f * u[1] / norm + 3.0, 0.97 * f * u[1] / norm - 2.0,
                 1.01 * f * u[2] / norm + 1.5};
    for (int i = 0; i < 3; ++i) t.data[i].push_back(1000.0 * (h[i] + 0.05 * n01(rng)));
    t.extra[0].push_back(45.0);
  }
  return t;
}

void expect_same(const pipeline::MagResult& b, const pipeline::MagResult& m) {
  EXPECT_EQ(b.file, m.file);
  EXPECT_EQ(b.unit, m.unit);
  EXPECT_EQ(b.field_source, m.field_source);
  EXPECT_EQ(b.first_data_line, m.first_data_line);
  // The input points and per-point field norms are the input file's
  // content: the JSON names the file and leaves them out.
  EXPECT_TRUE(b.points.empty());
  EXPECT_EQ(m.points.size(), m.calibration.points_used + m.calibration.points_rejected);
  EXPECT_TRUE(b.field_norms.empty());
  const mag::Result &r = m.calibration, &q = b.calibration;
  EXPECT_EQ(q.method, r.method);
  EXPECT_EQ(q.bias, r.bias);
  EXPECT_EQ(q.bias_sigma, r.bias_sigma);
  EXPECT_EQ(q.soft_iron, r.soft_iron);
  EXPECT_EQ(q.soft_iron_sigma, r.soft_iron_sigma);
  EXPECT_EQ(q.covariance, r.covariance);
  EXPECT_EQ(q.covariance_names, r.covariance_names);
  EXPECT_EQ(q.field_norm, r.field_norm);
  EXPECT_EQ(q.field_norm_default, r.field_norm_default);
  EXPECT_EQ(q.field_norm_per_point, r.field_norm_per_point);
  EXPECT_EQ(q.semi_axes, r.semi_axes);
  EXPECT_EQ(q.axis_ratio, r.axis_ratio);
  for (const auto& [x, y] : {std::pair{q.before, r.before}, std::pair{q.after, r.after}}) {
    EXPECT_EQ(x.mean, y.mean);
    EXPECT_EQ(x.rms, y.rms);
    EXPECT_EQ(x.max, y.max);
  }
  EXPECT_EQ(q.chi2, r.chi2);
  EXPECT_EQ(q.dof, r.dof);
  EXPECT_EQ(q.p_value, r.p_value);
  EXPECT_EQ(q.noise, r.noise);
  EXPECT_EQ(q.noise_estimated, r.noise_estimated);
  EXPECT_EQ(q.iterations, r.iterations);
  EXPECT_EQ(q.converged, r.converged);
  EXPECT_EQ(q.eta, r.eta);
  EXPECT_EQ(q.points_used, r.points_used);
  EXPECT_EQ(q.points_rejected, r.points_rejected);
  EXPECT_EQ(q.rejected, r.rejected);
  EXPECT_EQ(q.reject_sigma, r.reject_sigma);
  EXPECT_EQ(q.coverage.centre, r.coverage.centre);
  EXPECT_EQ(q.coverage.centre_from_sphere_fit, r.coverage.centre_from_sphere_fit);
  EXPECT_EQ(q.coverage.resultant, r.coverage.resultant);
  EXPECT_EQ(q.coverage.lambda_min, r.coverage.lambda_min);
  EXPECT_EQ(q.coverage.spread, r.coverage.spread);
  EXPECT_EQ(q.coverage.octants, r.coverage.octants);
  EXPECT_EQ(q.notes, r.notes);
}

TEST(CalibrationJson, MagRoundTrip) {
  pipeline::MagRequest req;
  req.counts_per_unit = 1000.0;
  req.reject_sigma = 3.0;
  req.unit = "uT";
  const pipeline::MagResult r = pipeline::calibrate_mag(mag_table(), req);
  EXPECT_EQ(r.calibration.rejected, (std::vector<std::size_t>{17, 301}));
  EXPECT_FALSE(r.calibration.p_value.has_value());
  expect_same(round_trip(r), r);

  // TWOSTEP with a field per point and a given noise: the p-value and the
  // field column travel too.
  req.method = mag::Method::twostep_full;
  req.field_column = true;
  req.noise = 0.05;
  req.reject_sigma = 0.0;
  req.unit.clear();
  const pipeline::MagResult t = pipeline::calibrate_mag(mag_table(), req);
  EXPECT_TRUE(t.calibration.p_value.has_value());
  EXPECT_EQ(t.field_source, pipeline::FieldNormSource::column);
  EXPECT_EQ(t.field_norms.size(), 400u);
  expect_same(round_trip(t), t);
}

TEST(CalibrationJson, MagRequestErrorsNameTheField) {
  pipeline::MagRequest req;
  req.counts_per_unit = 0.0;
  try {
    pipeline::calibrate_mag(mag_table(), req);
    ADD_FAILURE() << "zero counts per unit accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::counts_per_unit);
  }
  req = {};
  req.field_column = true;  // with the ellipsoid method
  try {
    pipeline::calibrate_mag(mag_table(), req);
    ADD_FAILURE() << "a field column accepted with the ellipsoid fit";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::field_column);
  }
}

// ---------------------------------------------------------------------------
// calibrate multiposition

const std::string kXsens = std::string(CUBECAL_SHARED_DATA) + "/imu/xsens-multiposition/";

pipeline::TriadSamples xsens(const std::string& name) {
  io::TableOptions to;
  to.columns = {"2", "3", "4"};
  to.extra_columns = {"1"};
  const io::Table t = io::read_table(kXsens + name, to);
  pipeline::TriadSamples s;
  s.file = t.file;
  s.t = t.extra[0];
  for (std::size_t i = 0; i < t.rows(); ++i) s.x.push_back({t.data[0][i], t.data[1][i], t.data[2][i]});
  return s;
}

void expect_same(const multipos::TriadCalibration& b, const multipos::TriadCalibration& m) {
  EXPECT_EQ(b.mis_yz, m.mis_yz);
  EXPECT_EQ(b.mis_zy, m.mis_zy);
  EXPECT_EQ(b.mis_zx, m.mis_zx);
  EXPECT_EQ(b.mis_xz, m.mis_xz);
  EXPECT_EQ(b.mis_xy, m.mis_xy);
  EXPECT_EQ(b.mis_yx, m.mis_yx);
  EXPECT_EQ(b.scale, m.scale);
  EXPECT_EQ(b.bias, m.bias);
}

void expect_same(const multipos::Residuals& b, const multipos::Residuals& r) {
  EXPECT_EQ(b.count, r.count);
  EXPECT_EQ(b.cost, r.cost);
  EXPECT_EQ(b.rms, r.rms);
  EXPECT_EQ(b.max, r.max);
}

TEST(CalibrationJson, MultipositionRoundTrip) {
  pipeline::MultipositionRequest req;
  req.options.g = 9.81744;
  req.options.acc_bias_guess = {32768.0, 32768.0, 32768.0};
  req.options.gyro_scale_guess = 1.598e-4;
  req.options.refine_gyro_bias = true;
  const pipeline::MultipositionResult r =
      pipeline::calibrate_multiposition(xsens("xsens_acc.txt"), xsens("xsens_gyro.txt"), req);
  ASSERT_TRUE(r.gyroscope.has_value());
  EXPECT_EQ(r.gyroscope->names.size(), 12u);
  EXPECT_EQ(r.accelerometer.intervals.size(), 38u);
  const pipeline::MultipositionResult b = round_trip(r);

  EXPECT_EQ(b.acc_file, r.acc_file);
  EXPECT_EQ(b.gyro_file, r.gyro_file);
  EXPECT_EQ(b.samples, r.samples);
  EXPECT_EQ(b.rate_hz, r.rate_hz);
  EXPECT_EQ(b.interval_times, r.interval_times);
  const multipos::Options &o = r.options, &p = b.options;
  EXPECT_EQ(p.g, o.g);
  EXPECT_EQ(p.init_static_s, o.init_static_s);
  EXPECT_EQ(p.window, o.window);
  EXPECT_EQ(p.interval_samples, o.interval_samples);
  EXPECT_EQ(p.min_intervals, o.min_intervals);
  EXPECT_EQ(p.th_mult_min, o.th_mult_min);
  EXPECT_EQ(p.th_mult_max, o.th_mult_max);
  EXPECT_EQ(p.acc_use_means, o.acc_use_means);
  EXPECT_EQ(p.acc_bias_guess, o.acc_bias_guess);
  EXPECT_EQ(p.acc_scale_guess, o.acc_scale_guess);
  EXPECT_EQ(p.gyro_scale_guess, o.gyro_scale_guess);
  EXPECT_EQ(p.refine_gyro_bias, o.refine_gyro_bias);
  EXPECT_EQ(p.max_iterations, o.max_iterations);

  const multipos::AccResult &a = r.accelerometer, &c = b.accelerometer;
  expect_same(c.model, a.model);
  expect_same(c.initial, a.initial);
  EXPECT_EQ(c.names, a.names);
  EXPECT_EQ(c.values, a.values);
  EXPECT_EQ(c.sigma, a.sigma);
  EXPECT_EQ(c.covariance, a.covariance);
  EXPECT_EQ(c.init_samples, a.init_samples);
  EXPECT_EQ(c.init_variance_norm, a.init_variance_norm);
  EXPECT_EQ(c.th_mult, a.th_mult);
  EXPECT_EQ(c.threshold, a.threshold);
  ASSERT_EQ(c.trials.size(), a.trials.size());
  for (std::size_t k = 0; k < a.trials.size(); ++k) {
    EXPECT_EQ(c.trials[k].th_mult, a.trials[k].th_mult);
    EXPECT_EQ(c.trials[k].threshold, a.trials[k].threshold);
    EXPECT_EQ(c.trials[k].intervals, a.trials[k].intervals);
    EXPECT_EQ(c.trials[k].fitted, a.trials[k].fitted);
    EXPECT_EQ(c.trials[k].cost, a.trials[k].cost);
  }
  EXPECT_EQ(c.intervals, a.intervals);
  expect_same(c.before, a.before);
  expect_same(c.after, a.after);
  EXPECT_EQ(c.sigma0, a.sigma0);
  EXPECT_EQ(c.iterations, a.iterations);
  EXPECT_EQ(c.converged, a.converged);

  const multipos::GyroResult &g = *r.gyroscope, &h = *b.gyroscope;
  expect_same(h.model, g.model);
  expect_same(h.initial, g.initial);
  EXPECT_EQ(h.names, g.names);
  EXPECT_EQ(h.values, g.values);
  EXPECT_EQ(h.sigma, g.sigma);
  EXPECT_EQ(h.sigma_fit, g.sigma_fit);
  EXPECT_EQ(h.covariance, g.covariance);
  EXPECT_EQ(h.init_samples, g.init_samples);
  EXPECT_EQ(h.init_bias, g.init_bias);
  EXPECT_EQ(h.init_bias_sigma, g.init_bias_sigma);
  EXPECT_EQ(h.bias_sigma, g.bias_sigma);
  EXPECT_EQ(h.pairs, g.pairs);
  expect_same(h.before, g.before);
  expect_same(h.after, g.after);
  EXPECT_EQ(h.angle_rms_before_deg, g.angle_rms_before_deg);
  EXPECT_EQ(h.angle_rms_after_deg, g.angle_rms_after_deg);
  EXPECT_EQ(h.angle_max_after_deg, g.angle_max_after_deg);
  EXPECT_EQ(h.sigma0, g.sigma0);
  EXPECT_EQ(h.iterations, g.iterations);
  EXPECT_EQ(h.converged, g.converged);
}

TEST(CalibrationJson, MultipositionNeedsTimeStampsOrARate) {
  pipeline::TriadSamples acc = xsens("xsens_acc.txt");
  pipeline::MultipositionRequest req;
  req.rate_hz = 100.0;  // and time stamps
  try {
    pipeline::calibrate_multiposition_accelerometer(acc, req);
    ADD_FAILURE() << "time stamps and a rate accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::sampling);
  }
  acc.t.clear();
  req.rate_hz = 0.0;
  EXPECT_THROW(pipeline::calibrate_multiposition_accelerometer(acc, req), UsageError);
}

// ---------------------------------------------------------------------------
// calibrate temperature

// Two channels with bias 0.7 and -0.2 per degC and a quadratic term, over a
// temperature sine; white noise.
io::Series temperature_series() {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  io::Series s;
  s.file = "temp.csv";
  s.rate_hz = 1.0;
  s.tau0 = 1.0;
  s.names = {"gx", "gy"};
  s.channels.resize(2);
  s.extra_names = {"temp"};
  s.extra.resize(1);
  for (int k = 0; k < 5000; ++k) {
    const double T = 25.0 + 10.0 * std::sin(k / 400.0);
    s.extra[0].push_back(T);
    s.channels[0].push_back(3.0 + 0.7 * (T - 25.0) + 0.01 * (T - 25.0) * (T - 25.0) + noise(rng));
    s.channels[1].push_back(-1.0 - 0.2 * (T - 25.0) + noise(rng));
  }
  s.segments = {{0, 5000}};
  return s;
}

TEST(CalibrationJson, TemperatureRoundTrip) {
  pipeline::TemperatureRequest req;
  req.order = 2;
  req.unit = "deg/h";
  const pipeline::TemperatureResult r = pipeline::calibrate_temperature(temperature_series(), req);
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_NEAR(r.channels[0].fit.coeff[1], 0.7, 5 * r.channels[0].fit.coeff_sigma[1]);
  EXPECT_EQ(r.channels[0].coeff_units[2], "deg/h/degC^2");
  const pipeline::TemperatureResult b = round_trip(r);
  EXPECT_EQ(b.file, r.file);
  EXPECT_EQ(b.temperature_column, r.temperature_column);
  EXPECT_EQ(b.order, r.order);
  EXPECT_EQ(b.unit, r.unit);
  EXPECT_EQ(b.samples, r.samples);
  ASSERT_EQ(b.channels.size(), r.channels.size());
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    EXPECT_EQ(b.channels[c].name, r.channels[c].name);
    EXPECT_EQ(b.channels[c].coeff_units, r.channels[c].coeff_units);
    const TemperatureFit &f = r.channels[c].fit, &g = b.channels[c].fit;
    EXPECT_EQ(g.t_ref, f.t_ref);
    EXPECT_EQ(g.coeff, f.coeff);
    EXPECT_EQ(g.coeff_sigma, f.coeff_sigma);
    EXPECT_EQ(g.cov, f.cov);
    EXPECT_EQ(g.residual_rms, f.residual_rms);
    EXPECT_EQ(g.r2, f.r2);
    EXPECT_EQ(g.order, f.order);
  }
}

TEST(CalibrationJson, TemperatureErrorsNameTheChannelOrTheField) {
  pipeline::TemperatureRequest req;
  req.order = 6;
  try {
    pipeline::calibrate_temperature(temperature_series(), req);
    ADD_FAILURE() << "order 6 accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.field(), cubecal::Field::order);
  }
  io::Series s = temperature_series();
  std::fill(s.extra[0].begin(), s.extra[0].end(), 20.0);
  try {
    pipeline::calibrate_temperature(s, {});
    ADD_FAILURE() << "a constant temperature accepted";
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()).rfind("gx: ", 0), 0u) << e.what();
  }
}

// ---------------------------------------------------------------------------
// turnon, compare

// A run of a two-axis gyro: white noise plus a bias random walk and a
// per-run bias, 10 Hz, 2 h (long enough for a minimum of the Allan curve).
io::Series gyro_run(int seed, const std::string& file) {
  std::mt19937_64 rng(static_cast<unsigned>(seed));
  std::normal_distribution<double> n01(0.0, 1.0);
  io::Series s;
  s.file = file;
  s.rate_hz = 10.0;
  s.tau0 = 0.1;
  s.names = {"gx", "gy"};
  s.channels.resize(2);
  for (int c = 0; c < 2; ++c) {
    double walk = 0.05 * n01(rng);
    for (int k = 0; k < 72000; ++k) {
      walk += 2e-4 * n01(rng);
      s.channels[c].push_back(0.3 * c + walk + 0.01 * n01(rng));
    }
  }
  s.segments = {{0, 72000}};
  return s;
}

void expect_same(const pipeline::RunSummary& b, const pipeline::RunSummary& r) {
  EXPECT_EQ(b.file, r.file);
  EXPECT_EQ(b.samples, r.samples);
  EXPECT_EQ(b.rate_hz, r.rate_hz);
  ASSERT_EQ(b.channels.size(), r.channels.size());
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const pipeline::RunChannel &x = b.channels[c], &y = r.channels[c];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.unit.name, y.unit.name);
    EXPECT_EQ(x.unit.kind, y.unit.kind);
    EXPECT_EQ(x.unit.to_si, y.unit.to_si);
    EXPECT_EQ(x.unit.si_name, y.unit.si_name);
    EXPECT_EQ(x.mean, y.mean);
    EXPECT_EQ(x.stddev, y.stddev);
    ASSERT_EQ(x.adev.size(), y.adev.size());
    for (std::size_t i = 0; i < y.adev.size(); ++i) {
      EXPECT_EQ(x.adev[i].m, y.adev[i].m);
      EXPECT_EQ(x.adev[i].tau, y.adev[i].tau);
      EXPECT_EQ(x.adev[i].dev, y.adev[i].dev);
      EXPECT_EQ(x.adev[i].n, y.adev[i].n);
      EXPECT_EQ(x.adev[i].interval.lo, y.adev[i].interval.lo);
      EXPECT_EQ(x.adev[i].interval.hi, y.adev[i].interval.hi);
      EXPECT_EQ(x.adev[i].edf, y.adev[i].edf);
      EXPECT_EQ(x.adev[i].alpha, y.adev[i].alpha);
    }
    const SlopeReadOffs &p = x.readoffs, &q = y.readoffs;
    for (const auto& [t, u] :
         {std::pair{p.Q, q.Q}, std::pair{p.N, q.N}, std::pair{p.B, q.B}, std::pair{p.K, q.K}, std::pair{p.R, q.R}}) {
      EXPECT_EQ(t.valid, u.valid);
      EXPECT_EQ(t.value, u.value);
      EXPECT_EQ(t.sigma, u.sigma);
      EXPECT_EQ(t.tau_lo, u.tau_lo);
      EXPECT_EQ(t.tau_hi, u.tau_hi);
    }
    EXPECT_EQ(p.tau_min, q.tau_min);
    EXPECT_EQ(p.tau_min_lo, q.tau_min_lo);
    EXPECT_EQ(p.tau_min_hi, q.tau_min_hi);
    EXPECT_EQ(p.sigma_min, q.sigma_min);
  }
}

pipeline::AnalyzeRequest runs_request() {
  pipeline::AnalyzeRequest req;
  req.units = {*parse_unit("deg/s")};
  req.grid = parse_tau_grid("log:10");
  return req;
}

TEST(CalibrationJson, TurnOnRoundTrip) {
  const std::vector<io::Series> runs{gyro_run(1, "run1.csv"), gyro_run(2, "run2.csv"), gyro_run(3, "run3.csv")};
  const pipeline::TurnOnResult t = pipeline::run_turnon(runs, runs_request());
  ASSERT_EQ(t.runs.size(), 3u);
  ASSERT_FALSE(t.runs[0].channels[0].adev.empty());
  EXPECT_TRUE(t.runs[0].channels[0].readoffs.N.valid);
  const pipeline::TurnOnResult b = round_trip(t);
  EXPECT_EQ(b.ci, t.ci);
  EXPECT_EQ(b.names, t.names);
  ASSERT_EQ(b.units.size(), t.units.size());
  for (std::size_t c = 0; c < t.units.size(); ++c) {
    EXPECT_EQ(b.units[c].name, t.units[c].name);
    EXPECT_EQ(b.units[c].kind, t.units[c].kind);
    EXPECT_EQ(b.units[c].to_si, t.units[c].to_si);
    EXPECT_EQ(b.units[c].si_name, t.units[c].si_name);
  }
  EXPECT_EQ(b.mean_bias, t.mean_bias);
  EXPECT_EQ(b.turn_on, t.turn_on);
  EXPECT_EQ(b.turn_on_interval, t.turn_on_interval);
  ASSERT_EQ(b.runs.size(), t.runs.size());
  for (std::size_t k = 0; k < t.runs.size(); ++k) expect_same(b.runs[k], t.runs[k]);
}

// Each sensor kind comes back as itself: acceleration was written as
// "field" and a magnetometer read back as an accelerometer.
TEST(CalibrationJson, TurnOnUnitKindsRoundTrip) {
  const std::vector<io::Series> runs{gyro_run(1, "run1.csv"), gyro_run(2, "run2.csv")};
  for (const char* unit : {"deg/s", "mGauss", "g", "counts"}) {
    pipeline::AnalyzeRequest req = runs_request();
    req.units = {*parse_unit(unit)};
    const pipeline::TurnOnResult t = pipeline::run_turnon(runs, req);
    const pipeline::TurnOnResult b = round_trip(t);
    ASSERT_EQ(b.units.size(), t.units.size());
    for (std::size_t c = 0; c < t.units.size(); ++c) EXPECT_EQ(b.units[c].kind, t.units[c].kind) << unit;
  }
}

TEST(CalibrationJson, CompareRoundTrip) {
  const std::vector<io::Series> runs{gyro_run(4, "a.csv"), gyro_run(5, "b.csv")};
  const std::vector<pipeline::RunSummary> r = pipeline::run_compare(runs, runs_request());
  const nlohmann::json j = nlohmann::json::parse(pipeline::to_json(r).dump(1));
  std::vector<pipeline::RunSummary> b;
  for (const nlohmann::json& run : j.at("runs")) b.push_back(pipeline::run_summary_from_json(run));
  ASSERT_EQ(b.size(), 2u);
  for (std::size_t k = 0; k < r.size(); ++k) expect_same(b[k], r[k]);
}

}  // namespace
}  // namespace cubecal
