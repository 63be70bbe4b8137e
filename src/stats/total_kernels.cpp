// MTOT and HTOT kernels (docs/formulas/stability.md, "Total variances").
//
// Both are, for each of the n = L - 3m + 1 subsequences y of 3m points of a
// series of length L (phase for MTOT, phase differences for HTOT):
//   1. the slope s from the means of the first and last floor(3m/2) points
//      over the distance between their centres; y[k] -= s k;
//   2. y extended to x* = [reverse(y), y, reverse(y)] (9m points);
//   3. E = 1/(6m) sum_{j=0}^{6m-1} (S(j) - 2 S(j+m) + S(j+2m))^2 / m^2, S(j)
//      the sum of x*[j .. j+m).
// With P the prefix sums of x*, S(j) - 2S(j+m) + S(j+2m) is the third
// difference P(j+3m) - 3P(j+2m) + 3P(j+m) - P(j), and P follows from the
// prefix sums Y of y alone: P(q) = Y(3m) - Y(3m-q) on the first third,
// Y(3m) + Y(q-3m) on the second, 3Y(3m) - Y(9m-q) on the last; the slope's
// part is the same third difference of the ramp, once per factor.
//
// The cost is O(m) per subsequence, O(L m) per factor, with a vectorised
// inner loop (against one interpreted step per term in AllanTools). No
// O(L) recurrence over the subsequences exists: from one subsequence to the
// next the middle third of x* moves one way and the reflected thirds the
// other, so the 6m terms do not slide; rewriting the sum as a quadratic form
// in lagged products of the record (computable for all subsequences at once
// by FFT) subtracts sums of size N var(x) to get sums of squared second
// differences, which loses every digit on random-walk phase. Each
// subsequence is taken relative to its first point, so sums stay at the size
// of the local excursion.
#include "detail/total_kernels.hpp"

#include <algorithm>
#include <vector>

#include "../detail/simd.hpp"

namespace cubecal {

namespace {

// Subsequences between fresh prefix sums: the update in between adds one
// rounding per step, so the drift stays within a few hundred ulp of the sums.
constexpr std::size_t kAnchor = 256;

// a[j] = A_j(D) for every j in [0, 6m), written out through P: the third
// differences of the extension built on prefix sums D[0 .. 3m] (used for the
// ramp, once per factor).
void third_differences(const double* D, std::size_t m, double* a) {
  const std::size_t L = 3 * m;
  std::vector<double> P(3 * L + 1);
  const double top = D[L];
  for (std::size_t q = 0; q <= L; ++q) P[q] = top - D[L - q];
  for (std::size_t q = 1; q <= L; ++q) P[L + q] = top + D[q];
  for (std::size_t q = 1; q <= L; ++q) P[2 * L + q] = 3.0 * top - D[L - q];
  for (std::size_t j = 0; j < 2 * L; ++j) a[j] = P[j + L] - 3.0 * P[j + 2 * m] + 3.0 * P[j + m] - P[j];
}

// Sums of (A_j(Y) - s B_j)^2 over a range of j, one function per range
// (the four terms of Y run forward or backward from j differently in each).
// Y: prefix sums of the subsequence (Y[0 .. 3m]), B: A_j of the ramp.
#define CUBECAL_RANGE_ENERGY(name, expr)                                                           \
  CUBECAL_VECTOR_CLONES                                                                            \
  double name(const double* Y, const double* B, double s, double c, std::size_t m, std::size_t lo, \
              std::size_t hi) noexcept {                                                           \
    double acc[4] = {0, 0, 0, 0};                                                                  \
    std::size_t u = lo;                                                                            \
    for (; u + 4 <= hi + 1; u += 4)                                                                \
      for (std::size_t k = 0; k < 4; ++k) {                                                        \
        const std::size_t j = u + k;                                                               \
        const double a = (c + (expr)) - s * B[j];                                                  \
        acc[k] += a * a;                                                                           \
      }                                                                                            \
    double tail = 0.0;                                                                             \
    for (std::size_t j = u; j <= hi; ++j) {                                                        \
      const double a = (c + (expr)) - s * B[j];                                                    \
      tail += a * a;                                                                               \
    }                                                                                              \
    return (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail;                                           \
  }

// j in [0, m]:   D(j) + 3D(m-j) - 3D(2m-j) + D(3m-j)
CUBECAL_RANGE_ENERGY(energy_first, (Y[j] + Y[3 * m - j]) + 3.0 * (Y[m - j] - Y[2 * m - j]))
// j in [m, 2m]:  D(j) - 3D(j-m) - 3D(2m-j) + D(3m-j)
CUBECAL_RANGE_ENERGY(energy_second, (Y[j] + Y[3 * m - j]) - 3.0 * (Y[j - m] + Y[2 * m - j]))
// j = 3m + v, v in [0, m]:   2T - D(3m-v) - 3D(2m+v) + 3D(m+v) - D(v)   (B indexed by j)
CUBECAL_RANGE_ENERGY(energy_third, -(Y[6 * m - j] + Y[j - 3 * m]) + 3.0 * (Y[j - 2 * m] - Y[j - m]))
// j = 3m + v, v in [m, 2m]:  -4T - D(3m-v) + 3D(4m-v) + 3D(m+v) - D(v)
CUBECAL_RANGE_ENERGY(energy_fourth, -(Y[6 * m - j] + Y[j - 3 * m]) + 3.0 * (Y[7 * m - j] + Y[j - 2 * m]))

#undef CUBECAL_RANGE_ENERGY

// Y[k] -= k step for k in [1, L).
CUBECAL_VECTOR_CLONES
void shift_update(double* Y, const double* k, double step, std::size_t L) noexcept {
  for (std::size_t i = 1; i < L; ++i) Y[i] -= k[i] * step;
}

// Sum over the subsequences of E (step 3 above), on data[0 .. len).
//
// Symmetry halves the terms: x* is one period of the even sequence
// [reverse(y), y] (period 6m) and the filter (+1, -2, +1 on m points each)
// is symmetric too, so A_j = A_{3m-j} and A_j = A_{9m-j} (mod 6m). With
// h = floor((3m-1)/2),
//   sum_j A_j^2 = 2 (sum_{j=0}^{h} A_j^2 + sum_{j=3m}^{3m+h} A_j^2) - A_0^2 - A_{3m}^2
//                 + (m even: A_{3m/2}^2 + A_{9m/2}^2),
// and on those ranges A_j is four prefix sums of the subsequence (the
// energy_* functions above; T = D[3m] enters with 0, 0, 2 and -4). The
// ramp's part s B_j is taken out (B = A of the ramp, once per factor).
// Per subsequence: one pass to update Y (no carried dependence) and about
// 3m terms of four loads each, with no array written but Y; Y and B stay in
// cache from one subsequence to the next.
double total_energy(const double* data, std::size_t len, std::size_t m) {
  const std::size_t L = 3 * m;
  const std::size_t n = len - L + 1;
  const std::size_t h1 = L / 2, h2 = (L + 1) / 2;
  const std::size_t h = (L - 1) / 2;
  // Distance between the centres of the halves [0, h1) and [h2, L).
  const double dist =
      (static_cast<double>(h2) + static_cast<double>(L - h2 - 1) / 2.0) - static_cast<double>(h1 - 1) / 2.0;
  std::vector<double> ramp(L + 1);  // sum_{k<q} k
  for (std::size_t q = 0; q <= L; ++q) ramp[q] = 0.5 * static_cast<double>(q) * (static_cast<double>(q) - 1.0);
  std::vector<double> B(2 * L);
  third_differences(ramp.data(), m, B.data());
  // Y of subsequence i at buf[base .. base + L]; each step moves base by one.
  std::vector<double> buf(L + kAnchor + 1);
  std::vector<double> kd(L);  // k
  for (std::size_t k = 0; k < L; ++k) kd[k] = static_cast<double>(k);
  const double md = static_cast<double>(m);
  const std::size_t first_hi = std::min(h, m);
  double total = 0.0;
  std::size_t base = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double* y = data + i;
    if (i % kAnchor == 0) {
      // Y[k] = sum_{j<k} (y[j] - y[0]), summed afresh.
      base = 0;
      const double y0 = y[0];
      double acc = 0.0;
      buf[0] = 0.0;
      for (std::size_t k = 0; k < L; ++k) {
        acc += y[k] - y0;
        buf[k + 1] = acc;
      }
    } else {
      // From the previous subsequence's sums: Y'[k] = Y[k+1] - k (y[0] - y[-1]).
      ++base;
      double* Yw = buf.data() + base;
      const double step = y[0] - y[-1];
      shift_update(Yw, kd.data(), step, L);
      Yw[L] = Yw[L - 1] + (y[L - 1] - y[0]);
    }
    const double* Y = buf.data() + base;
    const double mean1 = Y[h1] / static_cast<double>(h1);
    const double mean2 = (Y[L] - Y[h2]) / static_cast<double>(L - h2);
    const double s = (mean2 - mean1) / dist;
    const double T = Y[L];
    double half = energy_first(Y, B.data(), s, 0.0, m, 0, first_hi);
    if (h > m) half += energy_second(Y, B.data(), s, 0.0, m, m + 1, h);
    half += energy_third(Y, B.data(), s, 2.0 * T, m, L, L + first_hi);
    if (h > m) half += energy_fourth(Y, B.data(), s, -4.0 * T, m, L + m + 1, L + h);
    const double a0 = (Y[0] + Y[3 * m]) + 3.0 * (Y[m] - Y[2 * m]) - s * B[0];
    const double a3 = 2.0 * T - (Y[3 * m] + Y[0]) + 3.0 * (Y[m] - Y[2 * m]) - s * B[L];
    double e = 2.0 * half - a0 * a0 - a3 * a3;
    if (m % 2 == 0) {
      const std::size_t j = L / 2;  // 3m/2, in [m, 2m]
      const double am = (Y[j] + Y[3 * m - j]) - 3.0 * (Y[j - m] + Y[2 * m - j]) - s * B[j];
      const std::size_t k = L + L / 2;  // 9m/2 = 3m + 3m/2, in [4m, 5m]
      const double an = -4.0 * T - (Y[6 * m - k] + Y[k - 3 * m]) + 3.0 * (Y[7 * m - k] + Y[k - 2 * m]) - s * B[k];
      e += am * am + an * an;
    }
    total += e;
  }
  return total / (6.0 * md * md * md);
}

}  // namespace

VarianceTerm mtotvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m) return {};
  const std::size_t n = N - 3 * m + 1;
  const double e = total_energy(x.data(), N, m);
  const double tau = static_cast<double>(m) * tau0;
  return {e / (2.0 * tau * tau * static_cast<double>(n)), n};
}

VarianceTerm htotvar(std::span<const double> d, std::size_t m, double tau0) {
  const std::size_t L = d.size();
  if (m == 0 || L < 3 * m) return {};
  const std::size_t n = L - 3 * m + 1;
  const double e = total_energy(d.data(), L, m);
  return {e / (6.0 * tau0 * tau0 * static_cast<double>(n)), n};
}

}  // namespace cubecal
