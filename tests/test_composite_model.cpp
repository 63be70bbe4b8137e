// Composite noise models (noise/composite_model.hpp): the model syntax, and
// each process's Haar wavelet variance against the variance of the Haar
// coefficient computed term by term from the process written as a linear
// filter of unit white noise (no closed form involved), for short and long
// scales and correlation times near the random-walk limit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"

namespace cubecal {
namespace {

// The MODWT Haar filter at scale tau = 2m over X_0 .. X_{2m-1}.
double haar(std::size_t i, std::size_t m) {
  const double tau = 2.0 * static_cast<double>(m);
  return i < m ? 1.0 / tau : -1.0 / tau;
}

// var(W) = sum_s c_s^2, c_s the weight of innovation w_s in W.
double brute(ProcessKind kind, double value, double phi, std::size_t m) {
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
    case ProcessKind::dr: {
      double w = 0.0;
      for (std::size_t i = 0; i < n; ++i) w += value * static_cast<double>(i) * haar(i, m);
      return w * w;
    }
  }
  return NAN;
}

TEST(CompositeModel, HaarWaveletVarianceEqualsTheFilteredProcess) {
  for (std::size_t m : {1u, 2u, 3u, 5u, 8u, 16u, 64u, 200u}) {
    const double tau = 2.0 * static_cast<double>(m);
    const auto check = [&](Process p) {
      const double want = brute(p.kind, p.value, p.phi, m);
      EXPECT_NEAR(haar_wavelet_variance(p, tau), want, 1e-12 * want)
          << model_name({{p}}) << " phi " << p.phi << " tau " << tau;
    };
    check({ProcessKind::wn, 2.5, 0.0});
    check({ProcessKind::qn, 0.7, 0.0});
    check({ProcessKind::rw, 1e-3, 0.0});
    check({ProcessKind::dr, -0.02, 0.0});
    for (double phi : {0.05, 0.5, 0.9, 0.999}) check({ProcessKind::gm, 0.3, phi});
    if (m <= 8) check({ProcessKind::gm, 0.3, 0.99999});  // 4.6 M innovations back: short scales only
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
}

TEST(CompositeModel, ModelSyntax) {
  const CompositeModel m = parse_composite_model(" wn + QN+rw+ 2*GM +ar1 ");
  ASSERT_EQ(m.processes.size(), 6u);
  EXPECT_EQ(m.processes[3].kind, ProcessKind::gm);
  EXPECT_EQ(m.processes[5].kind, ProcessKind::gm);
  EXPECT_EQ(model_name(m), "WN+QN+RW+3*GM");
  EXPECT_EQ(model_name(parse_composite_model("DR")), "DR");
  for (const char* bad : {"", "WN+", "WN++RW", "XX", "WN+WN", "2*RW", "0*GM", "x*GM", "100*GM"}) {
    try {
      parse_composite_model(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_EQ(e.option(), "model");
      EXPECT_NE(std::string(e.what()).find("terms: WN, QN, RW, DR, GM"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace cubecal
