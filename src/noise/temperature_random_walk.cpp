// Temperature coefficients jointly with a random-walk bias and white noise
// (temperature_random_walk.hpp; docs/formulas/drift-covariance-temperature.md §4).
//
// Why GLS through a Kalman filter, and not ordinary least squares, the
// augmented-state smoother, or first differences:
// - OLS (fit_temperature) weights every sample alike. The random walk puts
//   most of its power at the daily period of a temperature cycle, and OLS
//   leaves the coefficient scattering ~3x more than the best linear unbiased
//   estimator; its sandwich covariance follows that scatter only roughly
//   (20 batches).
// - GLS with the covariance Sigma the noise model implies is that best
//   estimator, and its covariance (X^T Sigma^-1 X)^-1 is the coefficients' own.
//   Sigma (white + random walk) is n x n and dense, but the scalar Kalman
//   filter of the random walk factors it: its innovations e_k and their
//   variances F_k whiten any series, Sigma^-1 = L^T D^-1 L. Filtering y and
//   each regressor column with the same gains (the gains do not depend on the
//   data) gives X^T Sigma^-1 X = sum_k x~_k x~_k^T / F_k and
//   X^T Sigma^-1 y = sum_k x~_k y~_k / F_k: O(n (P+2)) operations, no n x n
//   matrix, no storage beyond the sums.
// - This is the Kalman filter with the coefficients as augmented constant
//   states (de Jong's augmented / diffuse filter): for constant states the
//   filtered estimate at the last sample is the smoothed one, so no RTS pass
//   is needed, and its covariance is the GLS covariance above.
// - First differences remove the random walk, but leave white + MA(1) noise
//   (variance 2 r + q, lag-1 covariance -r) whose GLS again needs a banded
//   factorization: the same cost, and the level information of the first
//   sample is lost. The filter keeps it and takes gaps (BiasGap) naturally.
#include "cubecal/noise/temperature_random_walk.hpp"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cubecal/error.hpp"
#include "detail/temperature_regressor.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMaxOrder = 5;

void require_noise(const RandomWalkModel& m) {
  const bool ok = std::isfinite(m.dt) && m.dt > 0.0 && std::isfinite(m.sigma_n) && m.sigma_n >= 0.0 &&
                  std::isfinite(m.sigma_mu) && m.sigma_mu >= 0.0 && std::isfinite(m.lsb) && m.lsb >= 0.0;
  if (!ok)
    throw CalibrationError(CalibrationReason::bad_option,
                           "temperature fit with the random walk: the noise model needs a positive sample period "
                           "and finite, non-negative sigma_n, sigma_mu and LSB");
}

// The whitened normal equations: X^T Sigma^-1 X, X^T Sigma^-1 y (y centred),
// and the mean of each column u^j.
struct Sums {
  Eigen::MatrixXd xx;
  Eigen::VectorXd xy;
  std::array<double, kMaxOrder + 1> umean{};
};

// One pass of the scalar Kalman filter of the random walk over y and the
// P columns u^0 .. u^(P-1) with the same gains. Series 0 is y, series 1 + j
// the column u^j; a holds each series' predicted state, pk the state
// variance before sample k (s_0 = 0 is known: the intercept is the level at
// the first sample). P is a template parameter so that the loops over the
// series unroll.
template <std::size_t P>
Sums filter_sums(std::span<const double> y, std::span<const double> temp,
                 const noise::detail::TemperatureRegressor& reg, double ymean, double r, double q,
                 std::span<const BiasGap> gaps) {
  const std::size_t n = y.size();
  std::array<double, P + 1> a{}, z{}, e{};
  std::array<double, P*(P + 1) / 2> xx{};
  std::array<double, P> xy{}, um{};
  const double inv_span = 1.0 / reg.half_span;
  double pk = 0.0;
  // The variance recursion does not depend on the data and settles within a
  // few sqrt(r/q) samples; once it stands still (to the last bits) w and the
  // gain are kept, which takes the division off the loop-carried path. A gap
  // restarts it.
  bool steady = false;
  double w = 1.0 / r, gain = 0.0;
  std::size_t g = 0;
  for (std::size_t k = 0; k < n; ++k) {
    for (; g < gaps.size() && gaps[g].index <= k; ++g)
      if (gaps[g].index == k && gaps[g].steps > 0.0) {
        pk += q * gaps[g].steps;
        steady = false;
      }
    if (!steady) {
      w = 1.0 / (pk + r);  // 1 / F_k
      gain = pk * w;
    }
    const double u = (temp[k] - reg.t_ref) * inv_span;
    z[0] = y[k] - ymean;
    z[1] = 1.0;
    for (std::size_t j = 2; j <= P; ++j) z[j] = z[j - 1] * u;
    for (std::size_t j = 0; j <= P; ++j) {
      e[j] = z[j] - a[j];
      a[j] += gain * e[j];
    }
    std::size_t c = 0;
    for (std::size_t i = 0; i < P; ++i) {
      um[i] += z[i + 1];
      const double ei = e[i + 1] * w;
      xy[i] += ei * e[0];
      for (std::size_t j = i; j < P; ++j) xx[c++] += ei * e[j + 1];
    }
    if (!steady) {
      const double next = pk * r * w + q;  // P_{k|k} = (1 - K) P = P r / F, then one step of the walk
      steady = std::abs(next - pk) <= 1e-15 * next;
      pk = next;
    }
  }
  Sums s;
  s.xx = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(P));
  s.xy = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(P));
  std::size_t c = 0;
  for (std::size_t i = 0; i < P; ++i) {
    s.xy(static_cast<Eigen::Index>(i)) = xy[i];
    s.umean[i] = um[i] / static_cast<double>(n);
    for (std::size_t j = i; j < P; ++j) {
      s.xx(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = xx[c];
      s.xx(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) = xx[c++];
    }
  }
  return s;
}

// Residual and total sums of squares of y about the polynomial cu in u
// (P coefficients, unrolled).
struct ResidualSums {
  double ss_res = 0.0, ss_tot = 0.0;
};
template <std::size_t P>
ResidualSums residual_sums(std::span<const double> y, std::span<const double> temp,
                           const noise::detail::TemperatureRegressor& reg, const std::array<double, kMaxOrder + 1>& cu,
                           double ymean) {
  ResidualSums s;
  for (std::size_t k = 0; k < y.size(); ++k) {
    const double u = reg(temp[k]);
    double model = 0.0, pw = 1.0;
    for (std::size_t j = 0; j < P; ++j, pw *= u) model += cu[j] * pw;
    const double res = y[k] - model;
    s.ss_res += res * res;
    s.ss_tot += (y[k] - ymean) * (y[k] - ymean);
  }
  return s;
}

}  // namespace

TemperatureFit fit_temperature_gls(std::span<const double> y, std::span<const double> temp, std::size_t order,
                                   const RandomWalkModel& noise, std::span<const BiasGap> gaps) {
  const noise::detail::TemperatureRegressor reg = noise::detail::temperature_regressor(y, temp, order);
  require_noise(noise);
  // Measurement noise r: white plus the quantizer's uniform error (as the
  // model's Allan variance counts it); process noise q: one step of the walk.
  const double r = noise.sigma_n * noise.sigma_n + (noise.lsb > 0.0 ? 1.0 / (12.0 * noise.lsb * noise.lsb) : 0.0);
  const double q = (noise.sigma_mu * noise.dt) * (noise.sigma_mu * noise.dt);
  if (!(r > 0.0))
    throw CalibrationError(CalibrationReason::bad_option,
                           "temperature fit with the random walk: the noise model has no white noise");
  const std::size_t n = y.size();
  const std::size_t p = order + 1;  // coefficients c_0 .. c_order
  double ymean = 0.0;
  for (double v : y) ymean += v;
  ymean /= static_cast<double>(n);

  Sums sums;
  switch (p) {
    case 2: sums = filter_sums<2>(y, temp, reg, ymean, r, q, gaps); break;
    case 3: sums = filter_sums<3>(y, temp, reg, ymean, r, q, gaps); break;
    case 4: sums = filter_sums<4>(y, temp, reg, ymean, r, q, gaps); break;
    case 5: sums = filter_sums<5>(y, temp, reg, ymean, r, q, gaps); break;
    default: sums = filter_sums<6>(y, temp, reg, ymean, r, q, gaps); break;
  }
  const Eigen::MatrixXd& xx = sums.xx;
  const Eigen::VectorXd& xy = sums.xy;
  const std::array<double, kMaxOrder + 1>& umean = sums.umean;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(xx);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-13) noise::detail::throw_too_few_distinct(order);
  const Eigen::VectorXd beta = ldlt.solve(xy);
  const Eigen::MatrixXd cov_u = ldlt.solve(Eigen::MatrixXd::Identity(xx.rows(), xx.cols()));

  // c_0: the mean of y - sum_{j>=1} c_j u^j (the record's mean bias at T_ref),
  // var r/n + g^T C g with g_j = mean(u^j), C the covariance of c_1..: the
  // white-noise share of the mean and the coefficients' share.
  const auto pe = static_cast<Eigen::Index>(order);
  Eigen::VectorXd gm(pe);
  for (Eigen::Index j = 0; j < pe; ++j) gm(j) = umean[static_cast<std::size_t>(j) + 1];
  const Eigen::MatrixXd cc = cov_u.bottomRightCorner(pe, pe);
  Eigen::VectorXd cu(static_cast<Eigen::Index>(p));
  cu.tail(pe) = beta.tail(pe);
  cu(0) = ymean - gm.dot(beta.tail(pe));
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
  full.bottomRightCorner(pe, pe) = cc;
  const Eigen::VectorXd cg = cc * gm;
  full(0, 0) = r / static_cast<double>(n) + gm.dot(cg);
  full.block(0, 1, 1, pe) = -cg.transpose();
  full.block(1, 0, pe, 1) = -cg;

  TemperatureFit fit;
  fit.order = order;
  fit.t_ref = reg.t_ref;
  std::array<double, kMaxOrder + 1> cu_a{};
  for (std::size_t j = 0; j < p; ++j) cu_a[j] = cu(static_cast<Eigen::Index>(j));
  ResidualSums res;
  switch (p) {
    case 2: res = residual_sums<2>(y, temp, reg, cu_a, ymean); break;
    case 3: res = residual_sums<3>(y, temp, reg, cu_a, ymean); break;
    case 4: res = residual_sums<4>(y, temp, reg, cu_a, ymean); break;
    case 5: res = residual_sums<5>(y, temp, reg, cu_a, ymean); break;
    default: res = residual_sums<6>(y, temp, reg, cu_a, ymean); break;
  }
  const double ss_res = res.ss_res, ss_tot = res.ss_tot;
  fit.residual_rms = std::sqrt(ss_res / static_cast<double>(n));
  fit.r2 = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 0.0;
  // Back to (T - t_ref)^j: c_j = cu_j / half_span^j.
  fit.coeff.resize(p);
  fit.coeff_sigma.resize(p);
  fit.cov = Matrix(p, p);
  for (std::size_t i = 0; i < p; ++i) {
    const double si = std::pow(reg.half_span, -static_cast<double>(i));
    fit.coeff[i] = cu(static_cast<Eigen::Index>(i)) * si;
    for (std::size_t j = 0; j < p; ++j)
      fit.cov(i, j) = full(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) * si *
                      std::pow(reg.half_span, -static_cast<double>(j));
    fit.coeff_sigma[i] = std::sqrt(std::max(fit.cov(i, i), 0.0));
  }
  return fit;
}

TemperatureRandomWalkFit fit_temperature_random_walk(std::span<const double> y, std::span<const double> temp,
                                                     std::size_t order, const CompensatedNoiseModel& noise_model,
                                                     std::span<const BiasGap> gaps, std::size_t max_iterations) {
  return fit_temperature_random_walk(y, temp, order, fit_temperature(y, temp, order), noise_model, gaps,
                                     max_iterations);
}

TemperatureRandomWalkFit fit_temperature_random_walk(std::span<const double> y, std::span<const double> temp,
                                                     std::size_t order, TemperatureFit ols,
                                                     const CompensatedNoiseModel& noise_model,
                                                     std::span<const BiasGap> gaps, std::size_t max_iterations) {
  if (!noise_model) throw std::invalid_argument("fit_temperature_random_walk: no noise model");
  if (max_iterations < 1) throw std::invalid_argument("fit_temperature_random_walk: max_iterations must be >= 1");
  if (ols.order != order || ols.coeff.size() != order + 1)
    throw std::invalid_argument("fit_temperature_random_walk: the OLS start is not a fit of this order");
  TemperatureRandomWalkFit r;
  r.ols = std::move(ols);
  const TemperatureFit* current = &r.ols;
  std::vector<double> comp(y.size());  // one buffer for every iteration: a record can be days long
  for (std::size_t it = 1; it <= max_iterations; ++it) {
    compensate_temperature(y, temp, *current, comp);
    RandomWalkModel noise = noise_model(comp);
    TemperatureFit gls = fit_temperature_gls(y, temp, order, noise, gaps);
    // Converged when the coefficients moved so little that the compensated
    // series, and so its noise model, would not change.
    bool small = true;
    for (std::size_t j = 1; j < gls.coeff.size(); ++j)
      small = small && std::abs(gls.coeff[j] - current->coeff[j]) <= 0.05 * gls.coeff_sigma[j];
    r.fit = std::move(gls);
    r.noise = noise;
    r.iterations = it;
    current = &r.fit;
    if (small) {
      r.converged = true;
      break;
    }
  }
  return r;
}

}  // namespace cubecal
