#include "temperature_solution.hpp"

#include <algorithm>
#include <cmath>

namespace cubecal::noise::detail {

std::size_t temperature_batches(std::size_t n, std::size_t p) noexcept {
  constexpr std::size_t kBatches = 20;
  return std::min(kBatches, n / (4 * p) + 1);
}

TemperatureSolution solve_temperature(const Eigen::MatrixXd& ata, const Eigen::VectorXd& aty, std::size_t order) {
  TemperatureSolution s;
  s.ldlt.compute(ata);
  if (s.ldlt.info() != Eigen::Success || s.ldlt.rcond() < 1e-13) throw_too_few_distinct(order);
  s.cu = s.ldlt.solve(aty);
  return s;
}

TemperatureFit temperature_fit_from(const TemperatureSolution& s, double ymean, const Eigen::MatrixXd& g, double ss_res,
                                    double ss_tot, std::size_t n, const TemperatureRegressor& reg, std::size_t order) {
  const std::size_t p = order + 1;
  const auto batches = static_cast<std::size_t>(g.cols());
  TemperatureFit f;
  f.order = order;
  f.t_ref = reg.t_ref;
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
  const auto pe = static_cast<Eigen::Index>(p);
  const Eigen::MatrixXd inv = s.ldlt.solve(Eigen::MatrixXd::Identity(pe, pe));
  const double s2 = ss_res / static_cast<double>(n - p);
  const Eigen::MatrixXd cov_white = s2 * inv;
  Eigen::MatrixXd cov_u = cov_white;
  if (batches >= 2) {
    const Eigen::MatrixXd scores =
        g * g.transpose() * (static_cast<double>(batches) / static_cast<double>(batches - 1));
    cov_u = inv * scores * inv;
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(cov_u.rows());
    for (Eigen::Index a = 0; a < cov_u.rows(); ++a)
      if (cov_u(a, a) < cov_white(a, a)) scale(a) = cov_u(a, a) > 0.0 ? std::sqrt(cov_white(a, a) / cov_u(a, a)) : 0.0;
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
  f.cov = Matrix(p, p);
  for (std::size_t a = 0; a < p; ++a) {
    const double sa = std::pow(reg.half_span, -static_cast<double>(a));
    f.coeff[a] = (s.cu(static_cast<Eigen::Index>(a)) + (a == 0 ? ymean : 0.0)) * sa;
    for (std::size_t b = 0; b < p; ++b) {
      const double sb = std::pow(reg.half_span, -static_cast<double>(b));
      f.cov(a, b) = cov_u(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) * sa * sb;
    }
    f.coeff_sigma[a] = std::sqrt(std::max(f.cov(a, a), 0.0));
  }
  return f;
}

}  // namespace cubecal::noise::detail
