// Rate-table calibration (docs/formulas/rate-table.md, the paper's eq. 6-13: docs/paper.md §2.6):
// plateau detection from reference columns, from the gyro signal and from a
// schedule; the forward fit and its inversion against exact and simulated
// data; the reported covariance against Monte Carlo; every bad-input path;
// and `cubecal calibrate rate-table` end to end.
#include <gtest/gtest.h>

#include "mat3.hpp"

#include "cli_runner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/rate_table.hpp"
#include "cubecal/error.hpp"
#include "reason_of.hpp"

namespace {

using cubecal::calibrate_rate_table;
using cubecal::Mat3;
using cubecal::Matrix;
using cubecal::Plateau;
using cubecal::PlateauDetection;
using cubecal::PlateauOptions;
using cubecal::RateTableCalibration;
using cubecal::ScheduleRow;
using cubecal::TriadRecord;
using Vec3 = std::array<double, 3>;
using cubecal::test::inverse;
using cubecal::test::mul;

// The paper's eq. (10) and (11), deg/s.
const Mat3 kPaperA{{{1.00330, 0.00792, 0.00798}, {0.00025, 1.02386, -0.01054}, {0.01879, 0.00047, 1.00042}}};
const Vec3 kPaperBeta{-289.59e-3, -1556.20e-3, 1627.19e-3};
// The forward model that produces them: w_g = S w + b_g, S = A^-1, b_g = -S beta.
Mat3 paper_S() { return inverse(kPaperA); }
Vec3 paper_bias() {
  const Vec3 sb = mul(paper_S(), kPaperBeta);
  return {-sb[0], -sb[1], -sb[2]};
}
// The paper's table rates about each axis (deg/s) and its gyro noise per
// sample at 10 Hz (sigma_n, docs/paper.md §3.1).
const std::vector<double> kPaperRates{0, 5, -5, 10, -10, 20, -20, 30, -30, 100, -100};
constexpr double kNoise = 14e-3;

// A simulated rate-table log: per axis x, y, z the rates held `plateau_s`
// each, linear ramps of `transition_s` between consecutive plateaus (also
// from one axis to the next), gyro = S w + b_g + white noise.
struct SimLog {
  double dt = 0.1;
  std::array<std::vector<double>, 3> gyro, ref;
  std::vector<ScheduleRow> schedule;  // the true plateaus, [start, start + plateau_s]

  TriadRecord record() const {
    TriadRecord r;
    for (int a = 0; a < 3; ++a) r.axes[a] = gyro[a];
    r.dt = dt;
    return r;
  }
  std::array<std::span<const double>, 3> reference() const { return {ref[0], ref[1], ref[2]}; }
  std::size_t size() const { return gyro[0].size(); }
};

struct RunSpec {
  std::vector<double> rates = kPaperRates;
  std::vector<int> axes{0, 1, 2};
  double plateau_s = 300.0;
  double transition_s = 20.0;
  double hz = 10.0;
};

SimLog simulate_run(const Mat3& S, const Vec3& bg, double sigma, std::uint64_t seed, const RunSpec& spec = {}) {
  std::vector<Vec3> rates;
  for (int axis : spec.axes)
    for (double r : spec.rates) {
      Vec3 w{};
      w[axis] = r;
      rates.push_back(w);
    }
  SimLog log;
  log.dt = 1.0 / spec.hz;
  const auto n_plateau = static_cast<std::size_t>(std::lround(spec.plateau_s * spec.hz));
  const auto n_ramp = static_cast<std::size_t>(std::lround(spec.transition_s * spec.hz));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  auto emit = [&](const Vec3& w) {
    const Vec3 g = mul(S, w);
    for (int a = 0; a < 3; ++a) {
      log.ref[a].push_back(w[a]);
      log.gyro[a].push_back(g[a] + bg[a] + (sigma > 0.0 ? noise(rng) : 0.0));
    }
  };
  for (std::size_t j = 0; j < rates.size(); ++j) {
    if (j > 0)
      for (std::size_t i = 0; i < n_ramp; ++i) {
        const double f = static_cast<double>(i + 1) / static_cast<double>(n_ramp + 1);
        Vec3 w{};
        for (int a = 0; a < 3; ++a) w[a] = rates[j - 1][a] + f * (rates[j][a] - rates[j - 1][a]);
        emit(w);
      }
    const double t0 = static_cast<double>(log.size()) * log.dt;
    log.schedule.push_back({t0, t0 + spec.plateau_s, rates[j]});
    for (std::size_t i = 0; i < n_plateau; ++i) emit(rates[j]);
  }
  return log;
}

Plateau exact_plateau(const Mat3& S, const Vec3& bg, const Vec3& w) {
  Plateau p;
  p.n = 1000;
  p.end = 1000;
  p.ref = w;
  p.has_ref = true;
  const Vec3 g = mul(S, w);
  for (int a = 0; a < 3; ++a) p.mean[a] = g[a] + bg[a];
  return p;
}

// Largest |estimate - truth| and |estimate - truth| / sigma, for A and beta.
struct Errors {
  double A_abs = 0.0, A_sigmas = 0.0, beta_abs = 0.0, beta_sigmas = 0.0;
};
Errors paper_errors(const RateTableCalibration& c) {
  Errors e;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double d = std::fabs(c.A[i][k] - kPaperA[i][k]);
      e.A_abs = std::max(e.A_abs, d);
      e.A_sigmas = std::max(e.A_sigmas, d / c.A_sigma[i][k]);
    }
    const double d = std::fabs(c.beta[i] - kPaperBeta[i]);
    e.beta_abs = std::max(e.beta_abs, d);
    e.beta_sigmas = std::max(e.beta_sigmas, d / c.beta_sigma[i]);
  }
  return e;
}

void expect_paper_recovered(const RateTableCalibration& c, const char* how) {
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(c.A[i][k], kPaperA[i][k], 1e-3) << how << " A" << i << k;
      EXPECT_NEAR(c.A[i][k], kPaperA[i][k], 3.0 * c.A_sigma[i][k]) << how << " A" << i << k;
      EXPECT_GT(c.A_sigma[i][k], 0.0);
    }
    EXPECT_NEAR(c.beta[i], kPaperBeta[i], 1e-3) << how << " beta" << i;
    EXPECT_NEAR(c.beta[i], kPaperBeta[i], 3.0 * c.beta_sigma[i]) << how << " beta" << i;
  }
  const Errors e = paper_errors(c);
  std::printf(
      "[ paper eq. 10-11 from %s ] A: max |error| %.2g (%.2f sigma, sigma ~%.2g); "
      "beta: max |error| %.2g deg/s (%.2f sigma, sigma ~%.2g deg/s)\n",
      how, e.A_abs, e.A_sigmas, c.A_sigma[0][0], e.beta_abs, e.beta_sigmas, c.beta_sigma[0]);
}

// Normalized estimation error squared e^T P^-1 e by Cholesky.
double nees(const std::array<double, 12>& e, const Matrix& P) {
  std::array<std::array<double, 12>, 12> L{};
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j <= i; ++j) {
      double s = P(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
      for (int k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      L[i][j] = i == j ? std::sqrt(s) : s / L[j][j];
    }
  std::array<double, 12> y{};
  double q = 0.0;
  for (int i = 0; i < 12; ++i) {
    double s = e[i];
    for (int k = 0; k < i; ++k) s -= L[i][k] * y[k];
    y[i] = s / L[i][i];
    q += y[i] * y[i];
  }
  return q;
}

// ---------------------------------------------------------------------------
// (1) docs/formulas/rate-table.md §7.1: exact recovery from noise-free +-1 rad/s plateaus.

TEST(RateTable, FormulasTestCaseIsRecoveredExactly) {
  const Mat3 S{{{1.01, .002, -.003}, {.001, .99, .004}, {-.002, .003, 1.005}}};
  const Vec3 bg{0.01, -0.02, 0.005};
  std::vector<Plateau> plateaus;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0}) {
      Vec3 w{};
      w[axis] = sign;
      plateaus.push_back(exact_plateau(S, bg, w));
    }
  const RateTableCalibration c = calibrate_rate_table(plateaus);
  const Mat3 A_expected{{{0.990106868, -0.002009196, 0.00296354},
                         {-0.001008081, 1.010115240, -0.004023368},
                         {0.001973371, -0.003019268, 0.995042783}}};
  const Mat3 A_exact = inverse(S);
  // As given to 9 significant digits in the reference values: A to 9 significant digits (A_yy = 1.010115240
  // is 1.0101152387 rounded, hence 2e-9 below), beta to 6.
  const Vec3 beta_expected{-0.00995607, 0.0202325, -0.00505533};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(c.S[i][k], S[i][k], 1e-12);
      EXPECT_NEAR(c.A[i][k], A_expected[i][k], 2e-9);
      EXPECT_NEAR(c.A[i][k], A_exact[i][k], 1e-12);
    }
    EXPECT_NEAR(c.bias[i], bg[i], 1e-12);
    EXPECT_NEAR(c.beta[i], -mul(A_exact, bg)[i], 1e-12);
    EXPECT_NEAR(c.beta[i], beta_expected[i], 5e-8);
  }
  EXPECT_EQ(c.plateaus, 6u);
  EXPECT_EQ(c.dof, 2u);
  EXPECT_LT(c.residual_after.max_abs, 1e-12);
  // Before calibration the +-1 rad/s plateaus are off by the bias and the
  // scale-factor errors: 0.01 + 0.01 + ... at most.
  EXPECT_GT(c.residual_before.max_abs, 0.01);
  EXPECT_NEAR(c.scale_factor_error[0], 0.01, 1e-12);
  EXPECT_NEAR(c.scale_factor_error[1], -0.01, 1e-12);
  EXPECT_NEAR(c.misalignment[0][1], std::atan(0.002 / 1.01), 1e-12);
  EXPECT_NEAR(c.misalignment[2][0], std::atan(-0.002 / 1.005), 1e-12);
  EXPECT_EQ(c.misalignment[1][1], 0.0);
}

TEST(RateTable, SymmetricDesignMatchesTheClosedForm) {
  // docs/formulas/rate-table.md §1.4: S col i = (w_+i - w_-i) / 2w, b_g = mean of the 6 plateaus;
  // with an unequal rate per axis the least-squares fit must still agree.
  const Mat3 S = paper_S();
  const Vec3 bg = paper_bias();
  std::vector<Plateau> plateaus;
  const Vec3 rate{7.0, 13.0, 55.0};
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0}) {
      Vec3 w{};
      w[axis] = sign * rate[axis];
      plateaus.push_back(exact_plateau(S, bg, w));
    }
  const RateTableCalibration c = calibrate_rate_table(plateaus);
  for (int i = 0; i < 3; ++i) {
    double mean = 0.0;
    for (const Plateau& p : plateaus) mean += p.mean[i] / 6.0;
    EXPECT_NEAR(c.bias[i], mean, 1e-12);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(c.S[i][k], (plateaus[2 * k].mean[i] - plateaus[2 * k + 1].mean[i]) / (2.0 * rate[k]), 1e-12);
  }
}

TEST(RateTable, EarthRateOnlyMovesTheBias) {
  const Mat3 S = paper_S();
  const Vec3 bg = paper_bias();
  std::vector<Plateau> plateaus;
  for (int axis = 0; axis < 3; ++axis)
    for (double r : {0.0, 10.0, -10.0}) {
      Vec3 w{};
      w[axis] = r;
      plateaus.push_back(exact_plateau(S, bg, w));
    }
  const RateTableCalibration ignored = calibrate_rate_table(plateaus);
  cubecal::RateTableOptions opt;
  // Vertical component at 45 deg latitude, in deg/s.
  constexpr double kDegPerRad = 180.0 / std::numbers::pi;
  opt.earth_rate = cubecal::earth_rate_along({0.0, 0.0, std::sqrt(0.5)}, kDegPerRad);
  EXPECT_NEAR(opt.earth_rate[2], 7.2921159e-5 * kDegPerRad * std::sqrt(0.5), 1e-15);
  const RateTableCalibration with = calibrate_rate_table(plateaus, opt);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(with.A[i][k], ignored.A[i][k], 1e-12);
    // w = A w_g + beta: the true rate grew by the Earth rate, so beta does.
    EXPECT_NEAR(with.beta[i] - ignored.beta[i], opt.earth_rate[i], 1e-12);
  }
}

// ---------------------------------------------------------------------------
// (2) The paper's A (eq. 10) and beta (eq. 11) from a simulated rate-table run.

TEST(RateTable, PaperCalibrationFromReferenceColumns) {
  const SimLog log = simulate_run(paper_S(), paper_bias(), kNoise, 20240611);
  const PlateauDetection found = cubecal::plateaus_from_reference(log.record(), log.reference());
  ASSERT_EQ(found.plateaus.size(), 33u);  // 11 rates about each of 3 axes
  EXPECT_EQ(found.dropped_short, 0u);
  // 300 s plateaus at 10 Hz less 10 s at both ends.
  EXPECT_EQ(found.plateaus[0].n, 2800u);
  EXPECT_DOUBLE_EQ(found.plateaus[0].t_begin, 10.0);
  EXPECT_NEAR(found.plateaus[0].t_end, 289.9, 1e-9);
  EXPECT_NEAR(found.plateaus[0].stddev[0], kNoise, 0.1 * kNoise);
  EXPECT_EQ(found.plateaus[9].ref[0], 100.0);
  EXPECT_EQ(found.plateaus[13].ref[1], -5.0);

  const RateTableCalibration c = calibrate_rate_table(found.plateaus);
  EXPECT_EQ(c.dof, 29u);
  EXPECT_TRUE(c.noise_from_residuals);
  expect_paper_recovered(c, "reference columns");
  // Before calibration: the 1.6 deg/s bias and 2 % scale errors at 100 deg/s;
  // after: the noise of a 280 s mean, 14e-3 / sqrt(2800) = 2.6e-4 deg/s.
  EXPECT_GT(c.residual_before.max_abs, 1.5);
  EXPECT_LT(c.residual_after.rms, 5e-4);
  EXPECT_LT(c.residual_after.max_abs, 1.5e-3);
  // Eq. (12): the calibrated samples scatter with A's rows times the noise.
  for (int i = 0; i < 3; ++i) {
    double row2 = 0.0;
    for (int k = 0; k < 3; ++k) row2 += kPaperA[i][k] * kPaperA[i][k];
    EXPECT_NEAR(c.error_covariance[i][i], kNoise * kNoise * row2, 0.05 * kNoise * kNoise);
  }
  EXPECT_NEAR(c.error_covariance[0][1], c.error_covariance[1][0], 1e-18);
}

TEST(RateTable, PaperCalibrationFromSignalWithKnownSchedule) {
  const SimLog log = simulate_run(paper_S(), paper_bias(), kNoise, 77);
  const PlateauDetection raw = cubecal::plateaus_from_signal(log.record());
  EXPECT_EQ(raw.plateaus.size(), 33u);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(raw.noise[a], kNoise, 0.1 * kNoise);
  for (const Plateau& p : raw.plateaus) EXPECT_FALSE(p.has_ref);
  const PlateauDetection found = cubecal::label_with_schedule(raw, log.schedule);
  ASSERT_EQ(found.plateaus.size(), 33u);
  EXPECT_EQ(found.unmatched, 0u);
  // Each plateau lies inside its schedule interval, transitions excluded.
  for (std::size_t j = 0; j < 33; ++j) {
    EXPECT_GE(found.plateaus[j].t_begin, log.schedule[j].t_begin);
    EXPECT_LE(found.plateaus[j].t_end, log.schedule[j].t_end);
    EXPECT_GT(found.plateaus[j].n, 2500u);
    EXPECT_EQ(found.plateaus[j].ref, log.schedule[j].rate);
  }
  expect_paper_recovered(calibrate_rate_table(found.plateaus), "gyro signal + schedule");
}

TEST(RateTable, PaperCalibrationFromSchedule) {
  const SimLog log = simulate_run(paper_S(), paper_bias(), kNoise, 5);
  std::vector<ScheduleRow> rows = log.schedule;
  // A row past the end of the record (another axis's run) is skipped.
  rows.push_back({1e6, 1e6 + 300.0, {0.0, 0.0, 50.0}});
  const PlateauDetection found = cubecal::plateaus_from_schedule(log.record(), rows);
  ASSERT_EQ(found.plateaus.size(), 33u);
  EXPECT_EQ(found.skipped_rows, 1u);
  EXPECT_EQ(found.plateaus[0].n, 2801u);  // [10, 290] s inclusive at 10 Hz
  expect_paper_recovered(calibrate_rate_table(found.plateaus), "schedule");
}

// ---------------------------------------------------------------------------
// (3) The reported covariance is the estimator's: mean NEES over 100 runs.

TEST(RateTable, MonteCarloNeesMatchesReportedCovariance) {
  const Mat3 S = paper_S();
  const Vec3 bg = paper_bias();
  RunSpec spec;
  constexpr int kRuns = 100;
  double forward = 0.0, inverse_form = 0.0;
  std::size_t dof = 0;
  for (int seed = 1; seed <= kRuns; ++seed) {
    const SimLog log = simulate_run(S, bg, kNoise, static_cast<std::uint64_t>(seed) * 7919u, spec);
    const PlateauDetection found = cubecal::plateaus_from_reference(log.record(), log.reference());
    const RateTableCalibration c = calibrate_rate_table(found.plateaus);
    dof = c.dof;
    std::array<double, 12> ef{}, ei{};
    for (int k = 0; k < 3; ++k) {
      for (int m = 0; m < 3; ++m) {
        ef[4 * k + m] = c.S[k][m] - S[k][m];
        ei[4 * k + m] = c.A[k][m] - kPaperA[k][m];
      }
      ef[4 * k + 3] = c.bias[k] - bg[k];
      ei[4 * k + 3] = c.beta[k] - kPaperBeta[k];
    }
    forward += nees(ef, c.forward_cov) / kRuns;
    inverse_form += nees(ei, c.inverse_cov) / kRuns;
  }
  // With R estimated on nu residual dof, E[NEES] = 12 nu / (nu - 4)
  // (inverse-Wishart mean): 13.9 for the paper's 33 plateaus.
  const double nu = static_cast<double>(dof);
  const double expected = 12.0 * nu / (nu - 4.0);
  std::printf(
      "[ NEES over %d runs ] forward (S, b_g) %.2f, inverse (A, beta) %.2f; expected %.2f (12 if R were known)\n",
      kRuns, forward, inverse_form, expected);
  EXPECT_NEAR(forward, 12.0, 3.0);
  EXPECT_NEAR(forward, expected, 2.0);
  EXPECT_NEAR(inverse_form, expected, 2.0);
}

// ---------------------------------------------------------------------------
// Detection details.

TEST(Plateaus, SignalDetectionMergesAcrossAShortDisturbance) {
  SimLog log = simulate_run(paper_S(), paper_bias(), kNoise, 9);
  // A 1 s knock in the middle of the +10 deg/s plateau about x.
  const auto mid = static_cast<std::size_t>(std::lround((log.schedule[3].t_begin + 150.0) / log.dt));
  for (std::size_t k = mid; k < mid + 10; ++k) log.gyro[1][k] += 2.0;
  const PlateauDetection found = cubecal::plateaus_from_signal(log.record());
  ASSERT_EQ(found.plateaus.size(), 33u);
  const Plateau& p = found.plateaus[3];
  EXPECT_LT(p.begin, mid);
  EXPECT_GT(p.end, mid + 10);
  EXPECT_LT(p.n, p.end - p.begin);  // the knock is not averaged
  const Vec3 expected = mul(paper_S(), Vec3{10.0, 0.0, 0.0});
  EXPECT_NEAR(p.mean[1], expected[1] + paper_bias()[1], 5.0 * kNoise / std::sqrt(static_cast<double>(p.n)));
}

TEST(Plateaus, SignalDetectionSplitsAStepTheMovingStdMisses) {
  // Two plateaus 0.1 deg/s apart with an instant step: the window across the
  // step is barely noisier (0.05 deg/s vs 3 x 0.014), the jump test splits it.
  SimLog log;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, kNoise);
  for (int k = 0; k < 2 * 1200; ++k)
    for (int a = 0; a < 3; ++a) log.gyro[a].push_back((a == 0 && k >= 1200 ? 0.1 : 0.0) + noise(rng));
  const PlateauDetection found = cubecal::plateaus_from_signal(log.record());
  ASSERT_EQ(found.plateaus.size(), 2u);
  EXPECT_LE(found.plateaus[0].end, 1200u);
  EXPECT_GE(found.plateaus[1].begin, 1200u);
  EXPECT_NEAR(found.plateaus[1].mean[0] - found.plateaus[0].mean[0], 0.1, 0.01);
}

TEST(Plateaus, NoPlateauSpansAGap) {
  const SimLog log = simulate_run(paper_S(), paper_bias(), kNoise, 11);
  TriadRecord rec = log.record();
  // A gap in the middle of the first plateau (samples 0..2999).
  const std::vector<std::size_t> breaks{1500};
  rec.breaks = breaks;
  const PlateauDetection found = cubecal::plateaus_from_reference(rec, log.reference());
  ASSERT_EQ(found.plateaus.size(), 34u);
  // Each piece's run is trimmed like any other: what the table did during
  // the gap is unknown.
  EXPECT_EQ(found.plateaus[0].end, 1400u);
  EXPECT_EQ(found.plateaus[1].begin, 1600u);
}

TEST(Plateaus, ReferenceRunsShorterThanTheMinimumAreDropped) {
  RunSpec spec;
  spec.rates = {0.0, 10.0, -10.0};
  spec.plateau_s = 45.0;  // 25 s after the margins
  const SimLog log = simulate_run(paper_S(), paper_bias(), kNoise, 1, spec);
  PlateauOptions opt;
  EXPECT_THROW(cubecal::plateaus_from_reference(log.record(), log.reference(), opt), cubecal::CalibrationError);
  opt.min_plateau_s = 20.0;
  const PlateauDetection found = cubecal::plateaus_from_reference(log.record(), log.reference(), opt);
  EXPECT_EQ(found.plateaus.size(), 9u);
  EXPECT_EQ(found.plateaus[0].n, 250u);
}

// ---------------------------------------------------------------------------
// (4) Bad input.

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const cubecal::CalibrationError& e) {
    return e.what();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(RateTableErrors, ThreePlateausAreNotEnough) {
  std::vector<Plateau> p;
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 w{};
    w[axis] = 10.0;
    p.push_back(exact_plateau(paper_S(), paper_bias(), w));
  }
  const std::string msg = message_of([&] { calibrate_rate_table(p); });
  EXPECT_NE(msg.find("3 plateaus are not enough"), std::string::npos) << msg;
  EXPECT_NE(msg.find("4 affinely independent"), std::string::npos) << msg;
  EXPECT_THROW(calibrate_rate_table(std::span<const Plateau>()), cubecal::CalibrationError);
}

TEST(RateTableErrors, DegenerateGeometryIsRefused) {
  std::vector<Plateau> p;
  for (double r : {5.0, -5.0, 10.0, -10.0, 100.0, -100.0})
    p.push_back(exact_plateau(paper_S(), paper_bias(), {r, 0.0, 0.0}));
  const std::string line = message_of([&] { calibrate_rate_table(p); });
  EXPECT_NE(line.find("degenerate"), std::string::npos) << line;
  EXPECT_NE(line.find("one axis"), std::string::npos) << line;
  // About two axes only: a plane, still not enough.
  p.push_back(exact_plateau(paper_S(), paper_bias(), {0.0, 10.0, 0.0}));
  const std::string plane = message_of([&] { calibrate_rate_table(p); });
  EXPECT_NE(plane.find("one plane"), std::string::npos) << plane;
  // One plateau about z makes it well posed.
  p.push_back(exact_plateau(paper_S(), paper_bias(), {0.0, 0.0, 10.0}));
  EXPECT_NO_THROW(calibrate_rate_table(p));
}

TEST(RateTableErrors, PlateauWithoutReferenceOrNonFinite) {
  std::vector<Plateau> p;
  for (int axis = 0; axis < 3; ++axis)
    for (double r : {10.0, -10.0}) {
      Vec3 w{};
      w[axis] = r;
      p.push_back(exact_plateau(paper_S(), paper_bias(), w));
    }
  p[2].has_ref = false;
  EXPECT_NE(message_of([&] { calibrate_rate_table(p); }).find("plateau 3 has no reference"), std::string::npos);
  p[2].has_ref = true;
  p[4].mean[1] = std::nan("");
  EXPECT_THROW(calibrate_rate_table(p), cubecal::CalibrationError);
}

TEST(RateTableErrors, OverlappingOrReversedScheduleRows) {
  const SimLog log = simulate_run(paper_S(), paper_bias(), 0.0, 1);
  std::vector<ScheduleRow> rows{{0, 300, {0, 0, 0}}, {320, 620, {5, 0, 0}}, {600, 900, {-5, 0, 0}}};
  const auto problem = cubecal::check_schedule(rows);
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->row, 2u);
  EXPECT_NE(problem->what.find("rows 2 and 3 overlap"), std::string::npos) << problem->what;
  EXPECT_THROW(cubecal::plateaus_from_schedule(log.record(), rows), cubecal::CalibrationError);
  EXPECT_THROW(cubecal::label_with_schedule(PlateauDetection{}, rows), cubecal::CalibrationError);
  rows[2] = {640, 630, {-5, 0, 0}};
  ASSERT_TRUE(cubecal::check_schedule(rows).has_value());
  EXPECT_NE(cubecal::check_schedule(rows)->what.find("ends before it begins"), std::string::npos);
  rows[2] = {620, 920, {-5, 0, 0}};  // touching is fine
  EXPECT_FALSE(cubecal::check_schedule(rows).has_value());
}

TEST(RateTableErrors, NoPlateauFound) {
  // The table never holds a rate: a continuous ramp.
  SimLog log;
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, kNoise);
  for (int k = 0; k < 6000; ++k)
    for (int a = 0; a < 3; ++a) {
      const double w = 0.05 * static_cast<double>(k) * log.dt;
      log.ref[a].push_back(w);
      log.gyro[a].push_back(w + noise(rng));
    }
  const std::string ref_msg = message_of([&] { cubecal::plateaus_from_reference(log.record(), log.reference()); });
  EXPECT_NE(ref_msg.find("no plateau found"), std::string::npos) << ref_msg;
  const std::string sig_msg = message_of([&] { cubecal::plateaus_from_signal(log.record()); });
  EXPECT_NE(sig_msg.find("no plateau found"), std::string::npos) << sig_msg;
  // A schedule for another run: every row outside the record.
  const std::vector<ScheduleRow> rows{{1000, 1300, {1, 0, 0}}};
  const std::string sched_msg = message_of([&] { cubecal::plateaus_from_schedule(log.record(), rows); });
  EXPECT_NE(sched_msg.find("no plateau found"), std::string::npos) << sched_msg;
  // Detected plateaus that no schedule row covers (the schedule of a later run).
  const SimLog run = simulate_run(paper_S(), paper_bias(), kNoise, 2);
  const std::vector<ScheduleRow> later{{2e5, 2e5 + 300, {1, 0, 0}}};
  const std::string label_msg =
      message_of([&] { cubecal::label_with_schedule(cubecal::plateaus_from_signal(run.record()), later); });
  EXPECT_NE(label_msg.find("no plateau found"), std::string::npos) << label_msg;
}

using cubecal::test::reason_of;

TEST(RateTableErrors, ErrorsCarryTheirReason) {
  std::vector<Plateau> p;
  for (int axis = 0; axis < 3; ++axis)
    for (double r : {10.0, -10.0}) {
      Vec3 w{};
      w[axis] = r;
      p.push_back(exact_plateau(paper_S(), paper_bias(), w));
    }
  EXPECT_EQ(reason_of([&] { calibrate_rate_table(p); }), "(none)");
  // too_few_points: 3 plateaus.
  EXPECT_EQ(reason_of([&] { calibrate_rate_table(std::span<const Plateau>(p).first(3)); }), "too_few_points");
  // bad_data: a plateau without a reference rate, a non-finite rate.
  auto q = p;
  q[2].has_ref = false;
  EXPECT_EQ(reason_of([&] { calibrate_rate_table(q); }), "bad_data");
  q = p;
  q[4].mean[1] = std::nan("");
  EXPECT_EQ(reason_of([&] { calibrate_rate_table(q); }), "bad_data");
  // degenerate: every rate about one axis; a gyro that does not sense z.
  std::vector<Plateau> x_only;
  for (double r : {5.0, -5.0, 10.0, -10.0, 100.0, -100.0})
    x_only.push_back(exact_plateau(paper_S(), paper_bias(), {r, 0.0, 0.0}));
  EXPECT_EQ(reason_of([&] { calibrate_rate_table(x_only); }), "degenerate");
  Mat3 blind = paper_S();
  for (auto& row : blind) row[2] = 0.0;
  std::vector<Plateau> blind_p;
  for (int axis = 0; axis < 3; ++axis)
    for (double r : {10.0, -10.0}) {
      Vec3 w{};
      w[axis] = r;
      blind_p.push_back(exact_plateau(blind, paper_bias(), w));
    }
  EXPECT_EQ(reason_of([&] { calibrate_rate_table(blind_p); }), "degenerate");

  // Plateau detection. bad_data: axes of different lengths, dt 0, reference
  // columns of another length, overlapping schedule rows.
  const SimLog log = simulate_run(paper_S(), paper_bias(), 0.0, 1);
  TriadRecord rec = log.record();
  rec.axes[2] = rec.axes[2].subspan(1);
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_signal(rec); }), "bad_data");
  rec = log.record();
  rec.dt = 0.0;
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_signal(rec); }), "bad_data");
  auto short_ref = log.reference();
  short_ref[1] = short_ref[1].first(10);
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_reference(log.record(), short_ref); }), "bad_data");
  const std::vector<ScheduleRow> overlapping{{0, 300, {0, 0, 0}}, {320, 620, {5, 0, 0}}, {600, 900, {-5, 0, 0}}};
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_schedule(log.record(), overlapping); }), "bad_data");
  EXPECT_EQ(reason_of([&] { cubecal::label_with_schedule(PlateauDetection{}, overlapping); }), "bad_data");
  // bad_option: a negative margin.
  PlateauOptions neg;
  neg.margin_s = -1.0;
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_signal(log.record(), neg); }), "bad_option");
  // no_plateaus: runs shorter than the minimum; a record shorter than one
  // detection window; an empty schedule; a schedule outside the record.
  RunSpec brief;
  brief.rates = {0.0, 10.0, -10.0};
  brief.plateau_s = 45.0;
  const SimLog short_runs = simulate_run(paper_S(), paper_bias(), kNoise, 1, brief);
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_reference(short_runs.record(), short_runs.reference()); }),
            "no_plateaus");
  TriadRecord tiny = log.record();
  for (auto& a : tiny.axes) a = a.first(5);
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_signal(tiny); }), "no_plateaus");
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_schedule(log.record(), std::vector<ScheduleRow>{}); }),
            "no_plateaus");
  const std::vector<ScheduleRow> later{{1e6, 1e6 + 300, {1, 0, 0}}};
  EXPECT_EQ(reason_of([&] { cubecal::plateaus_from_schedule(log.record(), later); }), "no_plateaus");
}

TEST(RateTableErrors, InconsistentRecord) {
  const SimLog log = simulate_run(paper_S(), paper_bias(), 0.0, 1);
  TriadRecord rec = log.record();
  rec.axes[2] = rec.axes[2].subspan(1);
  EXPECT_THROW(cubecal::plateaus_from_signal(rec), cubecal::CalibrationError);
  rec = log.record();
  rec.dt = 0.0;
  EXPECT_THROW(cubecal::plateaus_from_reference(rec, log.reference()), cubecal::CalibrationError);
}

// ---------------------------------------------------------------------------
// The command line.

namespace fs = std::filesystem;

using cubecal::test::CliRun;
using cubecal::test::one_error_line;
CliRun cubecal_cli(const std::string& args) { return cubecal::test::run_cubecal(args); }

class RateTableCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cubecal_rt_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A short run (0, +-10, +-100 deg/s, 60 s plateaus, 10 s ramps) as CSV:
  // t,gx,gy,gz,rx,ry,rz; and its schedule.
  std::string write_log(const std::string& name, const std::vector<int>& axes = {0, 1, 2}) {
    RunSpec spec;
    spec.rates = {0.0, 10.0, -10.0, 100.0, -100.0};
    spec.axes = axes;
    spec.plateau_s = 60.0;
    spec.transition_s = 10.0;
    log_ = simulate_run(paper_S(), paper_bias(), kNoise, 42, spec);
    const fs::path p = dir_ / name;
    FILE* f = std::fopen(p.c_str(), "w");
    std::fprintf(f, "t,gx,gy,gz,rx,ry,rz\n");
    for (std::size_t k = 0; k < log_.size(); ++k)
      std::fprintf(f, "%.1f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", static_cast<double>(k) * 0.1, log_.gyro[0][k],
                   log_.gyro[1][k], log_.gyro[2][k], log_.ref[0][k], log_.ref[1][k], log_.ref[2][k]);
    std::fclose(f);
    return p.string();
  }
  std::string write_schedule(const std::string& name, std::vector<ScheduleRow> rows) {
    const fs::path p = dir_ / name;
    std::ofstream out(p);
    out << "t_begin,t_end,wx,wy,wz\n";
    for (const auto& r : rows)
      out << r.t_begin << ',' << r.t_end << ',' << r.rate[0] << ',' << r.rate[1] << ',' << r.rate[2] << '\n';
    return p.string();
  }

  fs::path dir_;
  SimLog log_;
};

TEST_F(RateTableCli, JsonFromReferenceColumns) {
  const std::string log = write_log("run.csv");
  const CliRun r =
      cubecal_cli("calibrate rate-table " + log + " --columns gx,gy,gz --ref-columns rx,ry,rz --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* k : {"A", "beta", "A_sigma", "beta_sigma", "residual_before", "residual_after", "error_covariance",
                        "plateaus", "forward", "unit"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["unit"], "deg/s");
  ASSERT_EQ(j["plateaus"].size(), 15u);
  for (const char* k : {"t_begin", "t_end", "n", "ref", "gyro", "gyro_std"})
    EXPECT_TRUE(j["plateaus"][0].contains(k)) << k;
  EXPECT_EQ(j["plateaus"][0]["n"], 400);
  for (const char* k : {"S", "bias", "scale_factor_ppm", "misalignment_mrad"})
    EXPECT_TRUE(j["forward"].contains(k)) << k;
  EXPECT_EQ(j["forward"]["misalignment_mrad"].size(), 6u);
  EXPECT_TRUE(j["residual_after"].contains("max"));
  EXPECT_TRUE(j["residual_after"].contains("rms"));
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double a = j["A"][i][k].get<double>();
      EXPECT_NEAR(a, kPaperA[i][k], 4.0 * j["A_sigma"][i][k].get<double>());
    }
    EXPECT_NEAR(j["beta"][i].get<double>(), kPaperBeta[i], 4.0 * j["beta_sigma"][i].get<double>());
  }
  const double ppm_x = j["forward"]["scale_factor_ppm"][0].get<double>();
  EXPECT_NEAR(ppm_x, 1e6 * (paper_S()[0][0] - 1.0), 100.0);
  EXPECT_NEAR(j["forward"]["misalignment_mrad"]["xy"].get<double>(), 1e3 * std::atan(paper_S()[0][1] / paper_S()[0][0]),
              0.1);
}

TEST_F(RateTableCli, TableFromScheduleAndFromSignal) {
  const std::string log = write_log("run.csv");
  const std::string sched = write_schedule("schedule.csv", log_.schedule);
  const CliRun table = cubecal_cli("calibrate rate-table " + log + " --columns gx,gy,gz --schedule " + sched);
  ASSERT_EQ(table.code, 0) << table.err;
  EXPECT_NE(table.out.find("15 plateaus from the schedule"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("w = A w_g + beta"), std::string::npos);
  EXPECT_NE(table.out.find("misalignment"), std::string::npos);

  const std::string out = (dir_ / "cal.json").string();
  // The signal detection drops about a window at each transition besides
  // the margins: shorter settings for 60 s plateaus.
  const CliRun sig = cubecal_cli("calibrate rate-table " + log + " --columns gx,gy,gz --schedule " + sched +
                                 " --from-signal --window 5 --min-plateau 20 --format json --out " + out);
  ASSERT_EQ(sig.code, 0) << sig.err;
  EXPECT_TRUE(sig.out.empty());
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["plateaus"].size(), 15u);
  EXPECT_NEAR(j["A"][1][1].get<double>(), kPaperA[1][1], 4.0 * j["A_sigma"][1][1].get<double>());

  // Never replaced unasked.
  const auto before = fs::file_size(out);
  const CliRun again =
      cubecal_cli("calibrate rate-table " + log + " --columns gx,gy,gz --schedule " + sched + " --out " + out);
  EXPECT_TRUE(one_error_line(again)) << again.err;
  EXPECT_NE(again.err.find("already exists"), std::string::npos);
  EXPECT_EQ(fs::file_size(out), before);
}

TEST_F(RateTableCli, ErrorsAreOneLineWithExitCode2) {
  const std::string log = write_log("run.csv");
  const std::string base = "calibrate rate-table " + log + " --columns gx,gy,gz";

  const CliRun neither = cubecal_cli(base);
  EXPECT_TRUE(one_error_line(neither)) << neither.err;
  EXPECT_NE(neither.err.find("--ref-columns"), std::string::npos);

  const std::string sched = write_schedule("s.csv", log_.schedule);
  const CliRun both = cubecal_cli(base + " --ref-columns rx,ry,rz --schedule " + sched);
  EXPECT_TRUE(one_error_line(both)) << both.err;

  const CliRun signal_alone = cubecal_cli(base + " --from-signal");
  EXPECT_TRUE(one_error_line(signal_alone)) << signal_alone.err;

  const CliRun two_refs = cubecal_cli(base + " --ref-columns rx,ry");
  EXPECT_TRUE(one_error_line(two_refs)) << two_refs.err;

  const CliRun two_axes = cubecal_cli("calibrate rate-table " + log + " --columns gx,gy --ref-columns rx,ry,rz");
  EXPECT_TRUE(one_error_line(two_axes)) << two_axes.err;

  const CliRun unknown_ref = cubecal_cli(base + " --ref-columns rx,ry,nope");
  EXPECT_TRUE(one_error_line(unknown_ref)) << unknown_ref.err;

  const CliRun missing =
      cubecal_cli("calibrate rate-table " + (dir_ / "nope.csv").string() + " --ref-columns rx,ry,rz");
  EXPECT_TRUE(one_error_line(missing)) << missing.err;

  const CliRun no_schedule = cubecal_cli(base + " --schedule " + (dir_ / "none.csv").string());
  EXPECT_TRUE(one_error_line(no_schedule)) << no_schedule.err;

  const CliRun earth = cubecal_cli(base + " --ref-columns rx,ry,rz --earth-axis 0,1");
  EXPECT_TRUE(one_error_line(earth)) << earth.err;

  std::vector<ScheduleRow> rows = log_.schedule;
  rows[2].t_begin = rows[1].t_end - 5.0;
  const std::string overlap = write_schedule("overlap.csv", rows);
  const CliRun bad_sched = cubecal_cli(base + " --schedule " + overlap);
  EXPECT_TRUE(one_error_line(bad_sched)) << bad_sched.err;
  // FILE:LINE of the offending row (header on line 1, row 3 on line 4).
  EXPECT_NE(bad_sched.err.find(overlap + ":4:"), std::string::npos) << bad_sched.err;

  const CliRun late = cubecal_cli(base + " --schedule " + write_schedule("late.csv", {{1e5, 1e5 + 60, {1, 0, 0}}}));
  EXPECT_TRUE(one_error_line(late)) << late.err;
  EXPECT_NE(late.err.find("no plateau found"), std::string::npos) << late.err;

  const CliRun too_long = cubecal_cli(base + " --ref-columns rx,ry,rz --min-plateau 100");
  EXPECT_TRUE(one_error_line(too_long)) << too_long.err;
  EXPECT_NE(too_long.err.find("no plateau found"), std::string::npos) << too_long.err;

  const std::string x_only = write_log("x.csv", {0});
  const CliRun degenerate =
      cubecal_cli("calibrate rate-table " + x_only + " --columns gx,gy,gz --ref-columns rx,ry,rz");
  EXPECT_TRUE(one_error_line(degenerate)) << degenerate.err;
  EXPECT_NE(degenerate.err.find("degenerate"), std::string::npos) << degenerate.err;
}

}  // namespace
