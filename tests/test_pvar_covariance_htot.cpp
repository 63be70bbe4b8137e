// The kernels AllanTools' API exposes beyond Stable32's statistics
// (stats/kernels.hpp): PVAR against its definition summed directly
// and against SigmaTheta's PDEV of the NBS14 1000-point record, the
// Groslambert covariance by its identities (OAVAR on the diagonal,
// bilinear, symmetric), and HTOT of frequency data against its definition
// at every factor, m = 1 included.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/stability.hpp"
#include "direct_total.hpp"

namespace cubecal {
namespace {

std::vector<double> white(std::size_t n, unsigned seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> w(0.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = w(g);
  return v;
}

std::vector<double> cumulative(const std::vector<double>& y) {
  std::vector<double> x(y.size() + 1, 0.0);
  for (std::size_t i = 0; i < y.size(); ++i) x[i + 1] = x[i] + y[i];
  return x;
}

// Vernotte et al. 2016, eq. of PVAR, summed as written.
double direct_pvar(const std::vector<double>& x, std::size_t m, double tau0) {
  const std::size_t M = x.size() - 2 * m;
  const double md = static_cast<double>(m);
  double sum = 0.0;
  for (std::size_t i = 0; i < M; ++i) {
    double s = 0.0;
    for (std::size_t k = 0; k < m; ++k) s += ((md - 1.0) / 2.0 - static_cast<double>(k)) * (x[i + k] - x[i + k + m]);
    sum += s * s;
  }
  return 72.0 * sum / (static_cast<double>(M) * md * md * md * md * (md * tau0) * (md * tau0));
}

// The NBS14 1000-point frequency record (NIST SP 1065 p. 107): the
// Lehmer generator n' = 16807 n mod 2^31 - 1 from 1234567890, scaled to [0, 1].
std::vector<double> nbs14_1000() {
  std::vector<double> y(1000);
  std::uint64_t n = 1234567890;
  for (double& v : y) {
    v = static_cast<double>(n) / 2147483647.0;
    n = (16807 * n) % 2147483647;
  }
  return y;
}

TEST(Pvar, MatchesItsDefinitionAtEveryFactor) {
  const auto x = cumulative(white(700, 1));
  for (std::size_t m : {2u, 3u, 4u, 7u, 16u, 33u, 100u, 349u, 350u}) {
    const VarianceTerm t = pvar(x, m, 0.25);
    EXPECT_EQ(t.n, x.size() - 2 * m) << m;
    EXPECT_NEAR(t.var, direct_pvar(x, m, 0.25), 1e-11 * t.var) << m;
  }
  // m = 1: the overlapping Allan variance; too long a factor: no term.
  EXPECT_DOUBLE_EQ(pvar(x, 1, 0.25).var, oavar(x, 1, 0.25).var);
  EXPECT_EQ(pvar(x, 351, 0.25).n, 0u);
}

TEST(Pvar, EqualsSigmaThetaOnNbs14) {
  // SigmaTheta v3.0 `PDev` of the NBS14 1000-point frequency record, tau0 = 1 s
  // (quoted in AllanTools' tests/nbs14/test_nbs14_1000point.py).
  const double want[] = {2.9223187810675200e-01, 2.1445233564252639e-01, 1.5618112158618463e-01,
                         1.1709745745448434e-01, 6.9029585189839343e-02, 4.9749707730398392e-02,
                         3.8947417330713739e-02, 3.0862392741372108e-02, 1.2447414341332683e-02};
  const auto x = cumulative(nbs14_1000());
  std::size_t m = 1;
  for (const double w : want) {
    EXPECT_NEAR(std::sqrt(pvar(x, m, 1.0).var), w, 1e-11 * w) << m;  // SigmaTheta's 17 digits agree to 1e-12
    m *= 2;
  }
}

TEST(AllanCovariance, IsOavarOnTheDiagonalBilinearAndSymmetric) {
  const auto a = cumulative(white(500, 2)), b = white(501, 3), c = white(501, 4);
  std::vector<double> ab(a.size()), ac(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ab[i] = a[i] + b[i];
    ac[i] = a[i] + 2.0 * c[i];
  }
  for (std::size_t m : {1u, 2u, 5u, 64u, 250u}) {
    const VarianceTerm aa = allan_covariance(a, a, m, 2.0);
    EXPECT_NEAR(aa.var, oavar(a, m, 2.0).var, 1e-12 * aa.var) << m;
    EXPECT_EQ(aa.n, a.size() - 2 * m);
    // cov(a + b, a + 2c) = cov(a, a) + 2 cov(a, c) + cov(b, a) + 2 cov(b, c)
    const double want = aa.var + 2.0 * allan_covariance(a, c, m, 2.0).var + allan_covariance(b, a, m, 2.0).var +
                        2.0 * allan_covariance(b, c, m, 2.0).var;
    const double got = allan_covariance(ab, ac, m, 2.0).var;
    EXPECT_NEAR(got, want, 1e-10 * (std::abs(want) + aa.var)) << m;
    EXPECT_DOUBLE_EQ(allan_covariance(b, c, m, 2.0).var, allan_covariance(c, b, m, 2.0).var) << m;
  }
  // Independent records: the covariance at m = 1 is within a few standard errors of zero.
  const VarianceTerm bc = allan_covariance(b, c, 1, 1.0);
  EXPECT_LT(std::abs(bc.var), 5.0 * 3.0 / std::sqrt(static_cast<double>(bc.n)));
  EXPECT_EQ(allan_covariance(a, std::vector<double>(a.size() - 1), 1, 1.0).n, 0u);
  EXPECT_EQ(allan_covariance(a, a, 251, 1.0).n, 0u);
}

TEST(HtotvarFrequency, MatchesTheDefinitionAtEveryFactor) {
  const auto y = cumulative(white(300, 5));  // a random-walk frequency record
  for (std::size_t m : {1u, 2u, 3u, 10u, 33u, 100u}) {
    const VarianceTerm t = htotvar_frequency(y, m);
    EXPECT_EQ(t.n, y.size() - 3 * m + 1) << m;
    EXPECT_NEAR(t.var, test::direct_total(y, m) / 6.0, 1e-10 * t.var) << m;
  }
  EXPECT_EQ(htotvar_frequency(y, 101).n, 0u);
  // From m = 2 on it is the HTOTDEV the statistic gives (which takes OHDEV at m = 1).
  const StabilityRecord r(y, DataType::freq, 1.0, Stat::htotdev);
  StabilityOptions none;
  none.intervals = false;
  for (std::size_t m : {2u, 9u, 50u}) {
    const double dev = r.evaluate(m, none).dev;
    EXPECT_NEAR(std::sqrt(htotvar_frequency(y, m).var), dev, 1e-12 * dev) << m;
  }
}

}  // namespace
}  // namespace cubecal
