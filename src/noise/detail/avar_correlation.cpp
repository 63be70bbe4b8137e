// The long-record correlation of Allan-variance estimates (the spectral
// approximation, avar_correlation.hpp).
#include "avar_correlation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cubecal::noise::detail {

using Eigen::Index;

PowerLawPsd psd_of(const std::array<double, 5>& c, double f_high) {
  constexpr double pi2 = std::numbers::pi * std::numbers::pi;
  PowerLawPsd s;
  s.h2 = 4.0 * pi2 * c[0] / (3.0 * f_high);
  s.h0 = 2.0 * c[1];
  s.hm1 = c[2] / (2.0 * std::numbers::ln2);
  s.hm2 = 3.0 * c[3] / (2.0 * pi2);
  return s;
}

namespace {

// Frequency grid of the correlation integrals: from three decades below
// 1/tau_max (where every Allan filter has died out) to the Nyquist frequency
// of the shortest tau, in steps of 1 % in f. Beyond x = pi f tau = 4 pi the
// filter's sin^4 is replaced by its mean 3/8 (and sin^8 by 35/128 on the
// diagonal): the oscillation is then faster than the grid and averages out.
constexpr double kLnStep = 0.01;
constexpr double kEnvelopeFrom = 4.0 * std::numbers::pi;

// Allan filter g(x) and the mean of its square, x = pi f tau.
struct FilterValue {
  double g;
  double g2;
};
FilterValue allan_filter(double x) noexcept {
  if (x < kEnvelopeFrom) {
    const double s2 = std::sin(x) * std::sin(x);
    const double g = 2.0 * s2 * s2 / (x * x);
    return {g, g * g};
  }
  const double x2 = x * x;
  return {0.75 / x2, 4.0 * (35.0 / 128.0) / (x2 * x2)};
}

}  // namespace

Eigen::MatrixXd projected_correlation(const std::vector<double>& tau, const Eigen::MatrixXd& q,
                                      const PowerLawPsd& psd) {
  const std::size_t n = tau.size();
  const Index p = q.cols();
  const double f_lo = 1e-3 / tau.back();
  const double f_hi = 0.5 / tau.front();
  const auto steps = static_cast<std::size_t>(std::ceil(std::log(f_hi / f_lo) / kLnStep));
  std::vector<double> f(steps + 1), weight(steps + 1);
  for (std::size_t k = 0; k <= steps; ++k) {
    f[k] = f_lo * std::exp(static_cast<double>(k) * kLnStep);
    const double s = psd(f[k]);
    // int ... df = int ... f dln f, trapezoid ends.
    weight[k] = s * s * f[k] * kLnStep * (k == 0 || k == steps ? 0.5 : 1.0);
  }

  std::vector<double> self(n, 0.0), cross(n, 0.0);  // int S^2 <g^2>, int S^2 g^2
  for (std::size_t k = 0; k <= steps; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const FilterValue g = allan_filter(std::numbers::pi * f[k] * tau[i]);
      self[i] += weight[k] * g.g2;
      cross[i] += weight[k] * g.g * g.g;
    }
  }
  std::vector<double> norm(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (self[i] > 0.0 && std::isfinite(self[i])) norm[i] = 1.0 / std::sqrt(self[i]);

  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd u(p);
  for (std::size_t k = 0; k <= steps; ++k) {
    u.setZero();
    for (std::size_t i = 0; i < n; ++i) {
      if (norm[i] == 0.0) continue;
      const double r = allan_filter(std::numbers::pi * f[k] * tau[i]).g * norm[i];
      u += r * q.row(static_cast<Index>(i)).transpose();
    }
    m.noalias() += weight[k] * u * u.transpose();
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double e = norm[i] > 0.0 ? std::max(0.0, 1.0 - cross[i] / self[i]) : 1.0;
    const auto row = q.row(static_cast<Index>(i));
    m.noalias() += e * row.transpose() * row;
  }
  return m;
}

}  // namespace cubecal::noise::detail
