// The record plan against a seeded Monte Carlo, light (issue 35, item 2; the
// full table is bench/plan_validation.cpp, docs/planning.md): 750 records of
// white noise plus a rate random walk simulated at one length, each analysed
// as `cubecal analyze` analyses it (the OADEV curve with analyze's request,
// read_off_noise_terms, fit_noise_terms, reported_terms). Each statistic is
// the plan's (docs/formulas/planning.md §0, §3): for N and K the spread is
// sd / mean over the records; for B half the central 68.3 % interval over
// the median; for T half the central 68.3 % interval of ln T, each record's
// T uniform over its tau's cell. The stated uncertainty is the mean of what
// analyze states (sigma / value; T: T_rel_sigma). Each lies within 15 % of
// plan_precision at 1 sigma. (K's stated uncertainty was 1.38 times the
// plan while analyze stated the sandwich sigma of the coefficients its fit
// freed; it states the planned sigma now, docs/formulas/planning.md §1.2:
// 1.07.)
//
// The Monte Carlo's own error. The sd over R records has a standard error
// SE(sd) = sqrt(Var(s^2)) / (2 sd), Var(s^2) ~ (m4 - (R - 3) / (R - 1) s^4) / R
// from the records' own fourth moment, and the mean's error adds in
// quadrature for sd / mean; the central intervals' errors are bootstrapped
// (400 resamples of the records). The records are enough when that standard
// error, relative to the plan, is at most kMaxMonteCarloSe: the test asserts
// it, and then asserts the ratio itself within 15 % of 1 with no allowance
// for the noise. So a plan exact to the truth fails only on a > 3 SE
// fluctuation (kMaxMonteCarloSe 0.05: 15 % is 3 of them), and a plan off by
// 25 % passes only on a > 2 SE one: the bound is the issue's, not widened by
// the noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/record_plan.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/sim/model_allan_variance.hpp"
#include "cubecal/sim/simulator.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "plan_statistics.hpp"

namespace cubecal {
namespace {

constexpr double kWithin = 0.15;
constexpr double kMaxMonteCarloSe = 0.05;
constexpr PlanTerm kTerms[4] = {PlanTerm::N, PlanTerm::B, PlanTerm::K, PlanTerm::T};

// One record's terms as analyze reports them: value, stated relative
// uncertainty, and whether analyze resolved the term.
struct Terms {
  double value[4] = {};
  double stated[4] = {};
  bool resolved[4] = {};
  std::array<double, 2> t_cell{};  // ln tau of T's cell: half-way to the neighbouring taus
};

// analyze's Allan curve (pipeline/detail/analysis_parts.cpp, oadev_request) and the terms it reports.
std::vector<Terms> analyse(const io::Series& s) {
  pipeline::DevRequest d;
  d.stat = Stat::oadev;
  d.type = DataType::freq;
  d.grid = TauGrid{TauGrid::Kind::log, 10, {}};
  d.options.ci = 0.683;
  d.options.conservative_short = true;
  d.threads = 1;
  std::vector<Terms> out;
  for (const auto& ch : pipeline::run_dev(s, d).channels) {
    const AllanCurve curve = to_allan_curve(ch.points);
    const SlopeReadOffs ro = read_off_noise_terms(curve);
    const ReportedTerms rep = reported_terms(ro, fit_noise_terms(curve), curve);
    Terms t;
    const ReportedTerm* r[3] = {&rep.N, &rep.B, &rep.K};
    for (int i = 0; i < 3; ++i) {
      t.resolved[i] = !r[i]->bound() && r[i]->value() > 0.0;
      t.value[i] = r[i]->value();
      t.stated[i] = t.resolved[i] ? r[i]->estimate.sigma / r[i]->value() : 0.0;
    }
    t.resolved[3] = !rep.no_minimum;
    t.value[3] = rep.T;
    t.stated[3] = rep.T_rel_sigma;
    const auto at = std::find(curve.tau.begin(), curve.tau.end(), rep.T);
    if (t.resolved[3] && at != curve.tau.end()) {
      const auto i = static_cast<std::size_t>(at - curve.tau.begin());
      const double l = std::log(rep.T);
      t.t_cell = {i > 0 ? 0.5 * (l + std::log(curve.tau[i - 1])) : l,
                  i + 1 < curve.size() ? 0.5 * (l + std::log(curve.tau[i + 1])) : l};
    }
    out.push_back(t);
  }
  return out;
}

// Three records per simulation: the triad's axes carry the same model on streams of their own.
std::vector<Terms> records(const AxisModel& axis, double rate_hz, std::size_t n, std::size_t sims) {
  TriadModel m;
  m.axes = {axis, axis, axis};
  std::vector<Terms> all;
  for (std::size_t k = 0; k < sims; ++k) {
    TriadSimulator sim(m, 1.0 / rate_hz, 1 + k, n);
    std::vector<double> out(3 * n);
    sim.run(n, {}, {}, out);
    io::Series s;
    s.file = "seeded";
    s.rate_hz = rate_hz;
    s.tau0 = 1.0 / rate_hz;
    s.names = {"a", "b", "c"};
    s.channels.assign(3, std::vector<double>(n));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t a = 0; a < 3; ++a) s.channels[a][i] = out[3 * i + a];
    s.segments = {IndexRange{0, n}};
    for (const Terms& t : analyse(s)) all.push_back(t);
  }
  return all;
}

using plan_statistics::b_half_width;
using plan_statistics::bootstrap_se;
using plan_statistics::Moments;
using plan_statistics::moments;
using plan_statistics::t_half_width;

// Term i over the records, each statistic the plan's (docs/formulas/planning.md
// §0, §3): the spread (N, K: sd / mean; B, T: the central intervals above)
// with its standard error, the mean stated uncertainty and its standard
// error, the share of records that resolve the term.
struct Observed {
  double spread = 0.0, spread_se = 0.0, stated = 0.0, stated_se = 0.0, resolved = 0.0;
};

Observed observe(const std::vector<Terms>& recs, int i) {
  std::vector<double> v, st;
  std::vector<std::array<double, 2>> cells;
  for (const Terms& t : recs) {
    if (!t.resolved[i]) continue;
    v.push_back(t.value[i]);
    st.push_back(t.stated[i]);
    cells.push_back(t.t_cell);
  }
  Observed o;
  o.resolved = static_cast<double>(v.size()) / static_cast<double>(recs.size());
  if (kTerms[i] == PlanTerm::B) {
    o.spread = b_half_width(v);
    o.spread_se = bootstrap_se(v, b_half_width);
  } else if (kTerms[i] == PlanTerm::T) {
    o.spread = t_half_width(cells);
    o.spread_se = bootstrap_se(cells, t_half_width);
  } else {
    const Moments m = moments(v);
    o.spread = m.sd / m.mean;
    o.spread_se = o.spread * std::hypot(m.sd_se / m.sd, 1.0 / std::sqrt(m.n));
  }
  const Moments ms = moments(st);
  o.stated = ms.mean;
  o.stated_se = ms.sd / std::sqrt(ms.n);
  return o;
}

// The plan of one term against the records and what the records show.
struct Compared {
  TermPrecision plan;
  Observed seen;
};

// The plan of `axis` at `n` samples against `sims` x 3 records of that length, per term of kTerms.
std::vector<Compared> compare(const AxisModel& axis, double rate_hz, std::size_t n, std::size_t sims) {
  TriadModel m;
  m.axes = {axis, axis, axis};
  const double length = static_cast<double>(n) / rate_hz;
  const std::vector<TermPrecision> plan = plan_precision(plan_model(m, 0, 1.0 / rate_hz), length, kTerms);
  const std::vector<Terms> recs = records(axis, rate_hz, n, sims);
  std::vector<Compared> out;
  for (int i = 0; i < 4; ++i) {
    out.push_back({plan[i], observe(recs, i)});
    const Observed& o = out.back().seen;
    const double p = plan[i].precision;
    std::printf("%s: plan %.4f, spread %.4f +- %.4f (ratio %.3f), stated %.4f +- %.4f (ratio %.3f), resolved %.3f\n",
                std::string(to_string(kTerms[i])).c_str(), p, o.spread, o.spread_se, o.spread / p, o.stated,
                o.stated_se, o.stated / p, o.resolved);
  }
  return out;
}

// White noise N = 0.01 u sqrt(s) and a rate random walk K = 1.7e-3 u / sqrt(s)
// at 100 Hz: the curve's minimum at sqrt(3) N / K ~ 10 s, the +1/2 arm read
// over the record's last decade and a half. 20 minutes (120,000 samples),
// 750 records, simulated once for the tests below.
const std::vector<Compared>& white_and_random_walk() {
  static const std::vector<Compared> c = [] {
    AxisModel axis;
    const double rate = 100.0;
    axis.white_sigma = 0.01 * std::sqrt(rate);  // N sqrt(rate): per sample
    axis.bias = BiasProcess::random_walk;
    axis.bias_sigma = 1.7e-3 * std::sqrt(rate);  // K sqrt(rate): sigma_mu
    return compare(axis, rate, 120'000, 250);
  }();
  return c;
}

std::string trace(const Compared& c) {
  return std::string(to_string(c.plan.term)) + ": plan " + std::to_string(c.plan.precision) + ", spread " +
         std::to_string(c.seen.spread) + " +- " + std::to_string(c.seen.spread_se) + ", stated " +
         std::to_string(c.seen.stated) + " +- " + std::to_string(c.seen.stated_se) + ", resolved in " +
         std::to_string(c.seen.resolved);
}

// The spread over records of every term, and the uncertainty analyze states
// for it, within 15 % of the plan; every term resolved in 95 % of the
// records. (One test: ctest runs each test in a process of its own, and the
// records are the cost.)
TEST(PlanMonteCarlo, SpreadAndStatedUncertaintyAreThePlans) {
  for (const Compared& c : white_and_random_walk()) {
    SCOPED_TRACE(trace(c));
    ASSERT_EQ(c.plan.reason, PlanReason::none) << c.plan.why;
    const double p = c.plan.precision;
    EXPECT_GE(c.seen.resolved, 0.95);
    EXPECT_LE(c.seen.spread_se / p, kMaxMonteCarloSe);  // enough records to judge the spread
    EXPECT_NEAR(c.seen.spread / p, 1.0, kWithin);
    EXPECT_LE(c.seen.stated_se / p, kMaxMonteCarloSe);
    EXPECT_NEAR(c.seen.stated / p, 1.0, kWithin);
  }
}

}  // namespace
}  // namespace cubecal
