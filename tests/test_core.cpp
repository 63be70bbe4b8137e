// Core statistics against closed forms and published reference values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "../src/detail/magnitude.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "reason_of.hpp"

namespace cubecal {
namespace {

std::vector<double> white(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<double> v(n);
  for (double& x : v) x = g(rng);
  return v;
}

TEST(TauGrid, Octave) {
  EXPECT_EQ(averaging_factors(parse_tau_grid("octave"), 100, 1.0), (std::vector<std::size_t>{1, 2, 4, 8, 16, 32, 64}));
}

TEST(TauGrid, Decade) {
  EXPECT_EQ(averaging_factors(parse_tau_grid("decade"), 450, 1.0),
            (std::vector<std::size_t>{1, 2, 4, 10, 20, 40, 100, 200, 400}));
}

TEST(TauGrid, LogRemovesDuplicates) {
  const auto ms = averaging_factors(parse_tau_grid("log:20"), 1000, 0.1);
  ASSERT_FALSE(ms.empty());
  EXPECT_EQ(ms.front(), 1u);
  EXPECT_EQ(ms.back(), 1000u);
  for (std::size_t i = 1; i < ms.size(); ++i) EXPECT_LT(ms[i - 1], ms[i]);
  // 10^(j/20) for j = 0..60 rounds to 1,1,1,1,2,2,2,2,3,... : 20 per decade
  // at most, fewer at the start where they collide.
  EXPECT_LT(ms.size(), 61u);
  EXPECT_GT(ms.size(), 40u);
}

TEST(TauGrid, ExplicitListInSeconds) {
  const auto ms = averaging_factors(parse_tau_grid("0.1, 1,10,1e6"), 1000, 0.1);
  EXPECT_EQ(ms, (std::vector<std::size_t>{1, 10, 100}));  // 1e6 s is beyond the record
}

TEST(TauGrid, RejectsGarbage) {
  EXPECT_THROW(parse_tau_grid("log:x"), std::invalid_argument);
  EXPECT_THROW(parse_tau_grid("1,-2"), std::invalid_argument);
  EXPECT_THROW(parse_tau_grid(""), std::invalid_argument);
}

TEST(Kernels, RateRampGivesExactClosedForm) {
  // y_i = R i tau0 (a linear frequency drift): AVAR = R^2 tau^2 / 2 at every m.
  const double R = 3e-4, tau0 = 0.5;
  std::vector<double> y(2000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = R * static_cast<double>(i) * tau0;
  const auto x = freq_to_phase(y, tau0);
  for (std::size_t m : {1u, 7u, 64u, 400u}) {
    const double tau = static_cast<double>(m) * tau0;
    EXPECT_NEAR(oavar(x, m, tau0).var / (R * R * tau * tau / 2.0), 1.0, 1e-9) << m;
    EXPECT_NEAR(avar(x, m, tau0).var / (R * R * tau * tau / 2.0), 1.0, 1e-9) << m;
  }
}

TEST(Kernels, HadamardRemovesLinearDrift) {
  // A linear frequency drift is invisible to the Hadamard variance.
  std::vector<double> y(1000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 1e-3 * static_cast<double>(i);
  const auto x = freq_to_phase(y, 1.0);
  EXPECT_LT(ohvar(x, 10, 1.0).var, 1e-20);
  EXPECT_LT(hvar(x, 10, 1.0).var, 1e-20);
}

TEST(Kernels, CountsMatchStable32) {
  const auto x = freq_to_phase(white(1000, 1.0, 1), 1.0);  // N = 1001 phase points
  EXPECT_EQ(avar(x, 10, 1.0).n, 99u);
  EXPECT_EQ(oavar(x, 10, 1.0).n, 981u);
  EXPECT_EQ(mvar(x, 10, 1.0).n, 972u);
  EXPECT_EQ(hvar(x, 10, 1.0).n, 98u);
  EXPECT_EQ(ohvar(x, 10, 1.0).n, 971u);
  EXPECT_EQ(totvar(totvar_extend(x), 10, 1.0).n, 999u);
  EXPECT_EQ(oavar(x, 501, 1.0).n, 0u);  // beyond the record
}

// TOTVAR as SP 1065 eq. 25 writes it, term by term on the reflected record:
// defined for every m up to N - 1 (the reflection holds N - 2 points on
// each side), as AllanTools evaluates it; m = N is beyond the record.
TEST(Kernels, TotvarEqualsTheReflectedSumUpToNMinusOne) {
  const auto x = freq_to_phase(white(60, 1.0, 3), 1.0);  // N = 61
  const std::size_t N = x.size();
  const auto at = [&](std::ptrdiff_t i) {
    const auto n = static_cast<std::ptrdiff_t>(N);
    if (i < 0) return 2.0 * x[0] - x[static_cast<std::size_t>(-i)];
    if (i >= n) return 2.0 * x[N - 1] - x[static_cast<std::size_t>(2 * (n - 1) - i)];
    return x[static_cast<std::size_t>(i)];
  };
  const TotvarExtension e = totvar_extend(x);
  for (std::size_t m = 1; m <= N - 1; ++m) {
    double sum = 0.0;
    const auto d = static_cast<std::ptrdiff_t>(m);
    for (std::ptrdiff_t i = 1; i <= static_cast<std::ptrdiff_t>(N) - 2; ++i) {
      const double s = at(i - d) - 2.0 * at(i) + at(i + d);
      sum += s * s;
    }
    const double want = sum / (2.0 * static_cast<double>(m * m) * static_cast<double>(N - 2));
    const VarianceTerm v = totvar(e, m, 1.0);
    ASSERT_EQ(v.n, N - 2) << "m " << m;
    EXPECT_NEAR(v.var, want, 1e-12 * want) << "m " << m;
  }
  EXPECT_EQ(totvar(e, N, 1.0).n, 0u);
}

TEST(Kernels, WhiteFmWithinConfidenceIntervalOverSeeds) {
  // White FM: AVAR = sigma^2 tau0 / tau exactly. Over 40 seeds the true value
  // must fall inside the 68.3 % interval about 68 % of the time.
  const double sigma = 0.02, tau0 = 0.1;
  const std::size_t ms[] = {1, 10, 100};
  int inside = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const auto y = white(20000, sigma, seed);
    const StabilityRecord rec(y, DataType::freq, tau0, Stat::oadev);
    for (std::size_t m : ms) {
      StabilityOptions o;
      o.alpha = 0;  // known noise type
      const auto p = rec.evaluate(m, o);
      const double truth = sigma / std::sqrt(static_cast<double>(m));
      inside += (p.interval.lo <= truth && truth <= p.interval.hi);
      ++total;
    }
  }
  // Binomial(120, 0.683): mean 82, sd 5.1; +-4 sd.
  EXPECT_GT(inside, 61);
  EXPECT_LT(inside, 103);
}

TEST(NoiseId, IdentifiesPureNoises) {
  const auto wfm = white(5000, 1.0, 3);
  // Random-walk FM: integrate white FM.
  std::vector<double> rwfm(wfm.size());
  double acc = 0.0;
  for (std::size_t i = 0; i < wfm.size(); ++i) rwfm[i] = acc += wfm[i];
  // White PM: white phase.
  const auto wpm = white(5001, 1.0, 4);
  const auto xw = freq_to_phase(wfm, 1.0);
  const auto xr = freq_to_phase(rwfm, 1.0);
  for (std::size_t m : {1u, 4u, 16u}) {
    EXPECT_EQ(identify_noise(xw, m, Stat::oadev).alpha, 0) << m;
    EXPECT_EQ(identify_noise(xr, m, Stat::oadev).alpha, -2) << m;
    EXPECT_EQ(identify_noise(wpm, m, Stat::oadev).alpha, 2) << m;
  }
}

// The grid form shares one walk over the record among its factors; every
// result, the unrounded estimate included, must be the single-factor one to
// the bit. The lengths make whole blocks of 1024 averages (21505 points: 3072
// averages at m = 7, 1024 at m = 21) and a ragged end (100001), and the
// records give every noise type a spread of lag-1 estimates.
TEST(NoiseId, GridEqualsEachFactorToTheBit) {
  for (const std::size_t n : {std::size_t{21504}, std::size_t{100000}}) {
    const auto w = white(n, 1.0, 11);
    std::vector<double> mixed(n);
    double walk = 0.0;
    const auto steps = white(n, 0.02, 12);
    for (std::size_t i = 0; i < n; ++i) mixed[i] = w[i] + (walk += steps[i]);
    for (const std::vector<double>* y : {&w, static_cast<const std::vector<double>*>(&mixed)}) {
      const std::vector<double> x = freq_to_phase(*y, 0.1);
      std::vector<std::size_t> ms;
      for (std::size_t m = 1; m <= 64; ++m) ms.push_back(m);
      for (std::size_t m = 70; m < x.size(); m = m * 5 / 4) ms.push_back(m);
      ms.push_back(0);
      for (const Stat stat : {Stat::oadev, Stat::ohdev, Stat::mdev}) {
        const std::vector<NoiseId> grid = identify_noise(x, ms, stat);
        ASSERT_EQ(grid.size(), ms.size());
        for (std::size_t j = 0; j < ms.size(); ++j) {
          const NoiseId one = identify_noise(x, ms[j], stat);
          EXPECT_EQ(grid[j].alpha, one.alpha) << n << " m " << ms[j];
          EXPECT_EQ(grid[j].method, one.method) << n << " m " << ms[j];
          EXPECT_EQ(std::memcmp(&grid[j].alpha_est, &one.alpha_est, sizeof(double)), 0)
              << n << " m " << ms[j] << ": " << grid[j].alpha_est << " vs " << one.alpha_est;
          EXPECT_EQ(grid[j].b1, one.b1) << n << " m " << ms[j];
        }
      }
    }
  }
}

TEST(Edf, GreenhallMatchesStable32GpsVectors) {
  // docs/formulas/stability.md §7.1: Stable32 OADEV of the GPS record, N = 241 218 phase points.
  const std::size_t N = 241218;
  EXPECT_NEAR(edf_greenhall(0, 2, 8192, N, true, false), 41.93, 0.01);
  EXPECT_NEAR(edf_greenhall(0, 2, 16384, N, true, false), 19.87, 0.01);
  EXPECT_NEAR(edf_greenhall(0, 2, 32768, N, true, false), 8.869, 0.001);
  EXPECT_NEAR(edf_greenhall(1, 2, 1024, N, true, false), 2869.5, 0.1);
  EXPECT_NEAR(edf_greenhall(2, 2, 1, N, true, false), 124054, 1);
}

TEST(Edf, SimpleFormulasOfSp1065) {
  // docs/formulas/stability.md §7.2, N = 10 001 phase points.
  EXPECT_NEAR(edf_simple(0, 1, 10001), 6665.8, 0.1);
  EXPECT_NEAR(edf_simple(0, 100, 10001), 148.0, 0.05);
  EXPECT_NEAR(edf_simple(-2, 10, 10001), 997.3, 0.05);
  EXPECT_NEAR(edf_simple(-2, 1000, 10001), 7.40, 0.005);
}

TEST(Confidence, ChiSquaredFactors) {
  // docs/formulas/stability.md §6.2, 68.27 % factors.
  const struct {
    double edf, lo, hi;
  } ref[] = {
      {1, 0.7094, 4.9957}, {2, 0.7370, 2.4059}, {5, 0.7927, 1.5595}, {10, 0.8355, 1.3268}, {100, 0.9362, 1.0789}};
  for (const auto& r : ref) {
    const auto ci = chi2_interval(1.0, r.edf, 0.6827);
    EXPECT_NEAR(ci.lo, r.lo, 2e-4) << r.edf;
    EXPECT_NEAR(ci.hi, r.hi, 2e-4) << r.edf;
  }
  const auto c95 = chi2_interval(1.0, 10, 0.95);
  EXPECT_NEAR(c95.lo, 0.6987, 2e-4);
  EXPECT_NEAR(c95.hi, 1.7549, 2e-4);
  EXPECT_EQ(chi2_interval(1.0, 0.0, 0.683).hi, 0.0);  // no EDF, no interval
}

}  // namespace
}  // namespace cubecal

namespace cubecal {
namespace {

TEST(Stability, ScaleInvariantOverTheDoubleRange) {
  // Exact power-of-two scaling inside: 1e+150 and 1e-150 data give the same
  // relative deviations as unit data, without overflow or underflow.
  const auto y = white(5000, 1.0, 11);
  const std::size_t ms[] = {1, 10, 100};
  for (Stat st : {Stat::oadev, Stat::mdev, Stat::ohdev, Stat::totdev}) {
    const auto ref = stability(y, DataType::freq, 1.0, st, ms);
    for (double f : {1e150, 1e-150}) {
      std::vector<double> z(y);
      for (double& v : z) v *= f;
      const auto got = stability(z, DataType::freq, 1.0, st, ms);
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(got[k].dev / (ref[k].dev * f), 1.0, 1e-12) << to_string(st) << " " << f;
        EXPECT_EQ(got[k].alpha, ref[k].alpha);
      }
    }
  }
}

TEST(Stability, RejectsNonFiniteSamples) {
  std::vector<double> y(100, 1.0);
  y[42] = std::nan("");
  EXPECT_THROW(StabilityRecord(y, DataType::freq, 1.0, Stat::oadev), std::invalid_argument);
  y[42] = HUGE_VAL;
  EXPECT_THROW(StabilityRecord(y, DataType::phase, 1.0, Stat::oadev), std::invalid_argument);
}

}  // namespace
}  // namespace cubecal

namespace cubecal {
namespace {

using cubecal::test::reason_of;

TEST(TemperatureFit, ErrorsCarryTheirReason) {
  // A bias of 0.02 per degree over a ramp from 10 to 40 degrees.
  std::vector<double> temp, y;
  for (int i = 0; i < 200; ++i) {
    temp.push_back(10.0 + 0.15 * i);
    y.push_back(0.5 + 0.02 * temp.back());
  }
  auto reason = [](const std::vector<double>& yy, const std::vector<double>& tt, std::size_t order) {
    return reason_of([&] { (void)fit_temperature(yy, tt, order); });
  };
  EXPECT_EQ(reason(y, temp, 1), "(none)");
  EXPECT_NEAR(fit_temperature(y, temp, 1).coeff[1], 0.02, 1e-12);
  // bad_option: order 0 or 6.
  EXPECT_EQ(reason(y, temp, 0), "bad_option");
  EXPECT_EQ(reason(y, temp, 6), "bad_option");
  // bad_data: lengths differ.
  EXPECT_EQ(reason(std::vector<double>(y.begin(), y.end() - 1), temp, 1), "bad_data");
  // too_few_points: 3 samples for order 2.
  EXPECT_EQ(reason({1.0, 2.0, 3.0}, {10.0, 20.0, 30.0}, 2), "too_few_points");
  // degenerate: a constant temperature; two distinct temperatures for order 3.
  EXPECT_EQ(reason(y, std::vector<double>(temp.size(), 25.0), 1), "degenerate");
  std::vector<double> two_levels(temp.size());
  for (std::size_t i = 0; i < two_levels.size(); ++i) two_levels[i] = i % 2 ? 20.0 : 30.0;
  EXPECT_EQ(reason(y, two_levels, 3), "degenerate");
}

}  // namespace
}  // namespace cubecal

namespace cubecal {
namespace {

// The vectorised largest magnitude against the plain loop, on every length
// around its eight lanes, the maximum and a non-finite sample put at each
// place in turn (a lane or the tail could miss either).
TEST(LargestMagnitude, EqualsThePlainLoopAtEveryPlace) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 3.0);
  for (std::size_t n : {0u, 1u, 7u, 8u, 9u, 15u, 16u, 17u, 31u, 100u}) {
    std::vector<double> v(n);
    for (double& x : v) x = g(rng);
    for (std::size_t at = 0; at < n; ++at) {
      std::vector<double> w = v;
      w[at] = -1e6;  // the largest, negative
      const Magnitude m = largest_magnitude(w);
      EXPECT_EQ(m.largest, 1e6) << n << " " << at;
      EXPECT_TRUE(m.finite);
      for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
        std::vector<double> u = v;
        u[at] = bad;
        double plain = 0.0;
        for (std::size_t k = 0; k < n; ++k)
          if (std::isfinite(u[k])) plain = std::max(plain, std::fabs(u[k]));
        const Magnitude b = largest_magnitude(u);
        EXPECT_FALSE(b.finite) << n << " " << at;
        if (std::isnan(bad))
          EXPECT_EQ(b.largest, plain);  // a NaN is passed over
        else
          EXPECT_EQ(b.largest, HUGE_VAL);  // an infinity is the largest
      }
    }
  }
  EXPECT_EQ(largest_magnitude({}).largest, 0.0);
  EXPECT_THROW(power_of_two_scale(std::vector<double>{1.0, std::nan("")}), std::invalid_argument);
  EXPECT_EQ(power_of_two_scale(std::vector<double>{-3.0, 1.0}), 2.0);
}

}  // namespace
}  // namespace cubecal
