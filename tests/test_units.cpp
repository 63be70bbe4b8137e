// Units: the unit a column name announces (noise/unit_from_name), the
// accelerometer terms in navigation units (closed form, 1 g = 9.80665 m/s^2),
// deg/h data, and which B to trust when the read-off and the fit disagree
// (noise/bias_verdict).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cubecal/noise/bias_verdict.hpp"
#include "cubecal/noise/unit_from_name.hpp"
#include "cubecal/noise/units.hpp"

namespace {

using namespace cubecal;

std::string unit_of(const std::string& name) {
  const auto u = unit_from_column_name(name);
  return u ? u->name : std::string("none");
}

TEST(UnitFromName, CommonSuffixes) {
  EXPECT_EQ(unit_of("gyro_x_dps"), "deg/s");
  EXPECT_EQ(unit_of("gx_DPS"), "deg/s");
  EXPECT_EQ(unit_of("gx_degps"), "deg/s");
  EXPECT_EQ(unit_of("gyro_x_deg_s"), "deg/s");
  EXPECT_EQ(unit_of("wx_rads"), "rad/s");
  EXPECT_EQ(unit_of("wx_rad_s"), "rad/s");
  EXPECT_EQ(unit_of("fog_z_dph"), "deg/h");
  EXPECT_EQ(unit_of("acc_x_g"), "g");
  EXPECT_EQ(unit_of("ax_mps2"), "m/s^2");
  EXPECT_EQ(unit_of("ax_ms2"), "m/s^2");
  EXPECT_EQ(unit_of("mag_x_uT"), "uT");
  EXPECT_EQ(unit_of("mag_x_ut"), "uT");
  EXPECT_EQ(unit_of("mx_mG"), "mGauss");
  EXPECT_EQ(unit_of("mx_mgauss"), "mGauss");
  EXPECT_EQ(unit_of("mx_nT"), "nT");
  EXPECT_EQ(unit_of("gx_counts"), "counts");
  EXPECT_EQ(unit_of("gyro.x.dps"), "deg/s");
}

TEST(UnitFromName, BracketsAndParentheses) {
  EXPECT_EQ(unit_of("gx[deg/s]"), "deg/s");
  EXPECT_EQ(unit_of("gyro x (rad/s)"), "rad/s");
  EXPECT_EQ(unit_of("ax [m/s^2]"), "m/s^2");
  EXPECT_EQ(unit_of("mx (mG)"), "mGauss");
  EXPECT_EQ(unit_of("gx[furlongs]"), "none");
}

TEST(UnitFromName, AmbiguousOrAbsentIsNone) {
  EXPECT_EQ(unit_of("gx"), "none");
  EXPECT_EQ(unit_of("ax"), "none");
  EXPECT_EQ(unit_of("col3"), "none");
  EXPECT_EQ(unit_of("dps"), "none");       // a suffix needs a name before it
  EXPECT_EQ(unit_of("gxdps"), "none");     // and a separator
  EXPECT_EQ(unit_of("acc_x_G"), "none");   // G: gauss or g?
  EXPECT_EQ(unit_of("acc_x_mg"), "none");  // mg: milli-g or milligauss?
  EXPECT_EQ(unit_of("magx"), "none");
}

TEST(UnitFromName, InferUnitsNamesTheColumnsWithout) {
  const InferredUnits all = infer_units({"gyro_x_dps", "acc_x_g"});
  EXPECT_TRUE(all.missing.empty());
  ASSERT_EQ(all.units.size(), 2u);
  EXPECT_EQ(all.units[0].name, "deg/s");
  EXPECT_EQ(all.units[1].kind, SensorKind::acceleration);
  const InferredUnits some = infer_units({"gyro_x_dps", "ax", "ay"});
  EXPECT_EQ(some.missing, (std::vector<std::string>{"ax", "ay"}));
  EXPECT_TRUE(some.units.empty());
}

TermEstimate value(double v, double s = 0.0) {
  TermEstimate t;
  t.valid = true;
  t.value = v;
  t.sigma = s;
  return t;
}

TEST(AccelerometerUnits, ClosedForm) {
  constexpr double g0 = 9.80665;
  const Unit g = *parse_unit("g");
  // N = 1e-4 g*sqrt(s) = 1e-4 g/sqrt(Hz) = 100 ug/sqrt(Hz);
  // in m/s/sqrt(h): 1e-4 * 9.80665 m/s^2*sqrt(s) = 9.80665e-4 m/s/sqrt(s) = 60 * that per sqrt(h).
  const auto N = accelerometer_display(value(1e-4, 1e-6), Term::N, g);
  ASSERT_EQ(N.size(), 2u);
  EXPECT_EQ(N[0].unit, "m/s/sqrt(h)");
  EXPECT_NEAR(N[0].value, 1e-4 * g0 * 60.0, 1e-15);
  EXPECT_NEAR(N[0].sigma, 1e-6 * g0 * 60.0, 1e-17);
  EXPECT_EQ(N[1].unit, "ug/sqrt(Hz)");
  EXPECT_NEAR(N[1].value, 100.0, 1e-10);
  // B = 5e-4 g = 500 ug = 0.5 mg.
  const auto B = accelerometer_display(value(5e-4), Term::B, g);
  ASSERT_EQ(B.size(), 2u);
  EXPECT_EQ(B[0].unit, "ug");
  EXPECT_NEAR(B[0].value, 500.0, 1e-9);
  EXPECT_EQ(B[1].unit, "mg");
  EXPECT_NEAR(B[1].value, 0.5, 1e-12);
  // K = 2e-5 g/sqrt(s) = 20 ug/sqrt(s) = 2e-5 * 9.80665 * 60 m/s^2/sqrt(h).
  const auto K = accelerometer_display(value(2e-5), Term::K, g);
  ASSERT_EQ(K.size(), 2u);
  EXPECT_EQ(K[0].unit, "m/s^2/sqrt(h)");
  EXPECT_NEAR(K[0].value, 2e-5 * g0 * 60.0, 1e-15);
  EXPECT_EQ(K[1].unit, "ug/sqrt(s)");
  EXPECT_NEAR(K[1].value, 20.0, 1e-10);
  // m/s^2 data: 9.80665 m/s^2 of bias instability is 1 g = 1e6 ug.
  const Unit si = *parse_unit("m/s^2");
  EXPECT_NEAR(accelerometer_display(value(g0), Term::B, si)[0].value, 1e6, 1e-6);
  EXPECT_NEAR(accelerometer_display(value(1.0), Term::N, si)[0].value, 60.0, 1e-12);
  // Not an accelerometer, or a term with no navigation unit: nothing.
  EXPECT_TRUE(accelerometer_display(value(1.0), Term::N, *parse_unit("deg/s")).empty());
  EXPECT_TRUE(accelerometer_display(value(1.0), Term::Q, g).empty());
}

TEST(Units, DegreesPerHourData) {
  const Unit u = *parse_unit("deg/h");
  EXPECT_EQ(u.kind, SensorKind::rate);
  EXPECT_EQ(parse_unit("dph")->name, "deg/h");
  EXPECT_NEAR(u.to_si, std::numbers::pi / 180.0 / 3600.0, 1e-22);
  // B of 3600 deg/h is 3600 deg/h; N of 60 deg/h*sqrt(s) = 1/60 deg/s*sqrt(s) = 1 deg/sqrt(h).
  EXPECT_NEAR(display(value(3600.0), Term::B, u).value, 3600.0, 1e-9);
  EXPECT_NEAR(display(value(60.0), Term::N, u).value, 1.0, 1e-12);
  // rad/s as before: 1 rad/s of B is 3600 * 180/pi deg/h.
  EXPECT_NEAR(display(value(1.0), Term::B, *parse_unit("rad/s")).value, 3600.0 * 180.0 / std::numbers::pi, 1e-6);
}

// A fit with white noise N and flicker B only (C_-1 = N^2, C_0 = (0.664 B)^2).
NoiseFit fit_of(double N, double B, double residual) {
  NoiseFit f;
  f.c = {0.0, N * N, kFlickerFloor * kFlickerFloor * B * B, 0.0, 0.0};
  f.N = value(N, 0.01 * N);
  f.B = value(B, 0.05 * B);
  f.rms_rel_residual = residual;
  return f;
}

SlopeReadOffs read_off_of(double B, double tau_min) {
  SlopeReadOffs r;
  r.B = value(B, 0.05 * B);
  r.tau_min = tau_min;
  return r;
}

TEST(BiasVerdict, AgreeWithinTwentyPercent) {
  const auto v = judge_bias_instability(read_off_of(1.1, 100.0), fit_of(0.1, 1.0, 0.05));
  EXPECT_EQ(v.trust, BiasTrust::agree);
  EXPECT_TRUE(v.reason.empty());
  EXPECT_NEAR(v.ratio, 1.0 / 1.1, 1e-12);
}

TEST(BiasVerdict, FitWhenItFollowsTheCurve) {
  // White noise N = 1 at tau_min = 1 s: variance 1 of the fit's 1 + 0.664^2 there.
  const auto v = judge_bias_instability(read_off_of(2.0, 1.0), fit_of(1.0, 1.0, 0.05));
  EXPECT_EQ(v.trust, BiasTrust::fit);
  EXPECT_TRUE(v.compared);
  EXPECT_NEAR(v.ratio, 0.5, 1e-12);
  EXPECT_TRUE(v.beyond_sigma);
  EXPECT_NEAR(v.other_terms_share, 1.0 / (1.0 + kFlickerFloor * kFlickerFloor), 1e-12);
  EXPECT_NE(v.reason.find("biases the read-off"), std::string::npos) << v.reason;
}

TEST(BiasVerdict, ReadOffWhenTheFitMissesTheCurve) {
  const auto v = judge_bias_instability(read_off_of(1.0, 10.0), fit_of(0.1, 2.0, 0.6));
  EXPECT_EQ(v.trust, BiasTrust::read_off);
  EXPECT_NE(v.reason.find("rms residual 60 %"), std::string::npos) << v.reason;
}

TEST(BiasVerdict, NoMinimumNothingToJudge) {
  SlopeReadOffs r;  // B invalid: the curve has no minimum inside the record
  EXPECT_EQ(judge_bias_instability(r, fit_of(0.1, 1.0, 0.05)).trust, BiasTrust::neither);
}

TEST(BiasVerdict, FitWithoutFlickerFloor) {
  NoiseFit f = fit_of(1.0, 0.0, 0.05);
  f.B.valid = false;
  const auto v = judge_bias_instability(read_off_of(1.0, 10.0), f);
  EXPECT_EQ(v.trust, BiasTrust::fit);
  EXPECT_FALSE(v.compared);
  f.rms_rel_residual = 0.5;
  EXPECT_EQ(judge_bias_instability(read_off_of(1.0, 10.0), f).trust, BiasTrust::read_off);
}

}  // namespace
