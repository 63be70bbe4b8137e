// The EDF of an OADEV point of mixed power-law noise (mixture_edf.hpp;
// docs/formulas/planning.md §2).
#include "cubecal/noise/mixture_edf.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal {

namespace {

constexpr double kPi = std::numbers::pi;

// J(p, X) = int_0^X x^p g(x)^2 dx, g(x) = 2 sin^4(pi x) / (pi x)^2: by
// Simpson's rule up to x0 = 64 (the sin^8 oscillates once per unit of x),
// beyond it with sin^8 replaced by its mean 35/128. p from -4 (finite at 0)
// to 4 (white PM, which needs the cut-off X = f_h tau).
double j_integral(int p, double x_max) {
  constexpr double x0 = 64.0;
  constexpr int steps = 64 * 256;
  const auto f = [p](double x) {
    if (x == 0.0) return p == -4 ? 4.0 * std::pow(kPi, 4) : 0.0;
    const double s = std::sin(kPi * x), s2 = s * s, s4 = s2 * s2;
    const double px = kPi * x;
    return std::pow(x, p) * 4.0 * s4 * s4 / (px * px * px * px);
  };
  const double end = std::min(x0, x_max);
  const double h = end / steps;
  double sum = f(0.0) + f(end);
  for (int i = 1; i < steps; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(i * h);
  double j = sum * h / 3.0;
  if (x_max > x0) {
    const double c = 4.0 * (35.0 / 128.0) / std::pow(kPi, 4);  // mean of the tail's integrand over x^(p-4)
    const int q = p - 4;
    j += q == -1 ? c * std::log(x_max / x0) : c * (std::pow(x_max, q + 1) - std::pow(x0, q + 1)) / (q + 1);
  }
  return j;
}

// The convergent integrals (every pair but white PM with itself), once.
double j_fixed(int p) {
  static const std::array<double, 9> table = [] {
    std::array<double, 9> t{};
    for (int q = -4; q <= 2; ++q) t[static_cast<std::size_t>(q + 4)] = j_integral(q, 1e300);
    return t;
  }();
  return table[static_cast<std::size_t>(p + 4)];
}

}  // namespace

double oadev_mixture_edf(const std::array<double, 5>& c, std::size_t m, double tau0, std::size_t n_phase) noexcept {
  // k = -2..1 (index 0..3): the random parts, their PSD exponent a (S_y ~ f^a) and noise type alpha (= a).
  constexpr std::array<int, 4> a = {2, 0, -1, -2};
  const double tau = static_cast<double>(m) * tau0;
  double total = 0.0;
  std::array<double, 5> share{};
  for (std::size_t k = 0; k < 5; ++k) {
    share[k] = std::max(0.0, c[k]) * std::pow(tau, static_cast<double>(k) - 2.0);
    total += share[k];
  }
  if (!(total > 0.0) || !std::isfinite(total)) return 0.0;
  std::array<double, 4> sv{};  // s_k sqrt(v_k)
  for (std::size_t k = 0; k < 4; ++k) {
    if (share[k] == 0.0) continue;
    const double edf = edf_for(Stat::oadev, a[k], m, n_phase);
    if (!(edf > 0.0)) return 0.0;
    sv[k] = share[k] / total * std::sqrt(2.0 / edf);
  }
  const double x_h = 0.5 * static_cast<double>(m);  // f_h tau, f_h the Nyquist frequency
  const auto j = [&](int p) { return p > 2 ? j_integral(p, x_h) : j_fixed(p); };
  double v = 0.0;
  for (std::size_t i = 0; i < 4; ++i) {
    if (sv[i] == 0.0) continue;
    for (std::size_t k = 0; k < 4; ++k) {
      if (sv[k] == 0.0) continue;
      const double rho = i == k ? 1.0 : j(a[i] + a[k]) / std::sqrt(j(2 * a[i]) * j(2 * a[k]));
      v += sv[i] * sv[k] * rho;
    }
  }
  return v > 0.0 ? 2.0 / v : 0.0;
}

}  // namespace cubecal
