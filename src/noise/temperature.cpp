#include "cubecal/noise/temperature.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "detail/temperature_regressor.hpp"
#include "detail/temperature_solution.hpp"

namespace cubecal {

TemperatureFit fit_temperature(std::span<const double> y, std::span<const double> temp,
                               std::size_t order) {
  const noise::detail::TemperatureRegressor reg = noise::detail::temperature_regressor(y, temp, order);
  const std::size_t n = y.size();
  const std::size_t p = order + 1;
  // Normal equations in the scaled variable u = (T - t_ref) / half_span, which
  // keeps V^T V well conditioned for any order used here; accumulated in one
  // pass so a multi-day record needs no n x p matrix.
  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
  Eigen::VectorXd aty = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(p));
  double ymean = 0.0;
  for (double v : y) ymean += v;
  ymean /= static_cast<double>(n);
  std::vector<double> row(p);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = reg(temp[i]);
    row[0] = 1.0;
    for (std::size_t k = 1; k < p; ++k) row[k] = row[k - 1] * u;
    const double yc = y[i] - ymean;  // centred: no cancellation in aty
    for (std::size_t a = 0; a < p; ++a) {
      aty(static_cast<Eigen::Index>(a)) += row[a] * yc;
      for (std::size_t b = a; b < p; ++b) ata(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) += row[a] * row[b];
    }
  }
  for (Eigen::Index a = 0; a < ata.rows(); ++a)
    for (Eigen::Index b = 0; b < a; ++b) ata(a, b) = ata(b, a);
  const noise::detail::TemperatureSolution sol = noise::detail::solve_temperature(ata, aty, order);
  Eigen::VectorXd cu = sol.cu;
  cu(0) += ymean;

  // Residuals, and per-batch score sums G_b = sum_{t in b} u_t e_t for the
  // covariance.
  const std::size_t batches = noise::detail::temperature_batches(n, p);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(batches));
  double ss_res = 0.0, ss_tot = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double u = reg(temp[i]);
    const auto b = static_cast<Eigen::Index>(i * batches / n);
    double fit = 0.0, pw = 1.0;
    for (std::size_t k = 0; k < p; ++k, pw *= u) fit += cu(static_cast<Eigen::Index>(k)) * pw;
    const double e = y[i] - fit;
    pw = 1.0;
    for (std::size_t k = 0; k < p; ++k, pw *= u) g(static_cast<Eigen::Index>(k), b) += pw * e;
    ss_res += e * e;
    ss_tot += (y[i] - ymean) * (y[i] - ymean);
  }
  return noise::detail::temperature_fit_from(sol, ymean, g, ss_res, ss_tot, n, reg, order);
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
