// Dynamic Allan deviation (docs/formulas/davar.md). The record is turned into
// phase once (stats/phase.hpp, scaled by an exact power of two as every
// statistic here); window k covers the phase points [kS, kS + P) and its
// OADEV at m sums the squared second differences d_i = x[i+2m] - 2x[i+m] +
// x[i] for i in [kS, kS + L), L = P - 2m.
//
// The fast method (§3 of the page) never subtracts: the terms are summed once
// per block of S (the step), blocks cut at multiples of S, and a window's sum
// is q = L / S whole blocks plus the head (the first r = L % S terms) of the
// block after them. The sum of q consecutive block sums comes from prefix and
// suffix sums inside chunks of q blocks (van Herk; Gil & Werman): one suffix
// plus one prefix per window. Every operation adds non-negative numbers, so
// each window's sum carries the rounding of a sum of its own terms, whatever
// the length of the record or the levels the window slid past; a running sum
// that added the entering terms and subtracted the leaving ones would keep
// the absolute error of the largest sums it ever held (§4).
#include "cubecal/stats/davar.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"

namespace cubecal {

std::size_t davar_window_points(std::size_t window, DataType type) noexcept {
  return type == DataType::freq ? window + 1 : window;
}

std::size_t davar_window_count(std::size_t samples, std::size_t window, std::size_t step) noexcept {
  if (step == 0 || window == 0 || window > samples) return 0;
  return (samples - window) / step + 1;
}

namespace {

// The block sums of one averaging factor m: window k sums the terms
// [kS, kS + L), L = P - 2m, that is the q = L / S whole blocks k .. k + q - 1
// and the head (the first r = L % S terms) of block k + q.
struct FactorBlocks {
  std::size_t m = 0, q = 0, r = 0;
  std::vector<double> head;   // head[k]: block k + q's first r terms (r > 0)
  std::vector<double> whole;  // whole[b]: block b, b < K + q - 1 (q > 0)
  // Blocks whose sums this factor needs: heads of q .. K + q - 1, wholes of 0 .. K + q - 2.
  std::size_t end(std::size_t K) const noexcept { return r > 0 ? K + q : K + q - 1; }
};

// The head and whole sums of blocks [b0, b1) of factor f (the head of a
// block first: its whole sum adds the rest to it).
void sum_blocks(const double* p, std::size_t S, std::size_t K, FactorBlocks& f, std::size_t b0, std::size_t b1) {
  const std::size_t m = f.m, q = f.q, r = f.r, nb = K + q - 1;
  b1 = std::min(b1, f.end(K));
  for (std::size_t b = b0; b < b1; ++b) {
    const double* x = p + b * S;
    const bool has_head = r > 0 && b >= q;
    if (has_head) f.head[b - q] = second_difference_energy(x, r, m);
    if (q > 0 && b < nb)
      f.whole[b] = has_head ? f.head[b - q] + second_difference_energy(x + r, S - r, m)
                            : second_difference_energy(x, S, m);
  }
}

// Window sums of factor f from its block sums: the q whole blocks by prefix
// and suffix sums inside chunks of q blocks, plus the head.
void window_sums(const FactorBlocks& f, std::size_t K, std::span<double> out) {
  const std::size_t q = f.q;
  if (q == 0) {  // a window is shorter than a step: its sum is one head
    for (std::size_t k = 0; k < K; ++k) out[k] = f.head[k];
    return;
  }
  const std::size_t nb = K + q - 1;
  const std::vector<double>& w = f.whole;
  std::vector<double> pre(nb), suf(nb);
  for (std::size_t b = 0; b < nb; ++b) pre[b] = (b % q == 0) ? w[b] : pre[b - 1] + w[b];
  for (std::size_t b = nb; b-- > 0;) {
    const bool last_in_chunk = (b % q == q - 1) || b + 1 == nb;
    suf[b] = last_in_chunk ? w[b] : w[b] + suf[b + 1];
  }
  for (std::size_t k = 0; k < K; ++k) {
    const std::size_t e = k + q - 1;  // last whole block of window k
    const double sum = (k % q == 0) ? pre[e] : suf[k] + pre[e];
    out[k] = f.r > 0 ? sum + f.head[k] : sum;
  }
}

// Sums of the squared second differences of every window at every factor,
// out[j * K + k]. The block sums are taken a stretch of the record at a time
// for every factor (about 32 Ki phase points and the 2m beyond: in the
// processor's cache, read once from memory instead of once per factor).
void fast_energies(std::span<const double> x, std::size_t P, std::size_t S, std::size_t K,
                   std::span<const std::size_t> ms, std::span<double> out) {
  std::vector<FactorBlocks> fs(ms.size());
  std::size_t last = 0;
  for (std::size_t j = 0; j < ms.size(); ++j) {
    FactorBlocks& f = fs[j];
    f.m = ms[j];
    const std::size_t L = P - 2 * f.m;
    f.q = L / S;
    f.r = L % S;
    if (f.r > 0) f.head.resize(K);
    if (f.q > 0) f.whole.resize(K + f.q - 1);
    last = std::max(last, f.end(K));
  }
  constexpr std::size_t kStretch = 32768;  // phase points per stretch
  const std::size_t per = std::max<std::size_t>(1, kStretch / S);
  for (std::size_t b0 = 0; b0 < last; b0 += per)
    for (FactorBlocks& f : fs) sum_blocks(x.data(), S, K, f, b0, b0 + per);
  for (std::size_t j = 0; j < ms.size(); ++j) window_sums(fs[j], K, out.subspan(j * K, K));
}

// The interval factors of one (alpha, m): EDF and the ratios lo/dev, hi/dev.
struct IntervalFactors {
  double edf = 0.0;
  Interval ratio;
  bool ready = false;
};

constexpr int kLowestAlpha = -2;  // the Allan family (docs/formulas/stability.md §4.1)
constexpr int kHighestAlpha = 2;

}  // namespace

DavarMatrix davar(std::span<const double> data, DataType type, double tau0, const DavarOptions& options) {
  if (!(tau0 > 0.0) || !std::isfinite(tau0)) throw std::invalid_argument("davar: tau0 must be a positive finite number");
  const std::size_t N = data.size();
  const std::size_t W = options.window, S = options.step;
  const std::size_t min_window = type == DataType::freq ? 4 : 5;
  if (S == 0) throw UsageError("step", "the step must be at least one sample");
  if (W < min_window)
    throw UsageError("window", "a window of " + std::to_string(W) + " samples is too short: OADEV needs at least " +
                                   std::to_string(min_window) + (type == DataType::freq ? " frequency" : " phase") +
                                   " samples for m = 1");
  if (W > N)
    throw UsageError("window", "a window of " + std::to_string(W) + " samples is longer than the record (" +
                                   std::to_string(N) + " samples)");
  const DavarIntervals& iv = options.intervals;
  if (iv.enabled && !(iv.ci > 0.0 && iv.ci < 1.0))
    throw UsageError("ci", "the confidence must be between 0 and 1 (e.g. 0.683 or 0.95)");
  if (iv.enabled && iv.alpha && (*iv.alpha < kLowestAlpha || *iv.alpha > kHighestAlpha))
    throw UsageError("alpha", "the noise type of an Allan deviation is one of +2 (WPM), +1 (FPM), 0 (WFM), "
                              "-1 (FFM), -2 (RWFM); got " + std::to_string(*iv.alpha));

  const std::size_t P = davar_window_points(W, type);
  const std::size_t top = max_averaging_factor(Stat::oadev, P);
  std::vector<std::size_t> ms = averaging_factors(options.grid, top, tau0);
  if (ms.empty())
    throw UsageError("taus", "no tau of the grid fits a window of " + std::to_string(W) +
                                 " samples (OADEV evaluates m up to " + std::to_string(top) + ")");

  const double scale = power_of_two_scale(data);
  const std::vector<double> x = type == DataType::freq ? freq_to_phase(data, tau0, scale) : normalize_phase(data, scale);
  const std::span<const double> xs(x);

  DavarMatrix res;
  res.tau0 = tau0;
  res.type = type;
  res.samples = N;
  res.window = W;
  res.step = S;
  res.window_points = P;
  const std::size_t K = davar_window_count(N, W, S);
  res.start.resize(K);
  res.centre.resize(K);
  for (std::size_t k = 0; k < K; ++k) {
    const double a = static_cast<double>(k * S);
    res.start[k] = a * tau0;
    res.centre[k] = (a + 0.5 * static_cast<double>(P - 1)) * tau0;
  }
  const std::size_t J = ms.size();
  res.m = ms;
  res.tau.resize(J);
  res.n.resize(J);
  for (std::size_t j = 0; j < J; ++j) {
    res.tau[j] = static_cast<double>(ms[j]) * tau0;
    res.n[j] = P - 2 * ms[j];
  }

  // Variances, then deviations (the OADEV of stats/kernels.cpp:
  // sum / (2 n tau^2), scaled back).
  res.dev.assign(J * K, 0.0);
  if (options.method == DavarMethod::fast) {
    fast_energies(xs, P, S, K, ms, res.dev);  // sums first, deviations in place
    for (std::size_t j = 0; j < J; ++j) {
      const double tau = res.tau[j];
      const double denom = 2.0 * static_cast<double>(res.n[j]) * tau * tau;
      for (std::size_t k = 0; k < K; ++k) {
        double& c = res.dev[res.cell(j, k)];
        c = std::sqrt(std::max(c / denom, 0.0)) * scale;
      }
    }
  } else {
    // One factor at a time: the single-factor kernel forms each second
    // difference as the fast method does, so the two differ only in how the
    // terms are summed. (The grouped kernel of a dense grid forms them in
    // another order, which moves each by the rounding of the phase values,
    // eps |x|, not of the sum: docs/formulas/davar.md §4.)
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t j = 0; j < J; ++j) {
        const VarianceTerm v = oavar(xs.subspan(k * S, P), ms[j], tau0);
        res.dev[res.cell(j, k)] = std::sqrt(std::max(v.var, 0.0)) * scale;
      }
  }

  if (!iv.enabled) return res;
  res.intervals = true;
  res.ci = iv.ci;
  res.edf_method = iv.edf;
  res.fixed_alpha = iv.alpha;
  res.lo.assign(J * K, 0.0);
  res.hi.assign(J * K, 0.0);
  res.edf.assign(J * K, 0.0);
  res.alpha.assign(J * K, 0);
  res.alpha_carried.assign(J * K, false);
  // The EDF depends on (alpha, m, P) only, the same in every window: each is
  // computed once, and the interval of a cell is its deviation times the
  // ratios chi2_interval gives for a deviation of 1.
  std::vector<std::array<IntervalFactors, kHighestAlpha - kLowestAlpha + 1>> factors(J);
  auto factor = [&](std::size_t j, int a) -> const IntervalFactors& {
    IntervalFactors& f = factors[j][static_cast<std::size_t>(a - kLowestAlpha)];
    if (!f.ready) {
      f.edf = edf_for(Stat::oadev, a, ms[j], P, iv.edf);
      f.ratio = chi2_interval(1.0, f.edf, iv.ci);
      f.ready = true;
    }
    return f;
  };
  for (std::size_t k = 0; k < K; ++k) {
    const std::span<const double> win = xs.subspan(k * S, P);
    for (std::size_t j = 0; j < J; ++j) {
      const std::size_t c = res.cell(j, k);
      if (iv.alpha) {
        res.alpha[c] = *iv.alpha;
      } else if (j > 0 && 2 * ms[j] > top) {  // the run rule (docs/formulas/stability.md §4.5)
        res.alpha[c] = res.alpha[res.cell(j - 1, k)];
        res.alpha_carried[c] = true;
      } else {
        res.alpha[c] = identify_noise(win, ms[j], Stat::oadev).alpha;
      }
      const IntervalFactors& f = factor(j, res.alpha[c]);
      res.edf[c] = f.edf;
      res.lo[c] = res.dev[c] * f.ratio.lo;
      res.hi[c] = res.dev[c] * f.ratio.hi;
    }
  }
  return res;
}

}  // namespace cubecal
