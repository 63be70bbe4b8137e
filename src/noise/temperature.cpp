#include "cubecal/noise/temperature.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "detail/temperature_regressor.hpp"

namespace cubecal {

TemperatureFit fit_temperature(std::span<const double> y, std::span<const double> temp,
                               std::size_t order) {
  const noise::detail::TemperatureRegressor reg = noise::detail::temperature_regressor(y, temp, order);
  const std::size_t n = y.size();
  const std::size_t p = order + 1;
  TemperatureFit f;
  f.order = order;
  f.t_ref = reg.t_ref;
  const double half_span = reg.half_span;
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
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(ata);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-13) noise::detail::throw_too_few_distinct(order);
  Eigen::VectorXd cu = ldlt.solve(aty);
  cu(0) += ymean;

  // Residuals, and per-batch score sums G_b = sum_{t in b} u_t e_t for the
  // covariance below.
  constexpr std::size_t kBatches = 20;
  const std::size_t batches = std::min(kBatches, n / (4 * p) + 1);
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
  f.residual_rms = std::sqrt(ss_res / static_cast<double>(n));
  f.r2 = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 0.0;
  // Coefficient covariance. A sensor bias is not white: its random walk and
  // flicker leave residuals correlated over hours, and the textbook
  // sigma^2 (V^T V)^-1 then understates the uncertainty many times over. The
  // sandwich (V^T V)^-1 S (V^T V)^-1 with S from batch means of the scores
  // (contiguous batches, assumed independent) follows the correlation; it
  // reduces to the textbook form for white residuals. No variance is let
  // below the textbook one (a few batches can come out small by chance):
  // such rows and columns are scaled up, which keeps the matrix valid.
  const Eigen::MatrixXd inv = ldlt.solve(Eigen::MatrixXd::Identity(ata.rows(), ata.cols()));
  const double s2 = ss_res / static_cast<double>(n - p);
  const Eigen::MatrixXd cov_white = s2 * inv;
  Eigen::MatrixXd cov_u = cov_white;
  if (batches >= 2) {
    const Eigen::MatrixXd scores =
        g * g.transpose() * (static_cast<double>(batches) / static_cast<double>(batches - 1));
    cov_u = inv * scores * inv;
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(cov_u.rows());
    for (Eigen::Index a = 0; a < cov_u.rows(); ++a)
      if (cov_u(a, a) < cov_white(a, a))
        scale(a) = cov_u(a, a) > 0.0 ? std::sqrt(cov_white(a, a) / cov_u(a, a)) : 0.0;
    for (Eigen::Index a = 0; a < cov_u.rows(); ++a)
      if (scale(a) == 0.0) {
        cov_u = cov_white;  // degenerate batches: fall back entirely
        break;
      }
    cov_u = scale.asDiagonal() * cov_u * scale.asDiagonal();
  }

  // Back to (T - t_ref)^k: c_k = cu_k / half_span^k.
  f.coeff.resize(p);
  f.coeff_sigma.resize(p);
  f.cov.assign(p, std::vector<double>(p));
  for (std::size_t a = 0; a < p; ++a) {
    const double sa = std::pow(half_span, -static_cast<double>(a));
    f.coeff[a] = cu(static_cast<Eigen::Index>(a)) * sa;
    for (std::size_t b = 0; b < p; ++b) {
      const double sb = std::pow(half_span, -static_cast<double>(b));
      f.cov[a][b] = cov_u(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) * sa * sb;
    }
    f.coeff_sigma[a] = std::sqrt(std::max(f.cov[a][a], 0.0));
  }
  return f;
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
