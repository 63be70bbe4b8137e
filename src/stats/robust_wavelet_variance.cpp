// The robust Haar wavelet variance (stats/robust_wavelet_variance.hpp;
// docs/formulas/noise-terms.md §8e).
#include "cubecal/stats/robust_wavelet_variance.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

#include "../detail/simd.hpp"
#include "cubecal/error.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/phase.hpp"

namespace cubecal {

namespace {

// ---------------------------------------------------------------------------
// Gaussian moments of chi(z) = z^2 (1 - z^2/c^2)^4 on |z| <= c: composite
// five-point Gauss-Legendre on panels of width <= 0.1 over [0, min(c, 12)]
// (the integrands are polynomials times the normal density, smooth inside
// the window; beyond 12 the density is below 1e-31), doubled for symmetry.
// Direct quadrature rather than the truncated-moment recursion, whose
// alternating sums up to z^20 / c^16 lose digits at small c.
struct Moments {
  double a = 0.0, z2chi = 0.0, chi2 = 0.0;  // E chi, E z^2 chi, E chi^2
};

Moments gaussian_moments(double c) {
  static constexpr double kNode[5] = {0.0, 0.5384693101056831, -0.5384693101056831, 0.9061798459386640,
                                      -0.9061798459386640};
  static constexpr double kWeight[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                                        0.2369268850561891};
  const double top = std::min(c, 12.0);
  const auto panels = static_cast<int>(std::ceil(top / 0.1));
  const double h = top / panels;
  const double norm = 1.0 / std::sqrt(2.0 * std::numbers::pi);
  const double ic2 = 1.0 / (c * c);
  Moments m;
  for (int p = 0; p < panels; ++p) {
    const double mid = (p + 0.5) * h;
    for (int k = 0; k < 5; ++k) {
      const double z = mid + 0.5 * h * kNode[k];
      const double z2 = z * z;
      const double t = 1.0 - z2 * ic2;
      const double t2 = t * t;
      const double chi = z2 * t2 * t2;
      const double w = kWeight[k] * 0.5 * h * norm * std::exp(-0.5 * z2);
      m.a += w * chi;
      m.z2chi += w * z2 * chi;
      m.chi2 += w * chi * chi;
    }
  }
  m.a *= 2.0;
  m.z2chi *= 2.0;
  m.chi2 *= 2.0;
  return m;
}

constexpr double kMaxC = 100.0;

// The c where E[(Z^2 - 1) chi] changes sign (near 2.6): below it the
// estimating equation's Gaussian root is on the wrong branch; above it the
// efficiency rises monotonically from 0 towards 1.
double branch_point() {
  double lo = 1.0, hi = 4.0;  // slope < 0 at 1, > 0 at 4
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (biweight_moments(mid).slope < 0.0 ? lo : hi) = mid;
  }
  return hi;
}

// ---------------------------------------------------------------------------
// Neumaier-compensated prefix sums of the mean-removed samples divided by
// scale (a power of two): P[i] = hi[i] + lo[i] to about a rounding of P[i]
// squared. A window sum is the difference of two nearby prefix sums (exact
// by Sterbenz's lemma where they are large and close, which is where a
// plain running sum would cancel) plus the difference of their corrections.
struct Prefix {
  std::vector<double> hi, lo;
  double scale = 1.0;
};

Prefix compensated_prefix(std::span<const double> y) {
  Prefix p;
  p.scale = power_of_two_scale(y);  // names a sample that is not finite
  const std::size_t N = y.size();
  const double inv = 1.0 / p.scale;
  double mean = 0.0;
  for (double v : y) mean += v * inv;
  mean /= static_cast<double>(N);
  p.hi.assign(N + 1, 0.0);
  p.lo.assign(N + 1, 0.0);
  double s = 0.0, comp = 0.0;
  for (std::size_t i = 0; i < N; ++i) {
    const double v = y[i] * inv - mean;
    const double t = s + v;
    comp += std::abs(s) >= std::abs(v) ? (s - t) + v : (v - t) + s;
    s = t;
    p.hi[i + 1] = s;
    p.lo[i + 1] = comp;
  }
  return p;
}

// tau W_t / scale: the later m-sample sum minus the earlier one.
inline double haar_difference(const Prefix& p, std::size_t t, std::size_t m) noexcept {
  const double first = (p.hi[t + m] - p.hi[t]) + (p.lo[t + m] - p.lo[t]);
  const double second = (p.hi[t + 2 * m] - p.hi[t + m]) + (p.lo[t + 2 * m] - p.lo[t + m]);
  return second - first;
}

// ---------------------------------------------------------------------------
// The estimating equation in u = ln s^2 over the squares v:
//   g(u)  = mean chi(r) - a,            r^2 = v / s^2,
//   g'(u) = -mean r^2 t^3 (1 - 5q),     q = r^2 / c^2, t = max(1 - q, 0),
// from d chi / dr * r = 2 r^2 t^3 (1 - 5q) and dr/du = -r/2. Branch-free
// (t = 0 outside the window) on explicit four-double lanes, two of them in
// flight (the compiler does not vectorise the max of a scalar loop).
struct Equation {
  double g = 0.0, dg = 0.0;
};

using Lanes = double __attribute__((vector_size(4 * sizeof(double))));

CUBECAL_VECTOR_CLONES
void chi_sums(const double* v, std::size_t n, double inv_s2, double inv_s2c2, double* out) noexcept {
  Lanes s[2] = {}, d[2] = {};
  const Lanes zero = {0.0, 0.0, 0.0, 0.0};
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (std::size_t k = 0; k < 2; ++k) {
      Lanes x;
      std::memcpy(&x, v + i + 4 * k, sizeof x);
      const Lanes q = x * inv_s2c2;
      const Lanes r2 = x * inv_s2;
      const Lanes u = 1.0 - q;
      const Lanes t = u > zero ? u : zero;
      const Lanes t3 = t * t * t;
      s[k] += r2 * t3 * t;
      d[k] += r2 * t3 * (1.0 - 5.0 * q);
    }
  double st = 0.0, dt = 0.0;
  for (; i < n; ++i) {
    const double q = v[i] * inv_s2c2;
    const double r2 = v[i] * inv_s2;
    const double t = std::max(1.0 - q, 0.0);
    const double t3 = t * t * t;
    st += r2 * t3 * t;
    dt += r2 * t3 * (1.0 - 5.0 * q);
  }
  const Lanes ss = s[0] + s[1], dd = d[0] + d[1];
  out[0] = ((ss[0] + ss[1]) + (ss[2] + ss[3])) + st;
  out[1] = ((dd[0] + dd[1]) + (dd[2] + dd[3])) + dt;
}

Equation equation(std::span<const double> v, double u, const BiweightTuning& t) {
  const double inv_s2 = std::exp(-u);
  double sums[2];
  chi_sums(v.data(), v.size(), inv_s2, inv_s2 / (t.c * t.c), sums);
  const double n = static_cast<double>(v.size());
  return {sums[0] / n - t.a, -sums[1] / n};
}

}  // namespace

BiweightTuning biweight_moments(double c) {
  const Moments m = gaussian_moments(c);
  BiweightTuning t;
  t.c = c;
  t.a = m.a;
  t.slope = m.z2chi - m.a;
  t.var_chi = m.chi2 - m.a * m.a;
  t.efficiency = t.slope * t.slope / (2.0 * t.var_chi);
  return t;
}

BiweightTuning biweight_tuning(double efficiency) {
  if (!(efficiency > 0.0 && efficiency < 1.0))
    throw UsageError(Field::efficiency,
                     "the efficiency of the robust wavelet variance must lie between 0 and 1 (0.6 is "
                     "usual; 1 is the classical estimator)");
  static const double lo0 = branch_point();
  static const double top = biweight_moments(kMaxC).efficiency;
  if (efficiency > top)
    throw UsageError(Field::efficiency, "the efficiency of the robust wavelet variance can be at most " +
                                            std::to_string(top).substr(0, 8) +
                                            " (a higher one is the classical estimator: leave the robust option off)");
  double lo = lo0, hi = kMaxC;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (biweight_moments(mid).efficiency < efficiency ? lo : hi) = mid;
  }
  return biweight_moments(0.5 * (lo + hi));
}

double biweight_variance(std::span<const double> v, const BiweightTuning& t) {
  const std::size_t n = v.size();
  if (n == 0) throw std::invalid_argument("biweight_variance: no values");
  // The start: the MAD scale (for zero-mean Gaussian values median |w| =
  // 0.67449 sigma) of at most 2^15 values taken at a stride; only the start
  // depends on it, not the root.
  const std::size_t stride = std::max<std::size_t>(n >> 15, 1);
  std::vector<double> sample;
  sample.reserve(n / stride + 1);
  for (std::size_t i = 0; i < n; i += stride) sample.push_back(v[i]);
  const auto mid = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2);
  std::nth_element(sample.begin(), mid, sample.end());
  double s2 = *mid / (0.6744897501960817 * 0.6744897501960817);
  if (!(s2 > 0.0)) {
    double sum = 0.0;
    for (double x : v) sum += x;
    s2 = sum / static_cast<double>(n);
    if (!(s2 > 0.0)) return 0.0;
  }
  const auto eval = [&](double u) { return equation(v, u, t); };
  // Golden-section search for the peak of g on [a, b].
  struct Peak {
    double u, g;
  };
  const auto peak = [&](double a, double b) {
    constexpr double kInvPhi = 0.6180339887498949;
    double x1 = b - kInvPhi * (b - a), x2 = a + kInvPhi * (b - a);
    double f1 = eval(x1).g, f2 = eval(x2).g;
    for (int i = 0; i < 100 && b - a > 1e-12; ++i) {
      if (f1 < f2) {
        a = x1;
        x1 = x2;
        f1 = f2;
        x2 = a + kInvPhi * (b - a);
        f2 = eval(x2).g;
      } else {
        b = x2;
        x2 = x1;
        f2 = f1;
        x1 = b - kInvPhi * (b - a);
        f1 = eval(x1).g;
      }
    }
    return f1 > f2 ? Peak{x1, f1} : Peak{x2, f2};
  };

  // Newton's method on u = ln s^2 from the start, kept on the upper root:
  // g -> -a at both ends (every r outside the window or at 0) and is
  // positive between its two roots; the consistent root is where g
  // decreases. lo: the highest u seen with g >= 0 (below the upper root);
  // hi: the lowest with g < 0 and falling (above it); left: the highest with
  // g < 0 and rising (below the lower root). Steps are at most a factor 2
  // in s; a Newton step that leaves [lo, hi] is a bisection; g rising
  // means a step up. Where g stays below 0 (more than about a quarter of
  // the values far out or zero) there is no root: the estimate is then g's
  // maximiser, the s that comes closest to the equation (what the gmwm
  // package's minimisation of (mean chi - a)^2 returns), continuous with
  // the root as it vanishes.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kStep = 0.6931471805599453;
  double lo = -kInf, hi = kInf, left = -kInf;
  double u = std::log(s2);
  for (int i = 0; i < 200; ++i) {
    const Equation e = eval(u);
    if (e.g == 0.0) break;
    const bool falling = e.dg < 0.0;
    if (e.g > 0.0)
      lo = std::max(lo, u);
    else if (falling)
      hi = std::min(hi, u);
    else
      left = std::max(left, u);
    double next;
    bool newton = false;
    if (lo == -kInf && left > -kInf && hi < kInf) {  // both sides of the peak, never above 0
      const Peak p = peak(left, hi);
      if (p.g < 0.0) return std::exp(p.u);
      lo = p.u;
      next = 0.5 * (lo + hi);
    } else {
      next = falling ? u - e.g / e.dg : u + kStep;
      newton = falling && std::abs(next - u) < kStep;
      next = std::clamp(next, u - 2.0 * kStep, u + 2.0 * kStep);
      if (lo > -kInf && hi < kInf && !(next > lo && next < hi)) {
        next = 0.5 * (lo + hi);
        newton = false;
      }
    }
    const double step = std::abs(next - u);
    u = next;
    // A Newton step below 1e-7 leaves an error of its square's order.
    if ((newton && step < 1e-7) || hi - lo < 1e-13) break;
  }
  return std::exp(u);
}

std::vector<double> haar_coefficients(std::span<const double> y, std::size_t tau) {
  const std::size_t N = y.size();
  if (tau < 2 || tau % 2 != 0 || tau > N)
    throw std::invalid_argument("haar_coefficients: the scale must be even, at least 2 and at most the samples");
  const Prefix p = compensated_prefix(y);
  const double f = p.scale / static_cast<double>(tau);
  std::vector<double> w(N - tau + 1);
  for (std::size_t t = 0; t < w.size(); ++t) w[t] = haar_difference(p, t, tau / 2) * f;
  return w;
}

WaveletVariance robust_wavelet_variance(std::span<const double> y, double ci, double efficiency,
                                        std::size_t max_scales) {
  const std::size_t N = y.size();
  if (N < 4)
    throw UsageError(Field::samples, "the wavelet variance needs at least 4 samples, not " + std::to_string(N));
  if (!(ci > 0.0 && ci < 1.0)) throw UsageError(Field::ci, "the confidence must lie between 0 and 1");
  const BiweightTuning tuning = biweight_tuning(efficiency);
  const Prefix p = compensated_prefix(y);  // once for all scales
  const double scale = p.scale;

  WaveletVariance wv;
  std::vector<double> v;
  v.reserve(N);
  for (std::size_t tau = 2; tau <= N / 2; tau *= 2) {
    if (max_scales > 0 && wv.size() == max_scales) break;
    const std::size_t m = tau / 2;
    const std::size_t M = N - tau + 1;
    const double f = 1.0 / static_cast<double>(tau);
    v.resize(M);
    for (std::size_t t = 0; t < M; ++t) {
      const double w = haar_difference(p, t, m) * f;
      v[t] = w * w;
    }
    const double nu2 = biweight_variance(v, tuning) * scale * scale;
    const double td = static_cast<double>(tau);
    // eta3 times the efficiency. By the Hermite expansion of chi the robust
    // estimate's variance is the classical one's times sum_k e_k^2/k! S_k /
    // (e_2^2/2 S_2), e_k = E[chi He_k], S_k = sum_l rho(l)^k over the
    // coefficients' correlations: 1/eff when they are uncorrelated, towards
    // 1 as they correlate (S_k <= S_2). eff * eta3 is the EDF on the safe
    // side for every model, and one factor on every scale leaves the GMWM
    // weights' ratios as the classical ones' (§8e).
    const double edf = tuning.efficiency * std::max(static_cast<double>(M) / td, 1.0);
    const Interval band = chi2_interval(std::sqrt(nu2), edf, ci);
    wv.tau.push_back(td);
    wv.nu2.push_back(nu2);
    wv.n.push_back(M);
    wv.edf.push_back(edf);
    wv.interval.push_back({band.lo * band.lo, band.hi * band.hi});
  }
  return wv;
}

}  // namespace cubecal
