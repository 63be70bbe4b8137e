// The pieces of power-law noise identification in their published forms
// (Riley & Greenhall, EFTF 2004; Howe, Beard, Greenhall & Riley, PTTI 2000;
// IEEE 1139-2008), for the Python module's AllanTools-shaped calls.
// noise_id.cpp is Stable32's variant (averages of frequency only, sample
// variance in r1, B1 at the statistic's number of terms); the differences
// are listed there.
#include <cmath>
#include <numbers>
#include <vector>

#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/noise_id.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMinLag1Points = 30;
constexpr int kMaxDetrendDegree = 8;

}  // namespace

double lag1_acf(std::span<const double> x) {
  if (x.size() < 2) return 0.0;
  double mean = 0.0;
  for (const double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  double num = 0.0, den = 0.0;
  for (std::size_t n = 0; n + 1 < x.size(); ++n) num += (x[n] - mean) * (x[n + 1] - mean);
  for (const double v : x) den += (v - mean) * (v - mean);
  return den > 0.0 ? num / den : 0.0;
}

std::vector<double> detrend(std::span<const double> x, int deg) {
  if (deg < 0 || deg > kMaxDetrendDegree || x.size() < static_cast<std::size_t>(deg) + 1) return {};
  const std::size_t n = x.size();
  // Modified Gram-Schmidt on 1, u, u^2, ... with u the index scaled to
  // [-1, 1] (well conditioned where the raw powers of the index are not),
  // each basis vector orthogonalized twice; the residual is x minus its
  // projections on them.
  const double half = n > 1 ? 0.5 * static_cast<double>(n - 1) : 1.0;
  std::vector<std::vector<double>> q;
  std::vector<double> power(n, 1.0);
  for (int k = 0; k <= deg; ++k) {
    std::vector<double> v = power;
    for (int pass = 0; pass < 2; ++pass) {
      for (const auto& b : q) {
        double dot = 0.0;
        for (std::size_t i = 0; i < n; ++i) dot += b[i] * v[i];
        for (std::size_t i = 0; i < n; ++i) v[i] -= dot * b[i];
      }
    }
    double norm = 0.0;
    for (const double e : v) norm += e * e;
    norm = std::sqrt(norm);
    if (norm > 0.0) {
      for (double& e : v) e /= norm;
      q.push_back(std::move(v));
    }
    for (std::size_t i = 0; i < n; ++i) power[i] *= (static_cast<double>(i) - half) / half;
  }
  std::vector<double> r(x.begin(), x.end());
  for (const auto& b : q) {
    double dot = 0.0;
    for (std::size_t i = 0; i < n; ++i) dot += b[i] * r[i];
    for (std::size_t i = 0; i < n; ++i) r[i] -= dot * b[i];
  }
  return r;
}

double b1_expected(double N, int mu) {
  switch (mu) {
    case 2: return N * (N + 1.0) / 6.0;
    case 1: return N / 2.0;
    case 0: return N * std::log(N) / (2.0 * (N - 1.0) * std::log(2.0));
    case -1: return 1.0;
    case -2: return (N * N - 1.0) / (1.5 * N * (N - 1.0));
    default: return N * (1.0 - std::pow(N, mu)) / (2.0 * (N - 1.0) * (1.0 - std::pow(2.0, mu)));
  }
}

double b1_ratio(std::span<const double> x, std::size_t m) {
  if (m == 0 || x.size() < m + 1) return 0.0;
  const std::size_t count = (x.size() - 1) / m;
  if (count < 2) return 0.0;
  auto z = [&](std::size_t k) { return x[(k + 1) * m] - x[k * m]; };
  double mean = 0.0;
  for (std::size_t k = 0; k < count; ++k) mean += z(k);
  mean /= static_cast<double>(count);
  double svar = 0.0, avar2 = 0.0;
  for (std::size_t k = 0; k < count; ++k) svar += (z(k) - mean) * (z(k) - mean);
  svar /= static_cast<double>(count - 1);
  for (std::size_t k = 0; k + 1 < count; ++k) avar2 += (z(k + 1) - z(k)) * (z(k + 1) - z(k));
  avar2 /= 2.0 * static_cast<double>(count - 1);
  return avar2 > 0.0 ? svar / avar2 : 0.0;
}

double rn_expected(double m, int alpha) {
  if (alpha == 2) return 1.0 / m;
  if (alpha == 1) {
    // AVAR and MVAR of flicker PM with f_h tau = m / 2 (IEEE 1139-2008):
    // (1.038 + 3 ln(2 pi f_h tau)) / (4 pi^2) and 3 ln(256/27) / (8 pi^2).
    const double pi2 = std::numbers::pi * std::numbers::pi;
    const double avar = (1.038 + 3.0 * std::log(std::numbers::pi * m)) / (4.0 * pi2);
    const double mvar = 3.0 * std::log(256.0 / 27.0) / (8.0 * pi2);
    return mvar / avar;
  }
  return 1.0;
}

double rn_ratio(std::span<const double> x, std::size_t m) {
  const VarianceTerm mv = mvar(x, m, 1.0);
  const VarianceTerm av = avar(x, m, 1.0);
  if (mv.n == 0 || av.n == 0 || !(av.var > 0.0)) return 0.0;
  return mv.var / av.var;
}

std::optional<Lag1NoiseId> lag1_noise_id(std::span<const double> x, std::size_t af, DataType type, int dmin, int dmax) {
  if (af == 0 || dmin < 0 || dmax < 0) return std::nullopt;
  std::vector<double> series;
  int add = 0;
  if (type == DataType::phase) {
    std::vector<double> decimated;
    for (std::size_t i = 0; i < x.size(); i += af) decimated.push_back(x[i]);
    if (decimated.size() < kMinLag1Points) return std::nullopt;
    series = detrend(decimated, 2);
    add = 2;
  } else {
    std::vector<double> averages(x.size() / af);
    for (std::size_t k = 0; k < averages.size(); ++k) {
      double sum = 0.0;
      for (std::size_t j = 0; j < af; ++j) sum += x[k * af + j];
      averages[k] = sum / static_cast<double>(af);
    }
    if (averages.size() < kMinLag1Points) return std::nullopt;
    series = detrend(averages, 1);
  }
  for (int d = 0;; ++d) {
    if (series.size() < 2) return std::nullopt;
    const double r1 = lag1_acf(series);
    const double rho = r1 / (1.0 + r1);
    if (d >= dmin && (rho < 0.25 || d >= dmax)) {
      Lag1NoiseId out;
      out.d = d;
      out.rho = rho;
      out.alpha = -2.0 * (rho + d) + add;
      out.alpha_int = static_cast<int>(-std::nearbyint(2.0 * rho)) - 2 * d + add;
      return out;
    }
    for (std::size_t i = 0; i + 1 < series.size(); ++i) series[i] = series[i + 1] - series[i];
    series.pop_back();
  }
}

}  // namespace cubecal
