#include "cubecal/stats/extra_kernels.hpp"

#include <cmath>

#include "detail/total_kernels.hpp"

namespace cubecal {

namespace {

// The two running sums of the PVAR term at i over d[j] = x[j] - x[j+m]:
// A = sum_k d[i+k], B = sum_k k d[i+k] (k = 0 .. m-1), computed afresh.
void pvar_sums(const double* x, std::size_t i, std::size_t m, double& A, double& B) {
  A = 0.0;
  B = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const double d = x[i + k] - x[i + k + m];
    A += d;
    B += static_cast<double>(k) * d;
  }
}

}  // namespace

VarianceTerm pvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 2 * m + 1) return {};
  if (m == 1) return oavar(x, 1, tau0);
  const std::size_t M = N - 2 * m;
  const double c = 0.5 * static_cast<double>(m - 1);
  const double md = static_cast<double>(m);
  double A = 0.0, B = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < M; ++i) {
    if (i % m == 0) {
      pvar_sums(x.data(), i, m, A, B);  // afresh every m terms: no drift of the running sums
    } else {
      // From term i-1 to i: d[i-1] leaves, d[i-1+m] enters with weight m-1, the others' weights drop by one.
      const double out = x[i - 1] - x[i - 1 + m];
      const double in = x[i - 1 + m] - x[i - 1 + 2 * m];
      B = B - (A - out) + (md - 1.0) * in;
      A = A - out + in;
    }
    const double s = c * A - B;
    sum += s * s;
  }
  const double tau = md * tau0;
  return {72.0 * sum / (static_cast<double>(M) * md * md * md * md * tau * tau), M};
}

VarianceTerm allan_covariance(std::span<const double> x1, std::span<const double> x2, std::size_t m, double tau0) {
  const std::size_t N = x1.size();
  if (m == 0 || N != x2.size() || N < 2 * m + 1) return {};
  const std::size_t n = N - 2 * m;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = x1[i + 2 * m] - 2.0 * x1[i + m] + x1[i];
    const double b = x2[i + 2 * m] - 2.0 * x2[i + m] + x2[i];
    sum += a * b;
  }
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (2.0 * tau * tau * static_cast<double>(n)), n};
}

VarianceTerm htotvar_frequency(std::span<const double> y, std::size_t m) { return htotvar(y, m, 1.0); }

}  // namespace cubecal
