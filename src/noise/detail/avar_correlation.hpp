// Correlation between Allan-variance estimates at different taus, for the
// covariance of the five-term noise fit. Not an installed header.
//
// Overlapping estimates at neighbouring taus share most of their data:
// on a random-walk arm the residuals of a fit are smooth, chi-squared comes
// out well below its degrees of freedom, and covariances that treat the
// points as independent are several times too small. The long-record
// (spectral) approximation of the covariance of two Allan-variance
// estimates is
//   cov(s2_i, s2_j) ~ (1/T) int S_y(f)^2 g(f tau_i) g(f tau_j) df,
//   g(f tau) = 2 sin^4(pi f tau) / (pi f tau)^2 (the Allan filter),
// so their correlation follows from the noise spectrum alone; the variance
// of each point is kept from its EDF.
#pragma once
#include <Eigen/Dense>
#include <array>
#include <vector>

namespace cubecal::noise::detail {

// One-sided PSD of y, S_y(f) = h2 f^2 + h0 + h_-1 / f + h_-2 / f^2, with the
// Allan variance of the stochastic terms of the fit (SP 1065 Table 2):
// white PM 3 f_h h2 / (4 pi^2 tau^2), white FM h0 / (2 tau), flicker FM
// 2 ln2 h_-1, random-walk FM (2 pi^2 / 3) h_-2 tau. The rate ramp is a
// deterministic drift with no spectrum; it enters through the EDFs only.
struct PowerLawPsd {
  double h2 = 0.0, h0 = 0.0, hm1 = 0.0, hm2 = 0.0;
  double operator()(double f) const noexcept { return h2 * f * f + h0 + hm1 / f + hm2 / (f * f); }
};

// The PSD of the fitted coefficients C_-2..C_2 (C_2, the rate ramp, has
// none); f_high: the white-PM cut-off.
PowerLawPsd psd_of(const std::array<double, 5>& c, double f_high);

// Q^T rho Q for the thin Q (n x p) of the whitened design, where rho is
// the correlation matrix of the whitened residuals (unit variances). rho is
// never formed: with r_i(f) = g_i(f) / sqrt(int S^2 g_i^2), rho = int S^2
// r r^T df + diag(e), where e_i >= 0 is the part of each point's variance
// the envelope leaves uncorrelated (all of it when the PSD is zero there).
// tau: increasing, positive.
Eigen::MatrixXd projected_correlation(const std::vector<double>& tau, const Eigen::MatrixXd& q, const PowerLawPsd& psd);

}  // namespace cubecal::noise::detail
