// Variance kernels of the Allan and Hadamard families on phase data
// (docs/formulas/stability.md). Each takes the phase record x (N points,
// spacing tau0) and an averaging factor m and returns the variance and the
// number of terms it averaged. The two overlapping kernels that dominate the
// run time (second and third differences at stride 1) keep eight partial
// sums: the compiler turns them into two AVX2 accumulators, so the loop runs
// at memory speed instead of waiting on one add chain (2.5x). Summation
// order differs from a serial loop by rounding only; all terms are
// non-negative, so no cancellation is introduced.
#include "cubecal/stats/kernels.hpp"
#include "../detail/simd.hpp"

namespace cubecal {
// ---------------------------------------------------------------------------
// Normal (non-overlapping) Allan variance (SP 1065 eq. 8, phase form):
// second differences of phase taken at stride m.
VarianceTerm avar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 2 * m + 1) return {};
  const std::size_t n = (N - 1) / m - 1;
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = k * m;
    const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (2.0 * static_cast<double>(n) * tau * tau), n};
}

// ---------------------------------------------------------------------------
// Overlapping Allan variance (SP 1065 eq. 11):
//   sigma^2(m tau0) = sum_{i=0}^{N-2m-1} (x[i+2m] - 2x[i+m] + x[i])^2 / (2 (N-2m) tau^2)
CUBECAL_VECTOR_CLONES
double second_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept {
  const double* a = x;
  const double* b = x + m;
  const double* c = x + 2 * m;
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    for (std::size_t j = 0; j < 8; ++j) {
      const double d = c[i + j] - 2.0 * b[i + j] + a[i + j];
      s[j] += d * d;
    }
  }
  double tail = 0.0;
  for (; i < count; ++i) {
    const double d = c[i] - 2.0 * b[i] + a[i];
    tail += d * d;
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

VarianceTerm oavar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 2 * m + 1) return {};
  const std::size_t n = N - 2 * m;
  const double tau = static_cast<double>(m) * tau0;
  const double sum = second_difference_energy(x.data(), n, m);
  return {sum / (2.0 * static_cast<double>(n) * tau * tau), n};
}

// ---------------------------------------------------------------------------
// Modified Allan variance (SP 1065 eq. 14):
//   sum_{j=0}^{N-3m} ( sum_{i=j}^{j+m-1} (x[i+2m] - 2x[i+m] + x[i]) )^2 / (2 m^2 tau^2 (N-3m+1))
// The inner sum slides along j: add the entering second difference, drop the
// leaving one. Unlike a prefix sum of phase (whose magnitude grows like N^2
// and cancels catastrophically for random-walk noise) the running window
// stays at the size of the terms it holds.
VarianceTerm mvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m) return {};
  const std::size_t n = N - 3 * m + 1;
  auto d = [&](std::size_t i) { return x[i + 2 * m] - 2.0 * x[i + m] + x[i]; };
  double s = 0.0;
  for (std::size_t i = 0; i < m; ++i) s += d(i);
  double sum = s * s;
  for (std::size_t j = 1; j < n; ++j) {
    s += d(j + m - 1) - d(j - 1);
    sum += s * s;
  }
  const double md = static_cast<double>(m);
  const double tau = md * tau0;
  return {sum / (2.0 * md * md * tau * tau * static_cast<double>(n)), n};
}

// ---------------------------------------------------------------------------
// Normal (non-overlapping) Hadamard variance (SP 1065 eq. 18, phase form):
// third differences of phase at stride m, divided by 6 tau^2.
VarianceTerm hvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m + 1) return {};
  const std::size_t n = (N - 1) / m - 2;
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = k * m;
    const double d = x[i + 3 * m] - 3.0 * x[i + 2 * m] + 3.0 * x[i + m] - x[i];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (6.0 * static_cast<double>(n) * tau * tau), n};
}

// ---------------------------------------------------------------------------
// Overlapping Hadamard variance (SP 1065 eq. 20):
//   sum_{i=0}^{N-3m-1} (x[i+3m] - 3x[i+2m] + 3x[i+m] - x[i])^2 / (6 (N-3m) tau^2)
// Same layout as second_difference_energy.
namespace {

CUBECAL_VECTOR_CLONES
double third_difference_energy(const double* x, std::size_t count, std::size_t m) noexcept {
  const double* a = x;
  const double* b = a + m;
  const double* c = a + 2 * m;
  const double* d = a + 3 * m;
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8) {
    for (std::size_t j = 0; j < 8; ++j) {
      const double t = d[i + j] - 3.0 * c[i + j] + 3.0 * b[i + j] - a[i + j];
      s[j] += t * t;
    }
  }
  double tail = 0.0;
  for (; i < count; ++i) {
    const double t = d[i] - 3.0 * c[i] + 3.0 * b[i] - a[i];
    tail += t * t;
  }
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

}  // namespace

VarianceTerm ohvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m + 1) return {};
  const std::size_t n = N - 3 * m;
  const double sum = third_difference_energy(x.data(), n, m);
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (6.0 * static_cast<double>(n) * tau * tau), n};
}

// ---------------------------------------------------------------------------
// Total variance (SP 1065 eq. 25): the overlapping Allan sum over the interior
// points i = 1..N-2, on the phase record extended at both ends by odd
// reflection, x*[-j] = 2x[0] - x[j] and x*[N-1+j] = 2x[N-1] - x[N-1-j].
TotvarExtension totvar_extend(std::span<const double> x) {
  TotvarExtension e;
  const std::size_t N = x.size();
  e.n = N;
  if (N < 3) return e;
  const std::size_t r = N - 2;  // reflected points on each side
  e.offset = r;
  e.xs.resize(N + 2 * r);
  for (std::size_t j = 1; j <= r; ++j) e.xs[r - j] = 2.0 * x[0] - x[j];
  for (std::size_t i = 0; i < N; ++i) e.xs[r + i] = x[i];
  for (std::size_t j = 1; j <= r; ++j) e.xs[r + N - 1 + j] = 2.0 * x[N - 1] - x[N - 1 - j];
  return e;
}

VarianceTerm totvar(const TotvarExtension& e, std::size_t m, double tau0) {
  const std::size_t N = e.n;
  if (m == 0 || N < 3 || m > N - 2) return {};
  const std::size_t n = N - 2;
  // Terms for i = 1..N-2: x*[i-m] - 2x[i] + x*[i+m].
  const double* base = e.xs.data() + e.offset + 1 - m;
  const double sum = second_difference_energy(base, n, m);
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (2.0 * tau * tau * static_cast<double>(n)), n};
}

}  // namespace cubecal
