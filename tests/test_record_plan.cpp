// The plan's core (noise/record_plan.hpp, mixture_edf.hpp, minimum_spread.hpp,
// sim/model_allan_variance.hpp): closed forms and properties. The plan against
// simulated records is tests/test_plan_monte_carlo.cpp.
#include <gtest/gtest.h>

#include <boost/math/distributions/normal.hpp>

#include <cmath>
#include <numbers>

#include "cubecal/error.hpp"
#include "cubecal/noise/minimum_spread.hpp"
#include "cubecal/noise/mixture_edf.hpp"
#include "cubecal/noise/record_plan.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/sim/model_allan_variance.hpp"
#include "cubecal/sim/power_law_generator.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal {
namespace {

TEST(PlanTargets, ParsesPercentagesAndFractions) {
  const auto t = parse_plan_targets("B:10%, n:1 % ,K:0.2,T:30%");
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[0].term, PlanTerm::B);
  EXPECT_DOUBLE_EQ(t[0].precision, 0.10);
  EXPECT_EQ(t[1].term, PlanTerm::N);
  EXPECT_DOUBLE_EQ(t[1].precision, 0.01);
  EXPECT_EQ(t[2].term, PlanTerm::K);
  EXPECT_DOUBLE_EQ(t[2].precision, 0.2);
  EXPECT_EQ(t[3].term, PlanTerm::T);
}

TEST(PlanTargets, RefusesWhatIsNoTarget) {
  for (const char* bad : {"", "B", "X:10%", "B:0%", "B:100%", "B:-5%", "B:ten", "B:10%,", "B:10%,B:5%", "B:1e400"}) {
    try {
      (void)parse_plan_targets(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_EQ(e.field(), Field::target) << bad;
    }
  }
}

TEST(PlanModel, TermsGiveIeee952Curve) {
  const PlanTerms t{0.01, 0.2, 0.05, 0.003, 1e-4};
  const PlanModel m = plan_model(t, 0.01);
  for (const std::size_t k : {1u, 7u, 100u, 12345u}) {
    const double tau = 0.01 * static_cast<double>(k);
    const double want = 3 * 0.01 * 0.01 / (tau * tau) + 0.04 / tau + std::pow(kFlickerFloor * 0.05, 2) +
                        0.003 * 0.003 * tau / 3 + 1e-8 * tau * tau / 2;
    EXPECT_NEAR(m.avar(k), want, 1e-14 * want);
  }
  EXPECT_THROW(plan_model(t, 0.0), std::invalid_argument);
  EXPECT_THROW(plan_model(PlanTerms{0, -1, 0, 0, 0}, 0.1), std::invalid_argument);
}

TEST(ModelAllanVariance, SumsTheParts) {
  TriadModel tm;
  tm.lsb = 50.0;
  AxisModel& a = tm.axes[1];
  a.white_sigma = 0.3;
  a.bias = BiasProcess::random_walk;
  a.bias_sigma = 0.002;
  a.power_law.push_back(flicker_term(0.01));
  const double dt = 0.05;
  for (const std::size_t m : {1u, 10u, 1000u}) {
    const double rw = avar(RandomWalkModel{0.3, 0.002, dt, 50.0}, m);
    const double flicker = 2.0 * std::numbers::ln2 * flicker_term(0.01).h;  // SP 1065 Table 2
    EXPECT_NEAR(model_avar(tm, 1, dt, m), rw + flicker, 1e-13 * rw);
    EXPECT_NEAR(plan_model(tm, 1, dt).avar(m), model_avar(tm, 1, dt, m), 0.0);
  }
  a.power_law.push_back({-3.0, 1.0});
  EXPECT_THROW(model_avar(tm, 1, dt, 1), std::invalid_argument);
  EXPECT_THROW(model_avar(tm, 3, dt, 1), std::invalid_argument);
}

TEST(MixtureEdf, OneTypeIsGreenhalls) {
  const std::size_t n = 100001;
  for (const std::size_t m : {1u, 10u, 300u, 5000u}) {
    std::array<double, 5> c{};
    c[1] = 2.0;  // white FM
    EXPECT_NEAR(oadev_mixture_edf(c, m, 0.1, n), edf_for(Stat::oadev, 0, m, n), 1e-9 * edf_for(Stat::oadev, 0, m, n));
    c = {};
    c[3] = 0.5;  // random walk
    EXPECT_NEAR(oadev_mixture_edf(c, m, 0.1, n), edf_for(Stat::oadev, -2, m, n), 1e-9 * edf_for(Stat::oadev, -2, m, n));
    c = {};
    c[2] = 0.5;  // flicker
    EXPECT_NEAR(oadev_mixture_edf(c, m, 0.1, n), edf_for(Stat::oadev, -1, m, n), 1e-9 * edf_for(Stat::oadev, -1, m, n));
  }
  EXPECT_EQ(oadev_mixture_edf({}, 10, 0.1, n), 0.0);
}

TEST(MixtureEdf, TwoTypesAtEqualSharesAreSteadierThanEither) {
  // White FM N^2 / tau and random walk K^2 tau / 3 equal at tau = 10 s: the estimate averages two parts.
  const std::size_t n = 100001, m = 100;
  const double tau0 = 0.1, tau = 10.0;
  std::array<double, 5> c{};
  c[1] = 1.0 * tau;  // N^2 = tau: share 1 at tau
  c[3] = 1.0 / tau;  // K^2 / 3 = 1 / tau: share 1 at tau
  const double e = oadev_mixture_edf(c, m, tau0, n);
  const double ew = edf_for(Stat::oadev, 0, m, n), er = edf_for(Stat::oadev, -2, m, n);
  // Fully correlated parts would give v = (sqrt(vw) + sqrt(vr))^2 / 4, independent ones (vw + vr) / 4: the
  // spectra overlap only in part, so the EDF lies between, above the random walk's own.
  const double vw = 2.0 / ew, vr = 2.0 / er;
  EXPECT_GT(e, 2.0 / (0.25 * std::pow(std::sqrt(vw) + std::sqrt(vr), 2)));
  EXPECT_LT(e, 2.0 / (0.25 * (vw + vr)));
  EXPECT_GT(e, er);
}

TEST(PlanPrecision, WhiteNoiseFallsAsOneOverRootLength) {
  const PlanModel m = plan_model(PlanTerms{0, 0.1, 0, 0, 0}, 0.01);
  const PlanTerm n[] = {PlanTerm::N};
  const double p1 = plan_precision(m, 3600.0, n).front().precision;
  const double p4 = plan_precision(m, 4 * 3600.0, n).front().precision;
  EXPECT_NEAR(p4 / p1, 0.5, 0.01);
  // The mean of the 7 points within 2x of 1 s: below one point's 1 / sqrt(2 edf(1 s)), above 7 independent ones'.
  const double one = 1.0 / std::sqrt(2.0 * edf_for(Stat::oadev, 0, 100, 360001));
  EXPECT_LT(p1, one);
  EXPECT_GT(p1, one / std::sqrt(7.0));
  EXPECT_NEAR(plan_precision(m, 3600.0, n).front().value, 0.1, 1e-3);
}

TEST(PlanPrecision, ScalesWithTheConfidence) {
  const PlanModel m = plan_model(PlanTerms{0, 0.1, 0.02, 0.001, 0}, 0.01);
  const PlanTerm t[] = {PlanTerm::N, PlanTerm::B, PlanTerm::K};
  PlanOptions o95;
  o95.ci = 0.95;
  const auto a = plan_precision(m, 7200.0, t), b = plan_precision(m, 7200.0, t, o95);
  const boost::math::normal z;
  const double ratio = boost::math::quantile(z, 0.975) / boost::math::quantile(z, 0.5 + 0.683 / 2);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(b[i].precision / a[i].precision, ratio, 1e-12);
  o95.ci = 1.0;
  EXPECT_THROW(plan_precision(m, 7200.0, t, o95), UsageError);
}

TEST(PlanDuration, IsTheShortestLengthThatMeetsTheTarget) {
  const PlanModel m = plan_model(PlanTerms{0, 0.15, 0.02, 0.002, 0}, 0.01);
  const PlanTarget targets[] = {{PlanTerm::N, 0.02}, {PlanTerm::B, 0.10}, {PlanTerm::K, 0.20}, {PlanTerm::T, 0.30}};
  for (const TargetPlan& tp : plan_duration(m, targets)) {
    SCOPED_TRACE(std::string(to_string(tp.target.term)));
    ASSERT_EQ(tp.at.reason, PlanReason::none) << tp.at.why;
    EXPECT_LE(tp.at.precision, tp.target.precision);
    const PlanTerm t[] = {tp.target.term};
    const TermPrecision shorter = plan_precision(m, tp.duration_s / 1.03, t).front();
    EXPECT_TRUE(shorter.reason != PlanReason::none || shorter.precision > tp.target.precision);
  }
}

TEST(PlanDuration, SaysWhyATargetCannotBeMet) {
  const PlanTerm k[] = {PlanTerm::K};
  // White and flicker only: no random walk at any length, no precision for K.
  const PlanModel wf = plan_model(PlanTerms{0, 0.1, 0.02, 0, 0}, 0.01);
  EXPECT_EQ(plan_precision(wf, 3600.0, k).front().reason, PlanReason::not_resolved);
  const PlanTarget targets[] = {{PlanTerm::K, 0.2}, {PlanTerm::T, 0.05}, {PlanTerm::N, 1e-6}, {PlanTerm::R, 0.3}};
  const auto r = plan_duration(wf, targets);
  EXPECT_EQ(r[0].at.reason, PlanReason::not_in_model);
  EXPECT_NE(r[0].at.why.find("random walk"), std::string::npos) << r[0].at.why;
  EXPECT_TRUE(std::isnan(r[0].duration_s));
  EXPECT_EQ(r[1].at.reason, PlanReason::finer_than_model);
  EXPECT_NE(r[1].at.why.find("10 taus per decade"), std::string::npos) << r[1].at.why;
  EXPECT_EQ(r[2].at.reason, PlanReason::too_long);
  EXPECT_EQ(r[3].at.reason, PlanReason::not_in_model);
  // At 0.05 Hz the first tau (20 s) is already on the flicker floor: no white arm to read N on.
  const PlanModel slow = plan_model(PlanTerms{0, 0.1, 0.2, 0.0001, 0}, 20.0);
  const PlanTarget n[] = {{PlanTerm::N, 0.1}};
  EXPECT_EQ(plan_duration(slow, n).front().at.reason, PlanReason::rate_too_low);
}

TEST(PlanDuration, ThePapersGyroAt72Hours) {
  // The paper's adjusted gyro model (sport-gyro): white noise and a random-walk bias, its curve's minimum at ~6 s.
  const PlanModel m = plan_model(preset("sport-gyro"), 0, 0.1);
  const PlanTerm terms[] = {PlanTerm::N, PlanTerm::B, PlanTerm::K, PlanTerm::T};
  const auto p = plan_precision(m, 72 * 3600.0, terms);
  for (const TermPrecision& t : p) EXPECT_EQ(t.reason, PlanReason::none) << t.why;
  // N: EDF ~ 1.5 * 259200 s at 1 s, a mean of correlated points: about 1 / sqrt(2 * 3.9e5).
  EXPECT_NEAR(p[0].precision, 1.0 / std::sqrt(2 * 1.5 * 259200.0), 0.0003);
  EXPECT_NEAR(p[3].value, 6.3, 0.05);
}

TEST(MinimumSpread, AFlatterBottomSpreadsTFurther) {
  // The same white noise with two random walks: the weaker walk's minimum lies further out on a flatter bottom.
  const PlanTerm t[] = {PlanTerm::T};
  const double strong = plan_precision(plan_model(PlanTerms{0, 0.1, 0, 0.01, 0}, 0.1), 86400.0, t).front().precision;
  const double weak = plan_precision(plan_model(PlanTerms{0, 0.1, 0, 0.001, 0}, 0.1), 86400.0, t).front().precision;
  EXPECT_GT(weak, strong);
}

}  // namespace
}  // namespace cubecal
