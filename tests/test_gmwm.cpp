// The Haar wavelet variance and the GMWM fit (stats/wavelet_variance.hpp,
// noise/gmwm.hpp, sim/composite_simulator.hpp):
// - the estimator against the MODWT Haar coefficients summed directly;
// - the fit handed the exact theoretical moments recovers the parameters of
//   the composite processes (the optimiser and its starts, alone);
// - seeded records of a composite process: the empirical wavelet variance
//   inside its intervals about the theory at the nominal rate, and the
//   fitted parameters unbiased within their Monte Carlo standard error.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/gmwm_asymptotics.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {
namespace {

TEST(WaveletVariance, EqualsTheHaarCoefficientsSummedDirectly) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(5.0, 2.0);
  std::vector<double> y(333);
  double walk = 0.0;
  for (double& v : y) v = g(rng) + (walk += 0.1 * g(rng));
  const WaveletVariance wv = wavelet_variance(y, 0.683);
  ASSERT_EQ(wv.size(), 7u);  // 2 .. 128 <= 333 / 2
  for (std::size_t j = 0; j < wv.size(); ++j) {
    const auto tau = static_cast<std::size_t>(wv.tau[j]);
    const std::size_t m = tau / 2;
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t t = 0; t + tau <= y.size(); ++t, ++count) {
      double w = 0.0;
      for (std::size_t i = 0; i < tau; ++i) w += (i < m ? 1.0 : -1.0) * y[t + i] / static_cast<double>(tau);
      sum += w * w;
    }
    EXPECT_EQ(wv.n[j], count);
    EXPECT_NEAR(wv.nu2[j], sum / static_cast<double>(count), 1e-12 * wv.nu2[j]) << tau;
    EXPECT_DOUBLE_EQ(wv.edf[j], std::max(static_cast<double>(count) / static_cast<double>(tau), 1.0));
    EXPECT_LT(wv.interval[j].lo, wv.nu2[j]);
    EXPECT_GT(wv.interval[j].hi, wv.nu2[j]);
  }
  EXPECT_EQ(wavelet_variance(y, 0.683, 3).size(), 3u);
  EXPECT_THROW(wavelet_variance(std::vector<double>{1.0, 2.0, 3.0}), UsageError);
}

// The composite processes with their terms apart in scale.
CompositeModel truth(const std::string& name) {
  CompositeModel m = parse_composite_model(name);
  std::size_t gm = 0;
  for (Process& p : m.processes) {
    switch (p.kind) {
      case ProcessKind::wn: p.value = 1.0; break;
      case ProcessKind::qn: p.value = 0.5; break;
      case ProcessKind::rw: p.value = name == "WN+RW" ? 1e-6 : 1e-8; break;
      case ProcessKind::dr: p.value = 1e-5; break;
      case ProcessKind::gm:
        p = gm == 0 ? gm_process(name == "WN+2*GM+RW" ? 40.0 : 600.0, name == "WN+2*GM+RW" ? 0.3 : 0.25, 1.0)
                    : gm_process(4000.0, 0.15, 1.0);
        ++gm;
        break;
      case ProcessKind::ma1:  // a sensor's averaging filter, or its mirror
        p.value = 1.0;
        p.theta = name == "MA1+GM" ? -0.5 : 0.3;
        break;
      case ProcessKind::sin: break;  // in none of the models here
    }
  }
  return m;
}

void expect_parameters_near(const CompositeModel& got, const CompositeModel& want, double rel,
                            const std::string& what) {
  ASSERT_EQ(got.processes.size(), want.processes.size());
  for (std::size_t i = 0; i < want.processes.size(); ++i) {
    const Process& g = got.processes[i];
    const Process& w = want.processes[i];
    EXPECT_EQ(g.kind, w.kind);
    EXPECT_NEAR(g.value, w.value, rel * std::abs(w.value)) << what << " term " << i;
    if (w.kind == ProcessKind::gm) {
      // T_c = -1 / ln(phi), the quantity the fit carries
      EXPECT_NEAR(std::log(g.phi), std::log(w.phi), rel * std::abs(std::log(w.phi))) << what << " term " << i;
    }
    if (w.kind == ProcessKind::ma1) {
      EXPECT_NEAR(g.theta, w.theta, rel * std::abs(w.theta)) << what << " term " << i;
    }
  }
}

TEST(Gmwm, TheExactMomentsGiveTheParametersBack) {
  for (const std::string name :
       {"WN+RW", "WN+GM", "WN+2*GM+RW", "WN+QN+GM", "WN+GM+DR", "MA1+RW", "MA1+GM", "MA1+2*GM+RW"}) {
    const CompositeModel m = truth(name);
    WaveletVariance wv;
    for (double tau = 2.0; tau <= 1048576.0; tau *= 2.0) {
      wv.tau.push_back(tau);
      wv.nu2.push_back(haar_wavelet_variance(m, tau));
      wv.n.push_back(1048576);
      wv.edf.push_back(std::max(2097152.0 / tau, 1.0));
    }
    const GmwmFit fit = fit_gmwm(wv, parse_composite_model(name));
    EXPECT_EQ(model_name(fit.model), model_name(m));
    expect_parameters_near(fit.model, m, 1e-6, name);
    EXPECT_LT(fit.objective, 1e-12) << name;
    for (std::size_t j = 0; j < wv.size(); ++j) EXPECT_NEAR(fit.nu2_model[j], wv.nu2[j], 1e-8 * wv.nu2[j]);
  }
}

TEST(Gmwm, SeededRecordsUnbiasedWithinTheirSpread) {
  const CompositeModel m = truth("WN+GM");
  constexpr int kSeeds = 40;
  constexpr std::size_t kSamples = 100000;
  std::vector<std::vector<double>> est(3);  // sigma2_wn, sigma2_gm, ln(phi)
  std::size_t inside = 0, points = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const std::vector<double> y = simulate_composite(m, kSamples, static_cast<std::uint64_t>(seed));
    const WaveletVariance wv = wavelet_variance(y, 0.95);
    for (std::size_t j = 0; j < wv.size(); ++j, ++points) {
      const double theory = haar_wavelet_variance(m, wv.tau[j]);
      inside += theory >= wv.interval[j].lo && theory <= wv.interval[j].hi;
    }
    const GmwmFit fit = fit_gmwm(wv, parse_composite_model("WN+GM"));
    est[0].push_back(fit.model.processes[0].value);
    est[1].push_back(fit.model.processes[1].value);
    est[2].push_back(std::log(fit.model.processes[1].phi));
  }
  // eta3 is a rough EDF (it ignores the noise type): the 95 % intervals
  // hold the theory on most points, not exactly 95 %.
  const double rate = static_cast<double>(inside) / static_cast<double>(points);
  EXPECT_GT(rate, 0.85) << inside << " of " << points;
  const double want[3] = {m.processes[0].value, m.processes[1].value, std::log(m.processes[1].phi)};
  for (std::size_t k = 0; k < 3; ++k) {
    double mean = 0.0, var = 0.0;
    for (double v : est[k]) mean += v;
    mean /= kSeeds;
    for (double v : est[k]) var += (v - mean) * (v - mean);
    const double se = std::sqrt(var / (kSeeds - 1) / kSeeds);
    EXPECT_LT(std::abs(mean - want[k]), 3.0 * se)
        << "parameter " << k << ": mean " << mean << " truth " << want[k] << " se " << se;
    EXPECT_GT(se, 0.0);
  }
}

// MA1+RW: seeded records fitted, theta, sigma2 and gamma2 unbiased within 3
// Monte Carlo standard errors, and the sandwich standard deviations
// (noise/gmwm_asymptotics.hpp) of the first record match the spread over
// the 40 (an sd from 40 draws has a relative standard error of 1/sqrt(78)
// = 11 %: 3 of them).
TEST(Gmwm, SeededMovingAverageRecordsUnbiasedWithinTheirSpread) {
  const CompositeModel m = truth("MA1+RW");
  constexpr int kSeeds = 40;
  constexpr std::size_t kSamples = 100000;
  std::vector<std::vector<double>> est(3);  // sigma2, theta, gamma2
  std::vector<double> sandwich;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const std::vector<double> y = simulate_composite(m, kSamples, static_cast<std::uint64_t>(seed));
    const WaveletVariance wv = wavelet_variance(y, 0.95);
    const GmwmFit fit = fit_gmwm(wv, parse_composite_model("MA1+RW"));
    est[0].push_back(fit.model.processes[0].value);
    est[1].push_back(fit.model.processes[0].theta);
    est[2].push_back(fit.model.processes[1].value);
    if (seed == 1) {
      const GmwmAsymptotics as = gmwm_asymptotics(fit, wv, kSamples);
      sandwich = {as.sd[0].value, as.sd[0].theta, as.sd[1].value};
    }
  }
  const double want[3] = {m.processes[0].value, m.processes[0].theta, m.processes[1].value};
  for (std::size_t k = 0; k < 3; ++k) {
    double mean = 0.0, var = 0.0;
    for (double v : est[k]) mean += v;
    mean /= kSeeds;
    for (double v : est[k]) var += (v - mean) * (v - mean);
    const double sd = std::sqrt(var / (kSeeds - 1));
    const double se = sd / std::sqrt(static_cast<double>(kSeeds));
    EXPECT_LT(std::abs(mean - want[k]), 3.0 * se)
        << "parameter " << k << ": mean " << mean << " truth " << want[k] << " se " << se;
    EXPECT_GT(se, 0.0);
    EXPECT_NEAR(sandwich[k] / sd, 1.0, 3.0 / std::sqrt(78.0))
        << "parameter " << k << ": sandwich " << sandwich[k] << " spread " << sd;
  }
}

TEST(Gmwm, RefusesWhatItCannotFit) {
  WaveletVariance wv;
  for (double tau = 2.0; tau <= 8.0; tau *= 2.0) {
    wv.tau.push_back(tau);
    wv.nu2.push_back(1.0 / tau);
    wv.n.push_back(100);
    wv.edf.push_back(10.0);
  }
  EXPECT_THROW(fit_gmwm(wv, parse_composite_model("WN+2*GM")), UsageError);  // 5 parameters, 3 scales
  EXPECT_THROW(fit_gmwm(wv, CompositeModel{}), UsageError);
  wv.nu2[1] = 0.0;
  EXPECT_THROW(fit_gmwm(wv, parse_composite_model("WN")), UsageError);
  EXPECT_THROW(simulate_composite(CompositeModel{{Process{ProcessKind::gm, 1.0, 1.0}}}, 10, 1), UsageError);
}

TEST(Gmwm, AFitWithATermDrivenToZeroStartsABootstrapReplicate) {
  // A fit can drive a term to exactly zero (its log-parameter underflows);
  // the parametric bootstrap starts every replicate from that fit.
  const CompositeModel m = truth("WN+GM");
  const std::vector<double> y = simulate_composite(m, 1 << 14, 4);
  const WaveletVariance wv = wavelet_variance(y);
  GmwmOptions o;
  o.start = m;
  o.start->processes[0].value = 0.0;
  const GmwmFit f = fit_gmwm(wv, parse_composite_model("WN+GM"), o);
  EXPECT_TRUE(std::isfinite(f.objective));
  o.start->processes[0].value = -1.0;  // a negative variance is no start
  EXPECT_THROW(fit_gmwm(wv, parse_composite_model("WN+GM"), o), UsageError);
}

}  // namespace
}  // namespace cubecal
