// The pieces behind the Python module's AllanTools-shaped cubecal.ci:
// Greenhall & Riley's EDF by case, their equations and tables, SP 1065's
// MTOT table on its own, and the published noise identification (lag-1
// autocorrelation, polynomial detrending, B1 and R(n)), against closed forms
// and seeded power-law noise.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/noise_id.hpp"

namespace cubecal {
namespace {

std::vector<double> white(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> v(n);
  for (double& e : v) e = g(rng);
  return v;
}

std::vector<double> cumsum(std::vector<double> v) {
  std::partial_sum(v.begin(), v.end(), v.begin());
  return v;
}

TEST(GreenhallCase, SameEdfAsTheStrideFunctionAndTheCaseOfEachBranch) {
  struct Row {
    int alpha, d;
    std::size_t m, n, stride;
    bool modified;
    std::string method;
  };
  // Stride 1 (overlapping) with m >= 34 makes J = 3m exceed J_max = 100.
  const Row rows[] = {
      {0, 2, 1, 31, 1, true, "1.1"},      {2, 2, 40, 300, 1, true, "1.2"},   {2, 2, 64, 300, 1, true, "1.3"},
      {0, 2, 1, 31, 1, false, "2.1a"},    {0, 2, 40, 160, 1, false, "2.1b"}, {0, 2, 40, 300, 1, false, "2.2"},
      {0, 2, 64, 300, 1, false, "2.3"},   {1, 2, 1, 31, 1, false, "3.1"},    {1, 2, 40, 300, 1, false, "3.2"},
      {1, 2, 64, 300, 1, false, "3.3"},   {2, 2, 8, 31, 1, false, "4.1"},    {2, 2, 1, 31, 1, false, "4.2"},
      {-4, 3, 40, 1000, 1, false, "2.2"}, {2, 3, 10, 31, 10, false, "4.1"},
  };
  for (const Row& r : rows) {
    const GreenhallEdf g = edf_greenhall_case(r.alpha, r.d, r.m, r.n, r.stride, r.modified);
    SCOPED_TRACE(r.method);
    EXPECT_EQ(std::string(g.method), r.method);
    EXPECT_GT(g.edf, 0.0);
    EXPECT_EQ(g.edf, edf_greenhall_stride(r.alpha, r.d, r.m, r.n, r.stride, r.modified));
  }
}

TEST(GreenhallCase, WhitePmLargeRIsTheClosedForm) {
  // Case 4.2: 1/edf = (a0 - a1/r)/M with a0 = C(4d, 2d)/C(2d, d)^2, a1 = d/2.
  const std::size_t m = 4, n = 1001;
  const double M = 1.0 + std::floor((1001.0 - 9.0) / 4.0);  // S = 1, L = 1 + 2m
  const double a0 = 70.0 / 36.0, a1 = 1.0;
  const GreenhallEdf g = edf_greenhall_case(2, 2, m, n, m, false);
  EXPECT_STREQ(g.method, "4.2");
  EXPECT_NEAR(g.edf, M / (a0 - a1 / M), 1e-12 * g.edf);
}

TEST(GreenhallCase, NoAnswerOutsideTheAlgorithm) {
  EXPECT_EQ(edf_greenhall_case(-1, 1, 4, 1000, 1, false).edf, 0.0);  // alpha + 2d <= 1
  EXPECT_STREQ(edf_greenhall_case(-1, 1, 4, 1000, 1, false).method, "");
  EXPECT_EQ(edf_greenhall_case(0, 2, 100, 50, 1, false).edf, 0.0);  // N below the filter's span
  EXPECT_EQ(edf_greenhall_case(0, 2, 4, 1000, 3, false).edf, 0.0);  // stride not dividing m
}

TEST(GreenhallPieces, KernelsAndSumsAreTheEquations) {
  EXPECT_EQ(greenhall::sw(-3.0, 2), -3.0);
  EXPECT_EQ(greenhall::sw(2.0, 0), 8.0);
  EXPECT_DOUBLE_EQ(greenhall::sw(2.0, 1), 4.0 * std::log(2.0));
  EXPECT_EQ(greenhall::sw(0.0, -3), 0.0);
  // F infinite: sw at alpha + 2; otherwise F^2 (2 sw(t) - sw(t - 1/F) - sw(t + 1/F)).
  EXPECT_EQ(greenhall::sx(1.5, INFINITY, 0), greenhall::sw(1.5, 2));
  EXPECT_DOUBLE_EQ(greenhall::sx(1.0, 2.0, 0),
                   4.0 * (2.0 * greenhall::sw(1.0, 0) - greenhall::sw(0.5, 0) - greenhall::sw(1.5, 0)));
  // d = 1: 2 sx(t) - sx(t-1) - sx(t+1).
  EXPECT_DOUBLE_EQ(greenhall::sz(0.5, 1.0, -1, 1),
                   2.0 * greenhall::sx(0.5, 1.0, -1) - greenhall::sx(-0.5, 1.0, -1) - greenhall::sx(1.5, 1.0, -1));
  // Eq. (13) from N, m, S, F is eq. (13) with its J and M worked out.
  const double m = 8.0, S = 8.0, F = 1.0, N = 500.0;
  const double M = 1.0 + std::floor(S * (N - (m / F + 2.0 * m)) / m);
  const double J = std::min(M, 3.0 * S);
  EXPECT_EQ(greenhall::edf_eq13(0, 2, m, S, F, N), greenhall::edf_direct(J, M, S, F, 0, 2));
  const double z0 = greenhall::sz(0.0, F, 0, 2);
  EXPECT_DOUBLE_EQ(greenhall::edf_direct(J, M, S, F, 0, 2), z0 * z0 * M / greenhall::basic_sum(J, M, S, F, 0, 2));
}

TEST(GreenhallPieces, Tables) {
  EXPECT_DOUBLE_EQ(greenhall::table1(2, 1).a0, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(greenhall::table2(0, 3).a1, 0.5);
  EXPECT_EQ(greenhall::table1(-1, 1).a0, 0.0);  // does not converge
  EXPECT_EQ(greenhall::table2(-4, 2).a1, 0.0);
  EXPECT_EQ(greenhall::table3(2).a0, 15.23);
  EXPECT_EQ(greenhall::table3(4).a0, 0.0);
}

TEST(MtotTable, EveryFactorUnboundedBelow) {
  EXPECT_DOUBLE_EQ(edf_mtotvar_table(0, 100.0, 1000.0), 1.10 * 10.0 - 1.2);
  EXPECT_DOUBLE_EQ(edf_mtotvar_table(2, 2.0, 3.0), 1.90 * 1.5 - 2.1);
  EXPECT_LT(edf_mtotvar_table(-2, 1000.0, 100.0), 0.0);
  EXPECT_EQ(edf_mtotvar_table(-3, 10.0, 100.0), 0.0);
  // edf_mtotvar is the table from m = 10 on.
  EXPECT_DOUBLE_EQ(edf_mtotvar(-1, 16, 1024), edf_mtotvar_table(-1, 16.0, 1024.0));
}

TEST(Lag1Acf, AlternatingSeriesAndWhiteNoise) {
  std::vector<double> alt(100);
  for (std::size_t i = 0; i < alt.size(); ++i) alt[i] = i % 2 ? -1.0 : 1.0;
  EXPECT_DOUBLE_EQ(lag1_acf(alt), -99.0 / 100.0);
  const auto w = white(10000, 7);
  EXPECT_LT(std::abs(lag1_acf(w)), 3.0 / std::sqrt(10000.0));
  EXPECT_EQ(lag1_acf(std::vector<double>{1.0}), 0.0);
  EXPECT_EQ(lag1_acf(std::vector<double>(5, 2.0)), 0.0);
}

TEST(Detrend, RemovesThePolynomialAndNothingElse) {
  std::vector<double> q(200);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double t = static_cast<double>(i);
    q[i] = 3.0 + 2.0 * t + 0.5 * t * t;
  }
  for (const double r : detrend(q, 2)) EXPECT_NEAR(r, 0.0, 1e-8);
  // Degree 1: the residual is orthogonal to 1 and to the index.
  const auto r1 = detrend(q, 1);
  double s0 = 0.0, s1 = 0.0, s2 = 0.0;
  for (std::size_t i = 0; i < r1.size(); ++i) {
    s0 += r1[i];
    s1 += r1[i] * static_cast<double>(i);
    s2 += r1[i] * r1[i];
  }
  EXPECT_NEAR(s0, 0.0, 1e-8 * std::sqrt(s2));
  EXPECT_NEAR(s1, 0.0, 1e-6 * std::sqrt(s2));
  EXPECT_GT(s2, 1.0);
  EXPECT_TRUE(detrend(q, 9).empty());
  EXPECT_TRUE(detrend(std::vector<double>{1.0, 2.0}, 2).empty());
}

TEST(B1AndRn, ExpectedValues) {
  EXPECT_EQ(b1_expected(50.0, -1), 1.0);
  EXPECT_DOUBLE_EQ(b1_expected(10.0, 2), 10.0 * 11.0 / 6.0);
  EXPECT_DOUBLE_EQ(b1_expected(10.0, 1), 5.0);
  EXPECT_DOUBLE_EQ(b1_expected(10.0, -2), 99.0 / (1.5 * 10.0 * 9.0));
  EXPECT_DOUBLE_EQ(rn_expected(4.0, 2), 0.25);
  EXPECT_EQ(rn_expected(4.0, 0), 1.0);
  const double pi = 3.14159265358979323846;
  EXPECT_DOUBLE_EQ(rn_expected(4.0, 1), (3.0 * std::log(256.0 / 27.0) / 2.0) / (1.038 + 3.0 * std::log(4.0 * pi)));
}

TEST(B1AndRn, SeededNoiseGivesTheExpectedRatios) {
  // White FM: B1 = 1 (spread about sqrt(2/K) for K averages); white PM:
  // R(n) = 1/m.
  const auto wfm = cumsum(white(200001, 11));
  EXPECT_NEAR(b1_ratio(wfm, 4), 1.0, 0.05);
  const auto wpm = white(200001, 12);
  EXPECT_NEAR(rn_ratio(wpm, 8) * 8.0, 1.0, 0.05);
  // Random-walk FM: B1 = N/2 for mu = 1 (well above the white-FM value).
  const auto rw = cumsum(cumsum(white(20001, 13)));
  EXPECT_GT(b1_ratio(rw, 100), 10.0);
  EXPECT_EQ(b1_ratio(wfm, 0), 0.0);
  EXPECT_EQ(rn_ratio(std::vector<double>(10, 1.0), 2), 0.0);
}

TEST(Lag1NoiseId, PowerLawNoiseTypes) {
  const auto wpm = white(20000, 21);
  const auto wfm = cumsum(white(20000, 22));
  const auto rwfm = cumsum(cumsum(white(20000, 23)));
  EXPECT_EQ(lag1_noise_id(wpm, 4, DataType::phase, 0, 2)->alpha_int, 2);
  EXPECT_EQ(lag1_noise_id(wfm, 4, DataType::phase, 0, 2)->alpha_int, 0);
  EXPECT_EQ(lag1_noise_id(rwfm, 4, DataType::phase, 0, 2)->alpha_int, -2);
  EXPECT_EQ(lag1_noise_id(white(20000, 24), 8, DataType::freq, 0, 2)->alpha_int, 0);
  const auto id = lag1_noise_id(wfm, 1, DataType::phase, 0, 2);
  EXPECT_EQ(id->d, 1);
  EXPECT_NEAR(id->alpha, 2.0 - 2.0 * (id->rho + 1.0), 1e-12);
  // dmin forces differences: white PM differenced twice is still called.
  EXPECT_EQ(lag1_noise_id(wpm, 1, DataType::phase, 2, 2)->d, 2);
  // Fewer than 30 points at af: no answer.
  EXPECT_FALSE(lag1_noise_id(wpm, 1000, DataType::phase, 0, 2).has_value());
  EXPECT_FALSE(lag1_noise_id(wpm, 1000, DataType::freq, 0, 2).has_value());
}

}  // namespace
}  // namespace cubecal
