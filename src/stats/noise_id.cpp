// Power-law noise identification (Riley, "Handbook of Frequency Stability
// Analysis", NIST SP 1065 sec. 5.6; Riley & Greenhall, EFTF 2004).
//
// Lag-1 ACF method: take the data at the averaging factor (phase decimated,
// frequency averaged), remove the deterministic part, and difference until
// delta = r1/(1+r1) < 0.25 or the maximum order (2 for Allan, 3 for
// Hadamard statistics) is reached; then alpha = -round(2 delta) - 2d (+2 for
// phase). Fewer than 30 points: Barnes' B1 ratio (N-sample over 2-sample
// variance) against its expected value for each noise type, with the
// MVAR/AVAR ratio R(n) separating white from flicker PM for the modified
// statistics.
#include "cubecal/stats/noise_id.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "cubecal/stats/kernels.hpp"
#include "../detail/simd.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMinAcfPoints = 30;

// Running sums of one difference order of the sequence, enough for its
// lag-1 autocorrelation with the mean removed.
struct LagSums {
  std::size_t n = 0;
  double s1 = 0, s2 = 0, p = 0, first = 0, last = 0;
  double r1() const {
    if (n < 2) return 0.0;
    const double nn = static_cast<double>(n);
    const double mu = s1 / nn;
    const double den = s2 - nn * mu * mu;
    const double num = p - mu * (2.0 * s1 - first - last) + (nn - 1.0) * mu * mu;
    return den > 0.0 ? num / den : 0.0;
  }
};

// Adds w[0..len) to the sums; independent partial sums let the loops run
// vectorized (this runs on every averaging factor, over up to N points).
CUBECAL_VECTOR_CLONES
void accumulate(LagSums& s, const double* w, std::size_t len) {
  if (len == 0) return;
  if (s.n > 0) s.p += s.last * w[0];
  else s.first = w[0];
  // 16 lanes = four AVX2 registers per sum: enough independent chains to
  // hide the add latency.
  constexpr std::size_t L = 16;
  double a1[L] = {}, a2[L] = {}, ap[L] = {};
  std::size_t i = 0;
  for (; i + L + 1 <= len; i += L)
    for (std::size_t j = 0; j < L; ++j) {
      const double v = w[i + j];
      a1[j] += v;
      a2[j] += v * v;
      ap[j] += v * w[i + j + 1];
    }
  double t1 = 0, t2 = 0, tp = 0;
  for (; i < len; ++i) {
    t1 += w[i];
    t2 += w[i] * w[i];
    if (i + 1 < len) tp += w[i] * w[i + 1];
  }
  for (std::size_t j = 0; j < L; ++j) {
    t1 += a1[j];
    t2 += a2[j];
    tp += ap[j];
  }
  s.s1 += t1;
  s.s2 += t2;
  s.p += tp;
  s.last = w[len - 1];
  s.n += len;
}

// Frequency averaged over m samples, from the phase record: (x[(k+1)m] - x[km]).
// The 1/(m tau0) scale is left out; the ratios below do not depend on it.
std::vector<double> averaged_frequency(std::span<const double> x, std::size_t m) {
  const std::size_t count = (x.size() - 1) / m;
  std::vector<double> y(count);
  for (std::size_t k = 0; k < count; ++k) y[k] = x[(k + 1) * m] - x[k * m];
  return y;
}

int clamp_alpha(int alpha, Stat stat) {
  const int lowest = difference_order(stat) == 3 ? -4 : -2;
  return std::clamp(alpha, lowest, 2);
}

// Expected B1 for N averaged frequency points and phase-noise exponent mu
// (Howe, Beard, Greenhall, Riley, PTTI 2000, Table 3).
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

int alpha_from_mu(int mu) {
  // mu = -alpha - 1 for -4 <= alpha <= 0; white and flicker PM share mu = -2.
  return mu == -2 ? 2 : -mu - 1;
}

}  // namespace

double lag1_autocorrelation(std::span<const double> z) noexcept {
  const std::size_t n = z.size();
  if (n < 2) return 0.0;
  double mean = 0.0;
  for (double v : z) mean += v;
  mean /= static_cast<double>(n);
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = z[i] - mean;
    den += a * a;
    if (i + 1 < n) num += a * (z[i + 1] - mean);
  }
  return den > 0.0 ? num / den : 0.0;
}

namespace {

NoiseId identify_at(std::span<const double> x, std::size_t m, DataType original, Stat stat) {
  NoiseId out;
  if (m == 0 || x.size() < m + 1) return out;
  const int dmax = difference_order(stat);

  // The data at this averaging factor: decimated phase, or frequency
  // averaged over m samples (from phase differences).
  const bool phase = original == DataType::phase;
  const std::size_t count = phase ? (x.size() - 1) / m + 1 : (x.size() - 1) / m;
  auto z = [&](std::size_t k) { return phase ? x[k * m] : x[(k + 1) * m] - x[k * m]; };

  if (count >= kMinAcfPoints) {
    // Phase: remove the least-squares line first (a frequency offset); the
    // mean is removed inside the autocorrelation for every order.
    double a = 0.0, b = 0.0;
    if (phase) {
      const double tc = (static_cast<double>(count) - 1.0) / 2.0;
      double sz = 0.0, stz = 0.0, stt = 0.0;
      for (std::size_t k = 0; k < count; ++k) {
        const double t = static_cast<double>(k) - tc;
        const double v = z(k);
        sz += v;
        stz += t * v;
        stt += t * t;
      }
      a = sz / static_cast<double>(count);
      b = stz / stt;
      a -= b * tc;
    }
    // One pass accumulates the sums of every difference order 0..dmax,
    // block by block. buf[d][0] carries the last value of the previous block.
    constexpr std::size_t kBlock = 1024;
    static_assert(kBlock > 3);
    LagSums sums[4];
    std::vector<double> storage(4 * (kBlock + 1), 0.0);
    double* buf[4] = {storage.data(), storage.data() + (kBlock + 1),
                      storage.data() + 2 * (kBlock + 1), storage.data() + 3 * (kBlock + 1)};
    for (std::size_t k0 = 0; k0 < count; k0 += kBlock) {
      const std::size_t len = std::min(kBlock, count - k0);
      double* w0 = buf[0] + 1;
      if (phase) {
        for (std::size_t j = 0; j < len; ++j)
          w0[j] = x[(k0 + j) * m] - (a + b * static_cast<double>(k0 + j));
      } else if (m == 1) {
        const double* xs = x.data() + k0;
        for (std::size_t j = 0; j < len; ++j) w0[j] = xs[j + 1] - xs[j];
      } else {
        for (std::size_t j = 0; j < len; ++j) w0[j] = z(k0 + j);
      }
      accumulate(sums[0], w0, len);
      for (int d = 1; d <= dmax; ++d) {
        const double* src = buf[d - 1];
        double* dst = buf[d] + 1;
        for (std::size_t j = 0; j < len; ++j) dst[j] = src[j + 1] - src[j];
        // The d-th difference starts at index d of the sequence.
        const std::size_t start = k0 == 0 ? static_cast<std::size_t>(d) : 0;
        if (len > start) accumulate(sums[d], dst + start, len - start);
      }
      for (int d = 0; d <= dmax; ++d) buf[d][0] = buf[d][len];
    }
    for (int d = 0;; ++d) {
      const double r1 = sums[d].r1();
      const double delta = r1 / (1.0 + r1);
      if (delta < 0.25 || d >= dmax) {
        const int shift = phase ? 2 : 0;
        out.alpha_est = -2.0 * (delta + d) + shift;
        out.alpha = clamp_alpha(static_cast<int>(-std::lround(2.0 * delta)) - 2 * d + shift, stat);
        out.method = NoiseId::Method::acf;
        return out;
      }
    }
  }

  // B1 ratio on the averaged frequency.
  const std::vector<double> y = averaged_frequency(x, m);
  const std::size_t nf = y.size();
  out.method = NoiseId::Method::b1;
  if (nf < 2) return out;
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(nf);
  double svar = 0.0, avar2 = 0.0;
  for (std::size_t i = 0; i < nf; ++i) svar += (y[i] - mean) * (y[i] - mean);
  svar /= static_cast<double>(nf - 1);
  for (std::size_t i = 0; i + 1 < nf; ++i) avar2 += (y[i + 1] - y[i]) * (y[i + 1] - y[i]);
  avar2 /= 2.0 * static_cast<double>(nf - 1);
  if (!(avar2 > 0.0)) return out;
  const double b1 = svar / avar2;
  const double N = static_cast<double>(nf);

  int mu = -2;
  for (int cand = 2; cand > -2; --cand) {
    const double hi = b1_expected(N, cand);
    const double lo = b1_expected(N, cand - 1);
    const double boundary = cand == 2 ? 0.5 * (hi + lo) : std::sqrt(hi * lo);
    if (b1 > boundary) {
      mu = cand;
      break;
    }
  }
  out.alpha = clamp_alpha(alpha_from_mu(mu), stat);

  if (mu == -2 && (stat == Stat::mdev || stat == Stat::tdev)) {
    // R(n) = MVAR/AVAR: 1/m for white PM, 3.37/(1.04 + 3 ln(pi m)) for flicker PM.
    const VarianceTerm mv = mvar(x, m, 1.0);
    const VarianceTerm av = oavar(x, m, 1.0);
    if (mv.n > 0 && av.n > 0 && av.var > 0.0) {
      const double rn = mv.var / av.var;
      const double md = static_cast<double>(m);
      const double r_fpm = 3.37 / (1.04 + 3.0 * std::log(std::numbers::pi * md));
      const double r_wpm = 1.0 / md;
      out.alpha = rn > std::sqrt(r_fpm * r_wpm) ? 1 : 2;
      out.method = NoiseId::Method::b1_rn;
    }
  }
  return out;
}

}  // namespace

NoiseId identify_noise(std::span<const double> x, std::size_t m, DataType original, Stat stat) {
  NoiseId out = identify_at(x, m, original, stat);
  if (out.method == NoiseId::Method::acf || m == 0 || x.size() < 2) return out;
  // A B1 ratio from fewer than 30 averages scatters widely, and taking a
  // random walk for white PM there gives an EDF of the record length and an
  // interval a hundred times too narrow. The lag-1 ACF at the largest
  // averaging factor that still has 30 points is trusted instead as a bound:
  // the noise at longer tau is taken no whiter than it. (This also agrees
  // with Stable32 on more of its short-series rows than the B1 ratio alone.)
  const bool phase = original == DataType::phase;
  const std::size_t intervals = x.size() - 1;
  const std::size_t m_ref = phase ? intervals / (kMinAcfPoints - 1) : intervals / kMinAcfPoints;
  if (m_ref == 0 || m_ref >= m) return out;
  const NoiseId ref = identify_at(x, m_ref, original, stat);
  if (ref.method == NoiseId::Method::acf && ref.alpha < out.alpha) {
    out.alpha = ref.alpha;
    out.method = NoiseId::Method::b1_bounded;
  }
  return out;
}

}  // namespace cubecal
