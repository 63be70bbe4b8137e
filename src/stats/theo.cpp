// Theo1 and TheoBR (docs/formulas/stability.md, "The Theo family").
//
//   Theo1(m) = 1 / (0.75 (N-m) (m tau0)^2)
//              sum_{i=0}^{N-m-1} sum_{d=0}^{m/2-1} [(x_i - x_{i-d+m/2}) + (x_{i+m} - x_{i+d+m/2})]^2 / (m/2 - d)
//
// The inner sum over i, for one d, is the energy of a four-point filter
// along the record: vectorised like the other kernels, eight partial sums.
// O(N m / 2) per factor.
//
// TheoH (SP 1065 sec. 5.2.16; D. A. Howe, Metrologia 43, S322, 2006): the
// overlapping AVAR below the switch factor k/tau0 and TheoBR from
// k/(0.75 tau0) on, k the largest tau within 20 % of the record.
#include "cubecal/stats/theo.hpp"

#include <algorithm>
#include <cmath>

#include "cubecal/stats/statistic.hpp"
#include "../detail/simd.hpp"

namespace cubecal {

namespace {

// sum_{i<count} (x[i] + x[i+m] - x[i+a] - x[i+b])^2
CUBECAL_VECTOR_CLONES
double four_point_energy(const double* x, std::size_t count, std::size_t m, std::size_t a, std::size_t b) noexcept {
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8)
    for (std::size_t j = 0; j < 8; ++j) {
      const double t = (x[i + j] - x[i + j + a]) + (x[i + j + m] - x[i + j + b]);
      s[j] += t * t;
    }
  double tail = 0.0;
  for (; i < count; ++i) {
    const double t = (x[i] - x[i + a]) + (x[i + m] - x[i + b]);
    tail += t * t;
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

}  // namespace

VarianceTerm theo1var(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m < 2 || m % 2 != 0 || N < m + 1) return {};
  const std::size_t h = m / 2;
  const std::size_t count = N - m;
  double sum = 0.0;
  for (std::size_t d = 0; d < h; ++d)
    sum += four_point_energy(x.data(), count, m, h - d, h + d) / static_cast<double>(h - d);
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (0.75 * static_cast<double>(count) * tau * tau), count * h};
}

double theobr_ratio(std::span<const double> x) {
  const std::size_t N = x.size();
  if (N < 30) return 0.0;
  const std::size_t last = static_cast<std::size_t>(std::floor(static_cast<double>(N) / 6.0 - 3.0));
  double sum = 0.0;
  for (std::size_t i = 0; i <= last; ++i) {
    const VarianceTerm a = oavar(x, 9 + 3 * i, 1.0);
    // Theo1 at 12 + 4i spans 0.75 (12 + 4i) = 9 + 3i: the same tau.
    const VarianceTerm t = theo1var(x, 12 + 4 * i, 1.0);
    if (a.n == 0 || t.n == 0 || !(t.var > 0.0)) return 0.0;
    sum += a.var / t.var;
  }
  return sum / static_cast<double>(last + 1);
}

VarianceTerm theohvar(std::span<const double> x, std::size_t m, double tau0, double ratio) {
  const auto part = theoh_stat_at(Stat::theoh, m, x.size());
  if (!part) return {};
  if (*part == Stat::oadev) return oavar(x, m, tau0);
  if (!(ratio > 0.0)) return {};
  VarianceTerm v = theo1var(x, m, tau0);
  v.var *= ratio;
  return v;
}

TauGrid theoh_factor_grid(const TauGrid& grid, std::size_t n_phase, double tau0) {
  TauGrid out = grid;
  if (grid.kind != TauGrid::Kind::list) return out;
  const double k = static_cast<double>(theoh_switch_factor(n_phase)) * tau0;
  for (double& tau : out.taus)
    if (tau >= k) tau /= 0.75;
  return out;
}

}  // namespace cubecal
