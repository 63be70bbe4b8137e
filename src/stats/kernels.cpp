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

#include <algorithm>
#include <cmath>
#include <cstring>

#include "../detail/simd.hpp"
#include "detail/difference_energy.hpp"
#include "detail/total_kernels.hpp"

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
// leaving one (together, the third difference x[j+3m-1] - 3x[j+2m-1] +
// 3x[j+m-1] - x[j-1]). Unlike a prefix sum of phase (whose magnitude grows
// like N^2 and cancels catastrophically for random-walk noise) the running
// window stays at the size of the terms it holds. The j range is cut into
// four blocks, each window started from its own direct sum, and the four
// run interleaved: four independent add chains instead of one (3x), and
// each chain four times shorter, so less rounding accumulates.
namespace {

CUBECAL_VECTOR_CLONES
double second_difference_sum(const double* x, std::size_t count, std::size_t m) noexcept {
  const double* a = x;
  const double* b = x + m;
  const double* c = x + 2 * m;
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= count; i += 8)
    for (std::size_t j = 0; j < 8; ++j) s[j] += (c[i + j] - 2.0 * b[i + j]) + a[i + j];
  double tail = 0.0;
  for (; i < count; ++i) tail += (c[i] - 2.0 * b[i]) + a[i];
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

// Sum of the squared window sums for j in [first, last), the window at
// `first` given.
struct Window {
  double s;    // sum_{i=j}^{j+m-1} second difference, at the current j
  double sum;  // squares so far
};

inline double third_difference_back(const double* x, std::size_t j, std::size_t m) noexcept {
  return x[j + 3 * m - 1] - 3.0 * x[j + 2 * m - 1] + 3.0 * x[j + m - 1] - x[j - 1];
}

}  // namespace

VarianceTerm mvar(std::span<const double> x, std::size_t m, double tau0) {
  const std::size_t N = x.size();
  if (m == 0 || N < 3 * m) return {};
  const std::size_t n = N - 3 * m + 1;
  const double* p = x.data();
  constexpr std::size_t L = 4;
  const std::size_t len = n / L;  // j per block; the last block also takes the rest
  double sum = 0.0;
  if (len < 2) {
    double s = second_difference_sum(p, m, m);
    sum = s * s;
    for (std::size_t j = 1; j < n; ++j) {
      s += third_difference_back(p, j, m);
      sum += s * s;
    }
  } else {
    Window w[L];
    for (std::size_t l = 0; l < L; ++l) {
      const double s = second_difference_sum(p + l * len, m, m);
      w[l] = {s, s * s};
    }
    for (std::size_t t = 1; t < len; ++t)
      for (std::size_t l = 0; l < L; ++l) {
        w[l].s += third_difference_back(p, l * len + t, m);
        w[l].sum += w[l].s * w[l].s;
      }
    for (std::size_t j = L * len; j < n; ++j) {
      w[L - 1].s += third_difference_back(p, j, m);
      w[L - 1].sum += w[L - 1].s * w[L - 1].s;
    }
    sum = (w[0].sum + w[1].sum) + (w[2].sum + w[3].sum);
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
  if (m == 0 || N < 3 || m > N - 1) return {};
  const std::size_t n = N - 2;
  // Terms for i = 1..N-2: x*[i-m] - 2x[i] + x*[i+m]; the reflection reaches
  // x*[-(N-2)] and x*[2N-3], so every m up to N - 1 is defined.
  const double* base = e.xs.data() + e.offset + 1 - m;
  const double sum = second_difference_energy(base, n, m);
  const double tau = static_cast<double>(m) * tau0;
  return {sum / (2.0 * tau * tau * static_cast<double>(n)), n};
}

// ---------------------------------------------------------------------------
// Several averaging factors at once. One pass of a kernel reads two or three
// operands per term (x[i], x[i+m], x[i+2m]); for a group of eight close
// factors the operand they share (the centre x[c] of a second difference,
// the first point x[i] of a third) is loaded once for all eight, and the
// other streams of neighbouring factors overlap in cache. With eight
// accumulators in flight the loop is no longer bound by one add chain
// either: the `all` grid runs about twice as fast as one call per factor.
// Each factor's sum is its own (four lanes, then the tail), so the results
// equal the single-factor kernels up to rounding. Which factors form a group
// depends on their values only (kernel_group_at), so a factor's result is
// the same bits whichever way a caller cuts its grid into calls.
bool kernel_group_at(std::span<const std::size_t> ms, std::size_t j) noexcept {
  if (j + kKernelGroup > ms.size() || ms[j] % kKernelGroup != 1) return false;
  for (std::size_t k = 1; k < kKernelGroup; ++k)
    if (ms[j + k] != ms[j] + k) return false;
  return true;
}

namespace {

constexpr std::size_t kGroup = kKernelGroup;

using Lanes = double __attribute__((vector_size(4 * sizeof(double))));

// Unaligned load of four doubles (a macro: a function returning a vector
// type would have a different ABI in the baseline and the AVX2 clone).
#define CUBECAL_LOAD_LANES(v, p) \
  Lanes v;                       \
  std::memcpy(&v, (p), sizeof v)

// out[k] = sum_{i<count} (c[i-m_k] - 2 c[i] + c[i+m_k])^2: centred second
// differences around the points c[0..count); c - m_k must lie in the array.
CUBECAL_VECTOR_CLONES
void centred_second_difference_energies(const double* c, std::size_t count, const std::size_t* m,
                                        double* out) noexcept {
  Lanes s[kGroup] = {};
  std::size_t i = 0;
  for (; i + 4 <= count; i += 4) {
    CUBECAL_LOAD_LANES(mid, c + i);
    const Lanes twice = mid + mid;
    for (std::size_t k = 0; k < kGroup; ++k) {
      CUBECAL_LOAD_LANES(lo, c + i - m[k]);
      CUBECAL_LOAD_LANES(hi, c + i + m[k]);
      const Lanes d = (lo + hi) - twice;
      s[k] += d * d;
    }
  }
  for (std::size_t k = 0; k < kGroup; ++k) {
    double tail = 0.0;
    for (std::size_t j = i; j < count; ++j) {
      const double d = (c[j - m[k]] + c[j + m[k]]) - 2.0 * c[j];
      tail += d * d;
    }
    out[k] = ((s[k][0] + s[k][1]) + (s[k][2] + s[k][3])) + tail;
  }
}

// out[k] = sum_{i<count} (x[i+3m_k] - 3x[i+2m_k] + 3x[i+m_k] - x[i])^2.
CUBECAL_VECTOR_CLONES
void third_difference_energies(const double* x, std::size_t count, const std::size_t* m, double* out) noexcept {
  Lanes s[kGroup] = {};
  std::size_t i = 0;
  for (; i + 4 <= count; i += 4) {
    CUBECAL_LOAD_LANES(a, x + i);
    for (std::size_t k = 0; k < kGroup; ++k) {
      CUBECAL_LOAD_LANES(b, x + i + m[k]);
      CUBECAL_LOAD_LANES(c, x + i + 2 * m[k]);
      CUBECAL_LOAD_LANES(d, x + i + 3 * m[k]);
      const Lanes t = (d - a) + 3.0 * (b - c);
      s[k] += t * t;
    }
  }
  for (std::size_t k = 0; k < kGroup; ++k) {
    double tail = 0.0;
    for (std::size_t j = i; j < count; ++j) {
      const double t = (x[j + 3 * m[k]] - x[j]) + 3.0 * (x[j + m[k]] - x[j + 2 * m[k]]);
      tail += t * t;
    }
    out[k] = ((s[k][0] + s[k][1]) + (s[k][2] + s[k][3])) + tail;
  }
}

#undef CUBECAL_LOAD_LANES

// second_difference_energy of several factors, the record walked once in
// tiles of kTile starts rather than once per factor. Each factor keeps the
// single kernel's eight accumulators from tile to tile and adds its terms in
// the same order, so every result is the same bits as
// second_difference_energy(x, n - 2m, m). What changes is where the operands
// come from: for the factors whose three streams of a tile lie within a few
// hundred kB (m up to ~10^4) the tile's points are read from memory once
// and used by every factor from the L2 cache, instead of once per factor
// (a pass per factor over a 72 h x 10 Hz record streams 21 MB from memory).
constexpr std::size_t kTile = 2048;  // a multiple of the eight lanes
constexpr std::size_t kTiledFactors = 16;
// Beyond this factor the three streams of a tile lie apart by more than the
// L2 cache holds, nothing is shared, and one pass per factor (three streams
// the prefetcher follows) is faster than 2k+1 streams at once.
constexpr std::size_t kTiledMaxFactor = 16384;

CUBECAL_VECTOR_CLONES
void second_difference_energies(const double* x, std::size_t n, const std::size_t* m, std::size_t factors,
                                double* out) noexcept {
  double s[kTiledFactors][8] = {};
  std::size_t whole[kTiledFactors];  // starts the eight lanes take: count rounded down to 8
  std::size_t longest = 0;
  for (std::size_t k = 0; k < factors; ++k) {
    whole[k] = (n - 2 * m[k]) / 8 * 8;
    longest = std::max(longest, whole[k]);
  }
  for (std::size_t t0 = 0; t0 < longest; t0 += kTile) {
    for (std::size_t k = 0; k < factors; ++k) {
      const std::size_t end = std::min(t0 + kTile, whole[k]);
      if (end <= t0) continue;
      const double* a = x;
      const double* b = x + m[k];
      const double* c = x + 2 * m[k];
      double acc[8];
      for (std::size_t j = 0; j < 8; ++j) acc[j] = s[k][j];
      for (std::size_t i = t0; i < end; i += 8) {
        for (std::size_t j = 0; j < 8; ++j) {
          const double d = c[i + j] - 2.0 * b[i + j] + a[i + j];
          acc[j] += d * d;
        }
      }
      for (std::size_t j = 0; j < 8; ++j) s[k][j] = acc[j];
    }
  }
  for (std::size_t k = 0; k < factors; ++k) {
    const std::size_t count = n - 2 * m[k];
    const double* b = x + m[k];
    const double* c = x + 2 * m[k];
    double tail = 0.0;
    for (std::size_t i = whole[k]; i < count; ++i) {
      const double d = c[i] - 2.0 * b[i] + x[i];
      tail += d * d;
    }
    const double* a = s[k];
    out[k] = ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7])) + tail;
  }
}

// Walks ms: `group(j)` for each group of kernel_group_at, `singles(j, k)`
// for each run ms[j .. j+k) of the factors left over.
template <class Group, class Singles>
void by_groups(std::span<const std::size_t> ms, Group group, Singles singles) {
  std::size_t j = 0;
  while (j < ms.size()) {
    if (kernel_group_at(ms, j)) {
      group(j);
      j += kGroup;
    } else {
      std::size_t k = j + 1;
      while (k < ms.size() && !kernel_group_at(ms, k)) ++k;
      singles(j, k - j);
      j = k;
    }
  }
}

// One call per factor of a run.
template <class Single>
auto each(Single single) {
  return [single](std::size_t j, std::size_t count) {
    for (std::size_t k = j; k < j + count; ++k) single(k);
  };
}

}  // namespace

void oavar(std::span<const double> x, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out) {
  const std::size_t N = x.size();
  by_groups(
      ms,
      [&](std::size_t j) {
        const std::size_t* m = ms.data() + j;
        const std::size_t big = *std::max_element(m, m + kGroup);
        if (N < 2 * big + 1) {
          for (std::size_t k = 0; k < kGroup; ++k) out[j + k] = oavar(x, m[k], tau0);
          return;
        }
        // Centres c = i + m in [m, N - m): the range common to the group,
        // then each factor's own ends.
        double sum[kGroup];
        centred_second_difference_energies(x.data() + big, N - 2 * big, m, sum);
        for (std::size_t k = 0; k < kGroup; ++k) {
          const std::size_t edge = big - m[k];
          if (edge > 0) {
            sum[k] += second_difference_energy(x.data(), edge, m[k]);
            sum[k] += second_difference_energy(x.data() + N - m[k] - edge - m[k], edge, m[k]);
          }
          const std::size_t n = N - 2 * m[k];
          const double tau = static_cast<double>(m[k]) * tau0;
          out[j + k] = {sum[k] / (2.0 * static_cast<double>(n) * tau * tau), n};
        }
      },
      [&](std::size_t j, std::size_t count) {
        // The factors that fit the record, kTiledFactors at a time.
        std::size_t fit[kTiledFactors];
        std::size_t at[kTiledFactors];
        std::size_t used = 0;
        const auto flush = [&] {
          double sum[kTiledFactors];
          second_difference_energies(x.data(), N, fit, used, sum);
          for (std::size_t k = 0; k < used; ++k) {
            const std::size_t n = N - 2 * fit[k];
            const double tau = static_cast<double>(fit[k]) * tau0;
            out[at[k]] = {sum[k] / (2.0 * static_cast<double>(n) * tau * tau), n};
          }
          used = 0;
        };
        for (std::size_t k = j; k < j + count; ++k) {
          if (ms[k] > kTiledMaxFactor || ms[k] == 0 || N < 2 * ms[k] + 1) {
            out[k] = oavar(x, ms[k], tau0);
            continue;
          }
          fit[used] = ms[k];
          at[used++] = k;
          if (used == kTiledFactors) flush();
        }
        if (used > 0) flush();
      });
}

void ohvar(std::span<const double> x, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out) {
  const std::size_t N = x.size();
  by_groups(
      ms,
      [&](std::size_t j) {
        const std::size_t* m = ms.data() + j;
        const std::size_t big = *std::max_element(m, m + kGroup);
        if (N < 3 * big + 1) {
          for (std::size_t k = 0; k < kGroup; ++k) out[j + k] = ohvar(x, m[k], tau0);
          return;
        }
        double sum[kGroup];
        const std::size_t common = N - 3 * big;
        third_difference_energies(x.data(), common, m, sum);
        for (std::size_t k = 0; k < kGroup; ++k) {
          const std::size_t n = N - 3 * m[k];
          sum[k] += third_difference_energy(x.data() + common, n - common, m[k]);
          const double tau = static_cast<double>(m[k]) * tau0;
          out[j + k] = {sum[k] / (6.0 * static_cast<double>(n) * tau * tau), n};
        }
      },
      each([&](std::size_t j) { out[j] = ohvar(x, ms[j], tau0); }));
}

void totvar(const TotvarExtension& e, std::span<const std::size_t> ms, double tau0, std::span<VarianceTerm> out) {
  const std::size_t N = e.n;
  by_groups(
      ms,
      [&](std::size_t j) {
        const std::size_t* m = ms.data() + j;
        const std::size_t big = *std::max_element(m, m + kGroup);
        if (N < 3 || big > N - 1) {
          for (std::size_t k = 0; k < kGroup; ++k) out[j + k] = totvar(e, m[k], tau0);
          return;
        }
        // Centres i = 1..N-2 of the extended record, the same for every m.
        const std::size_t n = N - 2;
        double sum[kGroup];
        centred_second_difference_energies(e.xs.data() + e.offset + 1, n, m, sum);
        for (std::size_t k = 0; k < kGroup; ++k) {
          const double tau = static_cast<double>(m[k]) * tau0;
          out[j + k] = {sum[k] / (2.0 * tau * tau * static_cast<double>(n)), n};
        }
      },
      each([&](std::size_t j) { out[j] = totvar(e, ms[j], tau0); }));
}

}  // namespace cubecal

// The kernels AllanTools' API exposes beyond Stable32's statistics.
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
