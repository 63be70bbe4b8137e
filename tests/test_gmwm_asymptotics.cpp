// The sandwich covariance of a GMWM fit (noise/gmwm_asymptotics.hpp):
// - its algebra: the hat matrix is a projection of trace p, the sandwich
//   equals (A'WA)^-1 when V = W^-1, the Jacobian column of ln a equals a
//   difference quotient of the model's wavelet variance;
// - seeded Monte Carlo of WN+RW and WN+GM (400 records of 2^15 samples
//   each): the spread of the fitted log-parameters against the sandwich
//   standard deviations at the truth and at each record's fit; where the
//   scales are correlated (the random walk's) the sandwich is clearly wider
//   than (A'WA)^-1;
// - `cubecal model` as a library call: each quantity's asymptotic sd is the
//   delta method on the sandwich, and agrees with the bootstrap's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/gmwm_asymptotics.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {
namespace {

CompositeModel make(std::initializer_list<Process> p) {
  CompositeModel m;
  m.processes = p;
  return m;
}

const CompositeModel kWnRw = make({{ProcessKind::wn, 1.0, 0.0}, {ProcessKind::rw, 1e-4, 0.0}});
const CompositeModel kWnGm = make({{ProcessKind::wn, 1.0, 0.0}, {ProcessKind::gm, 7e-4, 0.99}});

// The fit a record of the model would give if its wavelet variance were
// the theory: the model itself, weighted as fit_gmwm weighs at the model.
GmwmFit fit_at_truth(const CompositeModel& model, const WaveletVariance& wv) {
  GmwmFit f;
  f.model = model;
  for (std::size_t j = 0; j < wv.size(); ++j) {
    f.nu2_model.push_back(haar_wavelet_variance(model, wv.tau[j]));
    f.sd.push_back(f.nu2_model.back() * std::sqrt(2.0 / wv.edf[j]));
  }
  return f;
}

std::vector<double> log_parameters(const CompositeModel& m) {
  std::vector<double> theta;
  for (const Process& p : m.processes) {
    theta.push_back(std::log(p.kind == ProcessKind::dr ? p.value * p.value : p.value));
    if (p.kind == ProcessKind::gm) theta.push_back(std::log(-std::log(p.phi)));
  }
  return theta;
}

TEST(GmwmAsymptotics, HatMatrixSandwichAndJacobian) {
  const std::size_t N = 1 << 14;
  const std::vector<double> y = simulate_composite(kWnGm, N, 5);
  const WaveletVariance wv = wavelet_variance(y);
  const GmwmFit fit = fit_gmwm(wv, parse_composite_model("WN+GM"));
  const GmwmAsymptotics as = gmwm_asymptotics(fit, wv, N);
  const std::size_t J = wv.size(), p = as.parameters;
  ASSERT_EQ(p, 3u);
  ASSERT_EQ(as.hat.rows(), J);
  ASSERT_EQ(as.hat.cols(), J);
  // P = A (A'WA)^-1 A'W: P P = P, tr P = p, P A = A.
  double trace = 0.0;
  for (std::size_t i = 0; i < J; ++i) {
    trace += as.hat(i, i);
    for (std::size_t k = 0; k < J; ++k) {
      double pp = 0.0;
      for (std::size_t l = 0; l < J; ++l) pp += as.hat(i, l) * as.hat(l, k);
      EXPECT_NEAR(pp, as.hat(i, k), 1e-9);
    }
    for (std::size_t c = 0; c < p; ++c) {
      double pa = 0.0;
      for (std::size_t l = 0; l < J; ++l) pa += as.hat(i, l) * as.jacobian(l, c);
      EXPECT_NEAR(pa, as.jacobian(i, c), 1e-9 * std::abs(as.jacobian(i, c)) + 1e-15);
    }
  }
  EXPECT_NEAR(trace, 3.0, 1e-9);
  // d nu2 / d ln a against a plain difference quotient.
  const Process& gm = fit.model.processes[1];
  const double a = -std::log(gm.phi);
  for (std::size_t j = 0; j < J; ++j) {
    const double h = 1e-6;
    const double dq = (gauss_markov_wavelet_variance(a * std::exp(h), gm.value, wv.tau[j]) -
                       gauss_markov_wavelet_variance(a * std::exp(-h), gm.value, wv.tau[j])) /
                      (2.0 * h);
    EXPECT_NEAR(as.jacobian(j, 2), dq, 1e-6 * std::abs(dq) + 1e-18) << wv.tau[j];
  }
  // The per-sample parameters' sd by the delta method.
  EXPECT_NEAR(as.sd[0].value, fit.model.processes[0].value * std::sqrt(as.covariance(0, 0)), 1e-15);
  EXPECT_NEAR(as.sd[1].phi, gm.phi * a * std::sqrt(as.covariance(2, 2)), 1e-15);
  EXPECT_EQ(as.sd[0].phi, 0.0);

  // Bad pairs.
  GmwmFit other = fit;
  other.sd.pop_back();
  EXPECT_THROW(gmwm_asymptotics(other, wv, N), UsageError);
}

struct Spread {
  std::vector<double> mc_sd;      // of the fitted log-parameters
  std::vector<double> truth_sd;   // the sandwich at the truth
  std::vector<double> median_sd;  // the median of the sandwich at each record's fit
  std::vector<double> naive_sd;   // (A'WA)^-1 at the truth
};

Spread spread(const CompositeModel& truth, std::size_t N, std::size_t records, std::uint64_t seed) {
  const CompositeModel structure = parse_composite_model(model_name(truth));
  std::vector<std::vector<double>> theta, sds;
  Spread s;
  for (std::size_t r = 0; r < records; ++r) {
    const std::vector<double> y = simulate_composite(truth, N, seed + r);
    const WaveletVariance wv = wavelet_variance(y);
    GmwmOptions opt;
    opt.start = truth;
    const GmwmFit fit = fit_gmwm(wv, structure, opt);
    theta.push_back(log_parameters(fit.model));
    const GmwmAsymptotics as = gmwm_asymptotics(fit, wv, N);
    std::vector<double> sd;
    for (std::size_t i = 0; i < as.parameters; ++i) sd.push_back(std::sqrt(as.covariance(i, i)));
    sds.push_back(sd);
    if (r == 0) {
      const GmwmAsymptotics at = gmwm_asymptotics(fit_at_truth(truth, wv), wv, N);
      for (std::size_t i = 0; i < at.parameters; ++i) {
        s.truth_sd.push_back(std::sqrt(at.covariance(i, i)));
        s.naive_sd.push_back(std::sqrt(at.naive(i, i)));
      }
    }
  }
  const std::size_t p = theta.front().size();
  const auto n = static_cast<double>(records);
  for (std::size_t i = 0; i < p; ++i) {
    double mean = 0.0, var = 0.0;
    for (const auto& t : theta) mean += t[i] / n;
    for (const auto& t : theta) var += (t[i] - mean) * (t[i] - mean) / (n - 1.0);
    s.mc_sd.push_back(std::sqrt(var));
    std::vector<double> col;
    for (const auto& d : sds) col.push_back(d[i]);
    std::nth_element(col.begin(), col.begin() + static_cast<long>(col.size() / 2), col.end());
    s.median_sd.push_back(col[col.size() / 2]);
  }
  return s;
}

TEST(GmwmAsymptotics, SandwichMatchesTheMonteCarloSpread) {
  // 400 records: the Monte Carlo sd of a near-normal estimate is itself
  // uncertain by 1 / sqrt(2 (n - 1)) = 3.5 %, so 15 % is a 4-sigma bound
  // less the few % the asymptotic form may be off at 2^15 samples (1000
  // records put the ratios at 0.97-1.01 there).
  const std::size_t N = 1 << 15, records = 400;
  struct Case {
    CompositeModel truth;
    std::vector<std::string> names;
  };
  for (const Case& c : {Case{kWnRw, {"ln sigma2", "ln gamma2"}}, Case{kWnGm, {"ln sigma2", "ln s2_GM", "ln a"}}}) {
    const Spread s = spread(c.truth, N, records, 7000);
    for (std::size_t i = 0; i < s.mc_sd.size(); ++i) {
      std::printf(
          "%-6s %-10s MC sd %.4f  sandwich at truth %.4f (%.2f)  median at fits %.4f (%.2f)  naive %.4f "
          "(sandwich / naive %.2f)\n",
          model_name(c.truth).c_str(), c.names[i].c_str(), s.mc_sd[i], s.truth_sd[i], s.truth_sd[i] / s.mc_sd[i],
          s.median_sd[i], s.median_sd[i] / s.mc_sd[i], s.naive_sd[i], s.truth_sd[i] / s.naive_sd[i]);
      EXPECT_NEAR(s.truth_sd[i] / s.mc_sd[i], 1.0, 0.15) << model_name(c.truth) << " " << c.names[i];
      EXPECT_NEAR(s.median_sd[i] / s.mc_sd[i], 1.0, 0.15) << model_name(c.truth) << " " << c.names[i];
    }
    // The random walk's scales are strongly correlated: (A'WA)^-1 with the
    // chi-square weights is ~25 % too narrow for ln gamma2 (a number fixed
    // by N and the model, not drawn).
    if (c.truth.processes[1].kind == ProcessKind::rw) {
      EXPECT_GT(s.truth_sd[1] / s.naive_sd[1], 1.15);
    }
  }
}

TEST(GmwmAsymptotics, ModelQuantitiesCarryTheDeltaMethodAndAgreeWithTheBootstrap) {
  // WN + GM at 100 Hz in deg/s, 2^17 samples.
  const std::size_t N = 1 << 17;
  const CompositeModel truth = make({{ProcessKind::wn, 1e-4, 0.0}, {ProcessKind::gm, 1e-7, std::exp(-0.002)}});
  io::Series s;
  s.file = "sim.csv";
  s.rate_hz = 100.0;
  s.tau0 = 0.01;
  s.names = {"gx"};
  s.channels = {simulate_composite(truth, N, 11)};
  s.segments = {{0, N}};
  pipeline::ModelRequest req;
  req.model = "WN+GM";
  req.bootstrap = 150;
  req.seed = 2;
  const pipeline::ModelResult r = pipeline::run_model(s, req);
  const pipeline::ModelChannel& ch = r.channels.at(0);
  const GmwmAsymptotics as = gmwm_asymptotics(ch.fit, ch.wv, N);
  const auto C = [&](std::size_t i, std::size_t k) { return as.covariance(i, k); };
  const double dt = 0.01;
  // N = sqrt(sigma2 dt): half the relative sd of sigma2.
  const pipeline::ModelQuantity& n = ch.terms[0].quantities[0];
  EXPECT_NEAR(n.asymptotic_sd, 0.5 * n.value * std::sqrt(C(0, 0)), 1e-12 * n.asymptotic_sd);
  // sigma_b and T_c of (ln s, ln a), against a numerical gradient.
  const Process& gm = ch.fit.model.processes[1];
  const double ls = std::log(gm.value), la = std::log(-std::log(gm.phi));
  const auto quantities = [&](double x, double y) {
    return gauss_markov_term(Process{ProcessKind::gm, std::exp(x), std::exp(-std::exp(y))}, dt);
  };
  const double h = 1e-6;
  const double dsb_ds = (quantities(ls + h, la).sigma_b - quantities(ls - h, la).sigma_b) / (2 * h);
  const double dsb_da = (quantities(ls, la + h).sigma_b - quantities(ls, la - h).sigma_b) / (2 * h);
  const double dtc_da = (quantities(ls, la + h).tau_c - quantities(ls, la - h).tau_c) / (2 * h);
  const double sd_sb = std::sqrt(dsb_ds * dsb_ds * C(1, 1) + 2 * dsb_ds * dsb_da * C(1, 2) + dsb_da * dsb_da * C(2, 2));
  const pipeline::ModelQuantity& sb = ch.terms[1].quantities[0];
  const pipeline::ModelQuantity& tc = ch.terms[1].quantities[1];
  EXPECT_NEAR(sb.asymptotic_sd, sd_sb, 1e-6 * sd_sb);
  EXPECT_NEAR(tc.asymptotic_sd, std::abs(dtc_da) * std::sqrt(C(2, 2)), 1e-6 * tc.asymptotic_sd);
  // In display units: the value's factor.
  EXPECT_NEAR(n.display_asymptotic_sd / n.asymptotic_sd, n.display.value / n.value, 1e-12);
  // The bootstrap (150 replicates: its sd is itself uncertain by ~6 %)
  // agrees with the sandwich within 25 %.
  ASSERT_GE(ch.replicates, 140u);
  for (const auto& t : ch.terms)
    for (const auto& q : t.quantities) {
      std::printf("%-8s value %.5g  asymptotic sd %.4g  bootstrap sd %.4g (ratio %.2f)\n", q.name.c_str(), q.value,
                  q.asymptotic_sd, q.sd, q.asymptotic_sd / q.sd);
      EXPECT_NEAR(q.asymptotic_sd / q.sd, 1.0, 0.25) << q.name;
    }
  // JSON: asymptotic_sd beside sd, in both units.
  const nlohmann::json j = pipeline::to_json(r);
  const auto& q0 = j.at("channels").at(0).at("terms").at(0).at("quantities").at(0);
  EXPECT_DOUBLE_EQ(q0.at("asymptotic_sd").get<double>(), n.asymptotic_sd);
  EXPECT_DOUBLE_EQ(q0.at("display").at("asymptotic_sd").get<double>(), n.display_asymptotic_sd);
}

}  // namespace
}  // namespace cubecal
