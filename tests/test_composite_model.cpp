// Composite noise models (noise/composite_model.hpp): the model syntax, and
// each process's Haar wavelet variance against the variance of the Haar
// coefficient computed term by term from the process written as a linear
// filter of unit white noise (no closed form involved), for short and long
// scales and correlation times near the random-walk limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/sim/composite_noise.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {
namespace {

// The MODWT Haar filter at scale tau = 2m over X_0 .. X_{2m-1}.
double haar(std::size_t i, std::size_t m) {
  const double tau = 2.0 * static_cast<double>(m);
  return i < m ? 1.0 / tau : -1.0 / tau;
}

// var(W) = sum_s c_s^2, c_s the weight of innovation w_s in W.
double brute(const Process& p, std::size_t m) {
  const ProcessKind kind = p.kind;
  const double value = p.value, phi = p.phi;
  const std::size_t n = 2 * m;
  double var = 0.0;
  switch (kind) {
    case ProcessKind::wn:
      for (std::size_t i = 0; i < n; ++i) var += value * haar(i, m) * haar(i, m);
      return var;
    case ProcessKind::qn:
      // X_i = U_{i+1} - U_i: U_s enters X_{s-1} with +1 and X_s with -1.
      for (std::size_t s = 0; s <= n; ++s) {
        double c = 0.0;
        if (s >= 1) c += haar(s - 1, m);
        if (s < n) c -= haar(s, m);
        var += value * c * c;
      }
      return var;
    case ProcessKind::rw:
      // X_i = sum_{s<=i} w_s (a start before 0 adds a constant the filter removes).
      for (std::size_t s = 0; s < n; ++s) {
        double c = 0.0;
        for (std::size_t i = s; i < n; ++i) c += haar(i, m);
        var += value * c * c;
      }
      return var;
    case ProcessKind::gm: {
      // X_i = sum_{k>=0} phi^k w_{i-k}, innovations from far enough back that
      // phi^K is below 1e-20 of the first.
      const auto back = static_cast<long>(std::ceil(-46.0 / std::log(phi)));
      for (long s = -back; s < static_cast<long>(n); ++s) {
        const long first = std::max(0L, s);
        double c = 0.0, w = std::pow(phi, static_cast<double>(first - s));  // phi^(i - s)
        for (long i = first; i < static_cast<long>(n); ++i, w *= phi) c += haar(static_cast<std::size_t>(i), m) * w;
        var += value * c * c;
      }
      return var;
    }
    case ProcessKind::ma1:
      // X_i = e_i + theta e_{i-1}: e_s enters X_s with 1 and X_{s+1} with theta.
      for (long s = -1; s < static_cast<long>(n); ++s) {
        double c = 0.0;
        if (s >= 0) c += haar(static_cast<std::size_t>(s), m);
        if (s + 1 < static_cast<long>(n)) c += p.theta * haar(static_cast<std::size_t>(s + 1), m);
        var += value * c * c;
      }
      return var;
    case ProcessKind::dr: {
      double w = 0.0;
      for (std::size_t i = 0; i < n; ++i) w += value * static_cast<double>(i) * haar(i, m);
      return w * w;
    }
    case ProcessKind::sin: {
      // W = sum_i h_i A sin(omega i + U): E over U of W^2 = (A^2 / 2) |sum_i h_i e^{j omega i}|^2.
      double re = 0.0, im = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        re += haar(i, m) * std::cos(p.omega * static_cast<double>(i));
        im += haar(i, m) * std::sin(p.omega * static_cast<double>(i));
      }
      return 0.5 * value * (re * re + im * im);
    }
  }
  return NAN;
}

TEST(CompositeModel, HaarWaveletVarianceEqualsTheFilteredProcess) {
  for (std::size_t m : {1u, 2u, 3u, 5u, 8u, 16u, 64u, 200u}) {
    const double tau = 2.0 * static_cast<double>(m);
    const auto check = [&](Process p) {
      const double want = brute(p, m);
      EXPECT_NEAR(haar_wavelet_variance(p, tau), want, 1e-12 * want)
          << model_name({{p}}) << " phi " << p.phi << " theta " << p.theta << " tau " << tau;
    };
    check({ProcessKind::wn, 2.5, 0.0});
    check({ProcessKind::qn, 0.7, 0.0});
    check({ProcessKind::rw, 1e-3, 0.0});
    check({ProcessKind::dr, -0.02, 0.0});
    for (double phi : {0.05, 0.5, 0.9, 0.999}) check({ProcessKind::gm, 0.3, phi});
    if (m <= 8) check({ProcessKind::gm, 0.3, 0.99999});  // 4.6 M innovations back: short scales only
    for (double theta : {-0.95, -0.4, 0.0, 0.17, 0.6, 0.99}) check({ProcessKind::ma1, 1.7, 0.0, theta});
    for (double omega : {1e-3, 0.05, 0.7, 1.2566, 2.9, 3.14})
      if (brute({ProcessKind::sin, 0.8, 0.0, 0.0, omega}, m) > 1e-9) check({ProcessKind::sin, 0.8, 0.0, 0.0, omega});
  }
}

// A periodic line: its wavelet variance from seeded records of both
// simulators (the phase drawn per record) within 3 standard errors of the
// closed form, at a scale where it peaks and one where it vanishes
// (omega tau / 4 = pi: two adjacent means over one period each).
TEST(CompositeModel, SineWaveletVarianceFromSeededRecords) {
  const double dt = 0.01;
  const Process line = sin_process(0.5, 20.0, dt);  // A = 0.5 at 20 Hz sampled at 100 Hz: omega = 0.4 pi
  EXPECT_NEAR(sine_term(line, dt).amplitude, 0.5, 1e-15);
  EXPECT_NEAR(sine_term(line, dt).frequency_hz, 20.0, 1e-12);
  EXPECT_NEAR(haar_wavelet_variance(line, 10.0), 0.0, 1e-30);  // tau = 2 periods
  CompositeModel model{{line, Process{ProcessKind::wn, 0.01, 0.0}}};
  const std::size_t n = 1 << 14;
  for (const std::size_t tau : {2u, 4u, 10u, 16u}) {
    std::vector<double> est;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      std::vector<double> y = simulate_composite(model, n, seed);
      if (seed % 2 == 0) {
        std::fill(y.begin(), y.end(), 0.0);
        CompositeNoise noise(model, seed);
        noise.add_next(std::span<double>(y).first(n / 3));
        noise.add_next(std::span<double>(y).subspan(n / 3));
      }
      const WaveletVariance wv = wavelet_variance(y);
      for (std::size_t j = 0; j < wv.size(); ++j)
        if (wv.tau[j] == static_cast<double>(tau)) est.push_back(wv.nu2[j]);
    }
    if (est.empty()) {  // tau = 10 is not dyadic: the closed form alone (above)
      EXPECT_EQ(tau, 10u);
      continue;
    }
    double mean = 0.0, var = 0.0;
    for (double v : est) mean += v;
    mean /= static_cast<double>(est.size());
    for (double v : est) var += (v - mean) * (v - mean);
    const double se = std::sqrt(var / static_cast<double>(est.size() - 1) / static_cast<double>(est.size()));
    const double want = haar_wavelet_variance(model, static_cast<double>(tau));
    EXPECT_NEAR(mean, want, 3.0 * se + 1e-3 * want) << "tau " << tau;
  }
  EXPECT_THROW(sin_process(0.5, 50.0, dt), UsageError);  // at the Nyquist frequency
  EXPECT_THROW(sin_process(-1.0, 5.0, dt), UsageError);
  EXPECT_EQ(model_name(parse_composite_model("MA1+RW+GM+2*SIN")), "MA1+RW+GM+2*SIN");
  EXPECT_EQ(parameter_count(parse_composite_model("WN+2*SIN")), 5u);
}

// The MA1's wavelet variance from its autocovariance (gamma0 = sigma2
// (1 + theta^2), gamma1 = sigma2 theta) summed over the Haar filter's
// pairs, and from seeded records (sim/composite_simulator.hpp and the
// block-wise sim/composite_noise.hpp): the mean over 40 records within 3
// standard errors of the closed form, and the lag-one correlation
// theta / (1 + theta^2).
TEST(CompositeModel, MovingAverageWaveletVarianceFromItsAutocovarianceAndSeededRecords) {
  const double sigma2 = 2.0, theta = 0.3;
  const Process ma{ProcessKind::ma1, sigma2, 0.0, theta};
  for (std::size_t m : {1u, 2u, 4u, 32u, 1024u}) {
    const std::size_t n = 2 * m;
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t lag = i > k ? i - k : k - i;
        const double gamma = lag == 0 ? sigma2 * (1.0 + theta * theta) : lag == 1 ? sigma2 * theta : 0.0;
        sum += haar(i, m) * haar(k, m) * gamma;
      }
    const double tau = static_cast<double>(n);
    EXPECT_NEAR(haar_wavelet_variance(ma, tau), sum, 1e-13 * sum) << tau;
    // WN of sigma2 (1 + theta)^2 and QN of -theta sigma2: the same moments.
    EXPECT_NEAR(haar_wavelet_variance(ma, tau),
                sigma2 * (1.0 + theta) * (1.0 + theta) / tau - 6.0 * theta * sigma2 / (tau * tau), 1e-14 * sum);
  }

  CompositeModel model;
  model.processes = {ma};
  constexpr int kSeeds = 40;
  constexpr std::size_t kSamples = 1 << 16;
  const std::vector<double> taus = {2.0, 4.0, 16.0, 256.0};
  for (const bool blocks : {false, true}) {
    std::vector<std::vector<double>> nu2(taus.size());
    std::vector<double> rho;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      std::vector<double> y;
      if (blocks) {
        y.assign(kSamples, 0.0);
        CompositeNoise noise(model, static_cast<std::uint64_t>(seed));
        for (std::size_t k = 0; k < kSamples; k += 1000)
          noise.add_next(std::span<double>(y.data() + k, std::min<std::size_t>(1000, kSamples - k)));
      } else {
        y = simulate_composite(model, kSamples, static_cast<std::uint64_t>(seed));
      }
      const WaveletVariance wv = wavelet_variance(y, 0.95, 8);
      for (std::size_t j = 0; j < taus.size(); ++j)
        for (std::size_t k = 0; k < wv.size(); ++k)
          if (wv.tau[k] == taus[j]) nu2[j].push_back(wv.nu2[k]);
      double c0 = 0.0, c1 = 0.0;
      for (std::size_t i = 0; i < y.size(); ++i) {
        c0 += y[i] * y[i];
        if (i > 0) c1 += y[i] * y[i - 1];
      }
      rho.push_back(c1 / c0);
    }
    const auto mean_se = [](const std::vector<double>& v) {
      double mean = 0.0, var = 0.0;
      for (double x : v) mean += x / static_cast<double>(v.size());
      for (double x : v) var += (x - mean) * (x - mean) / static_cast<double>(v.size() - 1);
      return std::pair{mean, std::sqrt(var / static_cast<double>(v.size()))};
    };
    for (std::size_t j = 0; j < taus.size(); ++j) {
      ASSERT_EQ(nu2[j].size(), static_cast<std::size_t>(kSeeds));
      const auto [mean, se] = mean_se(nu2[j]);
      EXPECT_LT(std::abs(mean - haar_wavelet_variance(ma, taus[j])), 3.0 * se)
          << (blocks ? "blocks" : "whole") << " tau " << taus[j] << ": " << mean << " vs "
          << haar_wavelet_variance(ma, taus[j]);
    }
    const auto [r, se] = mean_se(rho);
    EXPECT_LT(std::abs(r - theta / (1.0 + theta * theta)), 3.0 * se) << r;
  }
}

// A sum's variance is the sum of its processes' (they are independent), and
// the paper's random-walk model (sensor_noise_model.hpp) is WN + RW: its
// exact AVAR halved at m = tau / 2.
TEST(CompositeModel, TheSumAndThePapersModelAgree) {
  RandomWalkModel paper;
  paper.sigma_n = 0.8;
  paper.sigma_mu = 0.003;
  paper.dt = 0.1;
  CompositeModel model = parse_composite_model("WN+RW");
  model.processes[0].value = paper.sigma_n * paper.sigma_n;
  model.processes[1].value = std::pow(paper.sigma_mu * paper.dt, 2);
  for (std::size_t m = 1; m <= (1u << 20); m *= 2) {
    const double tau = 2.0 * static_cast<double>(m);
    EXPECT_NEAR(haar_wavelet_variance(model, tau), avar(paper, m) / 2.0, 1e-13 * avar(paper, m)) << m;
  }
  // Gauss-Markov in physical terms round-trips, to what phi can hold: with
  // T_c = 12000 samples, phi = 1 - 8.3e-5 carries -ln(phi) to 1e-16 / 8.3e-5
  // = 1.3e-12 relative, and T_c and sigma_b inherit that.
  const Process gm = gm_process(120.0, 0.05, 0.01);
  const GaussMarkovTerm t = gauss_markov_term(gm, 0.01);
  EXPECT_NEAR(t.tau_c, 120.0, 120.0 * 1.3e-12 * 4);
  EXPECT_NEAR(t.sigma_b, 0.05, 0.05 * 1.3e-12 * 4);
  const GaussMarkovTerm fast = gauss_markov_term(gm_process(0.05, 2.0, 0.01), 0.01);  // phi = e^-0.2
  EXPECT_NEAR(fast.tau_c, 0.05, 0.05 * 1e-15 * 8);
  EXPECT_NEAR(fast.sigma_b, 2.0, 2.0 * 1e-15 * 8);
  EXPECT_TRUE(std::isnan(haar_wavelet_variance(Process{ProcessKind::gm, 1.0, 1.0}, 4.0)));
  EXPECT_TRUE(std::isnan(haar_wavelet_variance(Process{ProcessKind::wn, -1.0, 0.0}, 4.0)));
  EXPECT_TRUE(std::isnan(haar_wavelet_variance(Process{ProcessKind::gm, 1.0, 0.5}, 3.0)));
  EXPECT_TRUE(std::isnan(haar_wavelet_variance(Process{ProcessKind::ma1, 1.0, 0.0, 1.0}, 4.0)));
  EXPECT_TRUE(std::isnan(haar_wavelet_variance(Process{ProcessKind::ma1, -1.0, 0.0, 0.2}, 4.0)));
  // MA1 in physical terms: N = sqrt(sigma2 dt) (1 + theta), the white level
  // its wavelet variance approaches, N^2 / (tau_s dt) in time units.
  const Process ma = ma1_process(0.04, -0.3, 0.01);
  const MovingAverageTerm mt = moving_average_term(ma, 0.01);
  EXPECT_NEAR(mt.n, 0.04, 1e-16);
  EXPECT_EQ(mt.theta, -0.3);
  const double tau = 1 << 20;
  EXPECT_NEAR(haar_wavelet_variance(ma, tau) * tau, mt.n * mt.n / 0.01, 1e-5 * mt.n * mt.n / 0.01);
  EXPECT_THROW((void)ma1_process(0.04, 1.0, 0.01), UsageError);
  EXPECT_THROW((void)moving_average_term(Process{ProcessKind::wn, 1.0, 0.0}, 0.01), UsageError);
}

TEST(CompositeModel, ModelSyntax) {
  const CompositeModel m = parse_composite_model(" wn + QN+rw+ 2*GM +ar1 ");
  ASSERT_EQ(m.processes.size(), 6u);
  EXPECT_EQ(m.processes[3].kind, ProcessKind::gm);
  EXPECT_EQ(m.processes[5].kind, ProcessKind::gm);
  EXPECT_EQ(model_name(m), "WN+QN+RW+3*GM");
  EXPECT_EQ(model_name(parse_composite_model("DR")), "DR");
  const CompositeModel ma = parse_composite_model("ma1 + RW + 2*AR1");
  EXPECT_EQ(model_name(ma), "MA1+RW+2*GM");
  EXPECT_EQ(ma.processes[0].kind, ProcessKind::ma1);
  EXPECT_EQ(parameter_count(ma), 7u);
  // MA1 beside WN or QN is again an MA1: refused, naming the pair.
  for (const char* bad : {"WN+MA1", "MA1+QN+RW"}) {
    try {
      parse_composite_model(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_EQ(e.field(), cubecal::Field::model);
      EXPECT_NE(std::string(e.what()).find("MA1 with"), std::string::npos) << e.what();
    }
  }
  for (const char* bad :
       {"", "WN+", "WN++RW", "XX", "WN+WN", "2*RW", "0*GM", "x*GM", "100*GM", "MA1+MA1", "2*MA1", "MA2"}) {
    try {
      parse_composite_model(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_EQ(e.field(), cubecal::Field::model);
      EXPECT_NE(std::string(e.what()).find("terms: WN, QN, RW, DR, GM"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace cubecal
