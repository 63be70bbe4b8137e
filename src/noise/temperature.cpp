#include "cubecal/noise/temperature.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "detail/temperature_regressor.hpp"
#include "detail/temperature_solution.hpp"

namespace cubecal {

namespace {

// The two passes of the fit for P = order + 1 coefficients (a template
// parameter, so that the loops over the powers unroll and the sums live in
// registers): the normal equations, then the residuals with the per-batch
// score sums G_b = sum_{t in b} u_t^k e_t of the covariance.
template <std::size_t P>
TemperatureFit fit_temperature_p(std::span<const double> y, std::span<const double> temp,
                                 const noise::detail::TemperatureRegressor& reg, std::size_t order) {
  const std::size_t n = y.size();
  // Normal equations in the scaled variable u = (T - t_ref) / half_span, which
  // keeps V^T V well conditioned for any order used here; accumulated in one
  // pass so a multi-day record needs no n x p matrix.
  double ymean = 0.0;
  for (double v : y) ymean += v;
  ymean /= static_cast<double>(n);
  std::array<double, P> aty{};
  std::array<double, P*(P + 1) / 2> ata{};
  for (std::size_t i = 0; i < n; ++i) {
    const double u = reg(temp[i]);
    std::array<double, P> row;
    row[0] = 1.0;
    for (std::size_t k = 1; k < P; ++k) row[k] = row[k - 1] * u;
    const double yc = y[i] - ymean;  // centred: no cancellation in aty
    std::size_t c = 0;
    for (std::size_t a = 0; a < P; ++a) {
      aty[a] += row[a] * yc;
      for (std::size_t b = a; b < P; ++b) ata[c++] += row[a] * row[b];
    }
  }
  Eigen::MatrixXd ata_m(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(P));
  Eigen::VectorXd aty_v(static_cast<Eigen::Index>(P));
  std::size_t c = 0;
  for (std::size_t a = 0; a < P; ++a) {
    aty_v(static_cast<Eigen::Index>(a)) = aty[a];
    for (std::size_t b = a; b < P; ++b, ++c) {
      ata_m(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = ata[c];
      ata_m(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(a)) = ata[c];
    }
  }
  const noise::detail::TemperatureSolution sol = noise::detail::solve_temperature(ata_m, aty_v, order);
  std::array<double, P> cu;
  for (std::size_t k = 0; k < P; ++k) cu[k] = sol.cu(static_cast<Eigen::Index>(k));
  cu[0] += ymean;

  // Residuals, and per-batch score sums; batch b holds samples
  // [b n / batches, (b + 1) n / batches).
  const std::size_t batches = noise::detail::temperature_batches(n, P);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(P), static_cast<Eigen::Index>(batches));
  double ss_res = 0.0, ss_tot = 0.0;
  for (std::size_t b = 0; b < batches; ++b) {
    // The first i with i * batches / n == b, as the per-sample rule assigns it.
    const std::size_t from = (b * n + batches - 1) / batches;
    const std::size_t to = ((b + 1) * n + batches - 1) / batches;
    std::array<double, P> gb{};
    for (std::size_t i = from; i < to; ++i) {
      const double u = reg(temp[i]);
      std::array<double, P> pw;
      pw[0] = 1.0;
      for (std::size_t k = 1; k < P; ++k) pw[k] = pw[k - 1] * u;
      double fit = 0.0;
      for (std::size_t k = 0; k < P; ++k) fit += cu[k] * pw[k];
      const double e = y[i] - fit;
      for (std::size_t k = 0; k < P; ++k) gb[k] += pw[k] * e;
      ss_res += e * e;
      ss_tot += (y[i] - ymean) * (y[i] - ymean);
    }
    for (std::size_t k = 0; k < P; ++k) g(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(b)) = gb[k];
  }
  return noise::detail::temperature_fit_from(sol, ymean, g, ss_res, ss_tot, n, reg, order);
}

}  // namespace

TemperatureFit fit_temperature(std::span<const double> y, std::span<const double> temp, std::size_t order) {
  const noise::detail::TemperatureRegressor reg = noise::detail::temperature_regressor(y, temp, order);
  switch (order + 1) {  // temperature_regressor took orders 1 to 5
    case 2: return fit_temperature_p<2>(y, temp, reg, order);
    case 3: return fit_temperature_p<3>(y, temp, reg, order);
    case 4: return fit_temperature_p<4>(y, temp, reg, order);
    case 5: return fit_temperature_p<5>(y, temp, reg, order);
    default: return fit_temperature_p<6>(y, temp, reg, order);
  }
}

void compensate_temperature(std::span<const double> y, std::span<const double> temp, const TemperatureFit& fit,
                            std::span<double> out) {
  if (temp.size() != y.size() || out.size() != y.size())
    throw std::invalid_argument("compensate_temperature: y, temp and out differ in length");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double d = temp[i] - fit.t_ref;
    double corr = 0.0, pw = d;
    for (std::size_t k = 1; k < fit.coeff.size(); ++k, pw *= d) corr += fit.coeff[k] * pw;
    out[i] = y[i] - corr;
  }
}

std::vector<double> compensate_temperature(std::span<const double> y, std::span<const double> temp,
                                           const TemperatureFit& fit) {
  std::vector<double> out(y.size());
  compensate_temperature(y, temp, fit, out);
  return out;
}

}  // namespace cubecal
