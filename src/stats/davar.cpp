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
//
// Missing samples (options.skip_missing, a record with NaN): whether a term
// needs a missing sample depends on the term alone, not on the window, so
// the blocks carry the sum of the whole terms and their count, slid alike
// (the counts exactly); a cell is the OADEV of dev --gaps skip
// (docs/formulas/stability.md §7a) on its window.
#include "cubecal/stats/davar.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "cubecal/error.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/gap_deviation.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"
#include "detail/difference_energy.hpp"

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
      f.whole[b] =
          has_head ? f.head[b - q] + second_difference_energy(x + r, S - r, m) : second_difference_energy(x, S, m);
  }
}

// Window sums from the block sums of one factor (q whole blocks and a head
// of r terms per window): the q whole blocks by prefix and suffix sums
// inside chunks of q blocks, plus the head. T: double for the sums of
// squares, std::size_t for the counts of whole terms (missing samples).
template <class T>
void window_sums(std::size_t q, std::size_t r, const std::vector<T>& head, const std::vector<T>& w, std::size_t K,
                 std::span<T> out) {
  if (q == 0) {  // a window is shorter than a step: its sum is one head
    for (std::size_t k = 0; k < K; ++k) out[k] = head[k];
    return;
  }
  const std::size_t nb = K + q - 1;
  std::vector<T> pre(nb), suf(nb);
  for (std::size_t b = 0; b < nb; ++b) pre[b] = (b % q == 0) ? w[b] : pre[b - 1] + w[b];
  for (std::size_t b = nb; b-- > 0;) {
    const bool last_in_chunk = (b % q == q - 1) || b + 1 == nb;
    suf[b] = last_in_chunk ? w[b] : w[b] + suf[b + 1];
  }
  for (std::size_t k = 0; k < K; ++k) {
    const std::size_t e = k + q - 1;  // last whole block of window k
    const T sum = (k % q == 0) ? pre[e] : suf[k] + pre[e];
    out[k] = r > 0 ? sum + head[k] : sum;
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
  for (std::size_t j = 0; j < ms.size(); ++j)
    window_sums(fs[j].q, fs[j].r, fs[j].head, fs[j].whole, K, out.subspan(j * K, K));
}

// A record with missing samples as phase points (scaled by `scale`, as the
// record without gaps): frequency data summed over the samples that are
// there (a missing sample adds nothing), phase data as given with NaN where
// a point is missing; and per input sample k the missing samples before it.
struct GappedRecord {
  std::vector<double> x;
  std::vector<std::size_t> missing_before;  // size N + 1
  bool frequency = false;
  double scale = 1.0;

  // Whether the term at phase point i of factor m needs no missing sample:
  // frequency, none of the 2m samples it spans; phase, its three points.
  bool whole(std::size_t i, std::size_t m) const noexcept {
    if (frequency) return missing_before[i] == missing_before[i + 2 * m];
    return !std::isnan(x[i]) && !std::isnan(x[i + m]) && !std::isnan(x[i + 2 * m]);
  }
  // Missing samples among the input samples [a, a + count).
  std::size_t missing_in(std::size_t a, std::size_t count) const noexcept {
    return missing_before[a + count] - missing_before[a];
  }
};

GappedRecord gapped_record(std::span<const double> data, DataType type, double tau0) {
  GappedRecord g;
  g.frequency = type == DataType::freq;
  const std::size_t N = data.size();
  double top = 0.0;
  for (std::size_t k = 0; k < N; ++k) {
    if (std::isinf(data[k])) throw std::invalid_argument("sample " + std::to_string(k) + " is not a finite number");
    if (!std::isnan(data[k])) top = std::max(top, std::abs(data[k]));
  }
  g.scale = top > 0.0 ? std::ldexp(1.0, std::ilogb(top)) : 1.0;  // as power_of_two_scale
  const double inv = 1.0 / g.scale;
  g.missing_before.assign(N + 1, 0);
  for (std::size_t k = 0; k < N; ++k) g.missing_before[k + 1] = g.missing_before[k] + (std::isnan(data[k]) ? 1 : 0);
  if (!g.frequency) {
    // Minus the first point that is there (normalize_phase's reason).
    const auto first = std::find_if(data.begin(), data.end(), [](double v) { return !std::isnan(v); });
    const double x0 = first == data.end() ? 0.0 : *first * inv;
    g.x.resize(N);
    for (std::size_t k = 0; k < N; ++k) g.x[k] = data[k] * inv - x0;  // NaN stays NaN
    return g;
  }
  // The mean of the samples that are there first (freq_to_phase's reason).
  double mean = 0.0;
  const std::size_t present = N - g.missing_before[N];
  for (const double v : data)
    if (!std::isnan(v)) mean += v * inv;
  if (present > 0) mean /= static_cast<double>(present);
  g.x.assign(N + 1, 0.0);
  double acc = 0.0;
  for (std::size_t k = 0; k < N; ++k) {
    if (!std::isnan(data[k])) acc += (data[k] * inv - mean) * tau0;
    g.x[k + 1] = acc;
  }
  return g;
}

// The sum of squares of the whole terms of factor m at phase points
// [i0, i0 + count), and their count (each term formed as the kernel forms it).
void whole_term_energy(const GappedRecord& g, std::size_t i0, std::size_t count, std::size_t m, double& energy,
                       std::size_t& terms) noexcept {
  const double* x = g.x.data();
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t i = i0; i < i0 + count; ++i) {
    if (!g.whole(i, m)) continue;
    const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    s += d * d;
    ++n;
  }
  energy = s;
  terms = n;
}

// fast_energies for a record with missing samples: the whole terms' sums of
// squares in `out` and their counts in `counts`, slid alike.
void fast_energies_gapped(const GappedRecord& g, std::size_t P, std::size_t S, std::size_t K,
                          std::span<const std::size_t> ms, std::span<double> out, std::span<std::size_t> counts) {
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const std::size_t m = ms[j];
    const std::size_t L = P - 2 * m, q = L / S, r = L % S;
    std::vector<double> head(r > 0 ? K : 0), whole(q > 0 ? K + q - 1 : 0);
    std::vector<std::size_t> head_n(head.size()), whole_n(whole.size());
    const std::size_t nb = K + q - 1, end = r > 0 ? K + q : K + q - 1;
    for (std::size_t b = 0; b < end; ++b) {
      const bool has_head = r > 0 && b >= q;
      double e = 0.0;
      std::size_t n = 0;
      if (has_head) {
        whole_term_energy(g, b * S, r, m, e, n);
        head[b - q] = e;
        head_n[b - q] = n;
      }
      if (q > 0 && b < nb) {
        double rest = 0.0;
        std::size_t rest_n = 0;
        whole_term_energy(g, b * S + (has_head ? r : 0), has_head ? S - r : S, m, rest, rest_n);
        whole[b] = has_head ? e + rest : rest;
        whole_n[b] = has_head ? n + rest_n : rest_n;
      }
    }
    window_sums(q, r, head, whole, K, out.subspan(j * K, K));
    window_sums(q, r, head_n, whole_n, K, counts.subspan(j * K, K));
  }
}

// The interval factors of one (alpha, m): EDF and the ratios lo/dev, hi/dev.
struct IntervalFactors {
  double edf = 0.0;
  Interval ratio;
  bool ready = false;
};

constexpr int kLowestAlpha = -2;  // lowest_alpha(Stat::oadev): the Allan family (docs/formulas/stability.md §4.1)
constexpr int kHighestAlpha = 2;

// The window, step and intervals asked for, checked against the record of N samples.
void check_davar_options(std::size_t N, DataType type, const DavarOptions& options) {
  const std::size_t W = options.window, S = options.step;
  const std::size_t min_window = type == DataType::freq ? 4 : 5;
  if (S == 0) throw UsageError(Field::step, "the step must be at least one sample");
  if (W < min_window)
    throw UsageError(Field::window, "a window of " + std::to_string(W) +
                                        " samples is too short: OADEV needs at least " + std::to_string(min_window) +
                                        (type == DataType::freq ? " frequency" : " phase") + " samples for m = 1");
  if (W > N)
    throw UsageError(Field::window, "a window of " + std::to_string(W) + " samples is longer than the record (" +
                                        std::to_string(N) + " samples)");
  const DavarIntervals& iv = options.intervals;
  if (iv.enabled && !(iv.ci > 0.0 && iv.ci < 1.0))
    throw UsageError(Field::ci, "the confidence must be between 0 and 1 (e.g. 0.683 or 0.95)");
  if (iv.enabled) check_noise_type(Stat::oadev, iv.alpha);  // the one rule of every statistic
}

// The matrix's axes: the windows' start and centre times, the factors'
// taus and term counts.
DavarMatrix davar_axes(std::size_t N, DataType type, double tau0, const DavarOptions& options, std::size_t P,
                       const std::vector<std::size_t>& ms, std::size_t missing) {
  const std::size_t W = options.window, S = options.step;
  DavarMatrix res;
  res.tau0 = tau0;
  res.type = type;
  res.samples = N;
  res.window = W;
  res.step = S;
  res.window_points = P;
  res.missing = missing;
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
  return res;
}

constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// The deviations of a record with missing samples: the whole terms of each
// cell (docs/formulas/stability.md §7a); a cell without one has no value.
void gapped_deviations(DavarMatrix& res, const GappedRecord& g, DavarMethod method, double scale) {
  const std::size_t P = res.window_points, S = res.step, K = res.start.size(), J = res.m.size();
  const std::vector<std::size_t>& ms = res.m;
  res.terms.assign(J * K, 0);
  if (method == DavarMethod::fast) {
    fast_energies_gapped(g, P, S, K, ms, res.dev, res.terms);
    for (std::size_t j = 0; j < J; ++j) {
      const double tau = res.tau[j];
      for (std::size_t k = 0; k < K; ++k) {
        const std::size_t c = res.cell(j, k);
        const double denom = 2.0 * static_cast<double>(res.terms[c]) * tau * tau;
        res.dev[c] = res.terms[c] > 0 ? std::sqrt(std::max(res.dev[c] / denom, 0.0)) * scale : kNoValue;
      }
    }
  } else {
    // The whole terms of every window summed anew, from the same phase
    // points as the fast method (as the direct method without gaps).
    for (std::size_t k = 0; k < K; ++k)
      for (std::size_t j = 0; j < J; ++j) {
        const std::size_t c = res.cell(j, k);
        double energy = 0.0;
        whole_term_energy(g, k * S, P - 2 * ms[j], ms[j], energy, res.terms[c]);
        const double tau = res.tau[j];
        const double denom = 2.0 * static_cast<double>(res.terms[c]) * tau * tau;
        res.dev[c] = res.terms[c] > 0 ? std::sqrt(std::max(energy / denom, 0.0)) * scale : kNoValue;
      }
  }
}

// The deviations of a record without missing samples, from its phase points xs.
void deviations(DavarMatrix& res, std::span<const double> xs, DavarMethod method, double scale) {
  const std::size_t P = res.window_points, S = res.step, K = res.start.size(), J = res.m.size();
  const std::vector<std::size_t>& ms = res.m;
  if (method == DavarMethod::fast) {
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
        const VarianceTerm v = oavar(xs.subspan(k * S, P), ms[j], res.tau0);
        res.dev[res.cell(j, k)] = std::sqrt(std::max(v.var, 0.0)) * scale;
      }
  }
}

// The EDF depends on (alpha, m, P) only, the same in every window: each is
// computed once, and the interval of a cell is its deviation times the
// ratios chi2_interval gives for a deviation of 1.
class IntervalFactorTable {
 public:
  IntervalFactorTable(const std::vector<std::size_t>& ms, std::size_t P, const DavarIntervals& iv)
      : ms_(ms), P_(P), iv_(iv), factors_(ms.size()) {}

  // A window without a missing sample.
  const IntervalFactors& whole(std::size_t j, int a) {
    IntervalFactors& f = factors_[j][static_cast<std::size_t>(a - kLowestAlpha)];
    if (!f.ready) {
      f.edf = edf_for(Stat::oadev, a, ms_[j], P_, iv_.edf);
      f.ratio = chi2_interval(1.0, f.edf, iv_.ci);
      f.ready = true;
    }
    return f;
  }

  // Windows with a missing sample: the EDF of a window without gaps giving
  // as many terms (per factor, type and count, once).
  const IntervalFactors& gapped(std::size_t j, int a, std::size_t terms) {
    IntervalFactors& f = gapped_factors_[{j, a, terms}];
    if (!f.ready) {
      f.edf = edf_for(Stat::oadev, a, ms_[j], terms + 2 * ms_[j], iv_.edf);
      f.ratio = chi2_interval(1.0, f.edf, iv_.ci);
      f.ready = true;
    }
    return f;
  }

 private:
  const std::vector<std::size_t>& ms_;
  std::size_t P_;
  const DavarIntervals& iv_;
  std::vector<std::array<IntervalFactors, kHighestAlpha - kLowestAlpha + 1>> factors_;
  std::map<std::tuple<std::size_t, int, std::size_t>, IntervalFactors> gapped_factors_;
};

// The intervals of window k with a missing sample: the noise type as dev
// --gaps skip identifies it on the window.
void gapped_window_intervals(DavarMatrix& res, std::size_t k, std::span<const double> data, const DavarIntervals& iv,
                             IntervalFactorTable& table) {
  const std::size_t S = res.step, W = res.window, J = res.m.size();
  const std::vector<std::size_t>& ms = res.m;
  std::vector<GapNoiseType> typed;
  if (!iv.alpha) {
    StabilityOptions so;
    so.ci = iv.ci;
    so.edf = iv.edf;
    typed = noise_types_skipping_missing(data.subspan(k * S, W), res.type, res.tau0, ms, so);
  }
  for (std::size_t j = 0; j < J; ++j) {
    const std::size_t c = res.cell(j, k);
    if (res.terms[c] == 0) {
      res.edf[c] = res.lo[c] = res.hi[c] = kNoValue;
      continue;
    }
    res.alpha[c] = iv.alpha ? *iv.alpha : typed[j].alpha;
    res.alpha_carried[c] = !iv.alpha && typed[j].carried;
    const IntervalFactors& f = table.gapped(j, res.alpha[c], res.terms[c]);
    res.edf[c] = f.edf;
    res.lo[c] = res.dev[c] * f.ratio.lo;
    res.hi[c] = res.dev[c] * f.ratio.hi;
  }
}

// The intervals of window k without a missing sample, from its phase points.
void window_intervals(DavarMatrix& res, std::size_t k, std::span<const double> xs, std::size_t top,
                      const DavarIntervals& iv, IntervalFactorTable& table) {
  const std::size_t S = res.step, P = res.window_points, J = res.m.size();
  const std::vector<std::size_t>& ms = res.m;
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
    const IntervalFactors& f = table.whole(j, res.alpha[c]);
    res.edf[c] = f.edf;
    res.lo[c] = res.dev[c] * f.ratio.lo;
    res.hi[c] = res.dev[c] * f.ratio.hi;
  }
}

// Every cell's interval, EDF and noise type.
void davar_intervals(DavarMatrix& res, std::span<const double> data, std::span<const double> xs,
                     const std::optional<GappedRecord>& gapped, std::size_t top, const DavarIntervals& iv) {
  const std::size_t S = res.step, W = res.window, K = res.start.size(), J = res.m.size();
  res.intervals = true;
  res.ci = iv.ci;
  res.edf_method = iv.edf;
  res.fixed_alpha = iv.alpha;
  res.lo.assign(J * K, 0.0);
  res.hi.assign(J * K, 0.0);
  res.edf.assign(J * K, 0.0);
  res.alpha.assign(J * K, 0);
  res.alpha_carried.assign(J * K, false);
  IntervalFactorTable table(res.m, res.window_points, iv);
  for (std::size_t k = 0; k < K; ++k) {
    if (gapped && gapped->missing_in(k * S, W) > 0)
      gapped_window_intervals(res, k, data, iv, table);
    else
      window_intervals(res, k, xs, top, iv, table);
  }
}

}  // namespace

DavarMatrix davar(std::span<const double> data, DataType type, double tau0, const DavarOptions& options) {
  if (!(tau0 > 0.0) || !std::isfinite(tau0))
    throw std::invalid_argument("davar: tau0 must be a positive finite number");
  const std::size_t N = data.size();
  const std::size_t W = options.window;
  check_davar_options(N, type, options);
  const DavarIntervals& iv = options.intervals;

  const std::size_t P = davar_window_points(W, type);
  const std::size_t top = max_averaging_factor(Stat::oadev, P);
  std::vector<std::size_t> ms = averaging_factors(options.grid, top, tau0);
  if (ms.empty())
    throw UsageError(Field::taus, "no tau of the grid fits a window of " + std::to_string(W) +
                                      " samples (OADEV evaluates m up to " + std::to_string(top) + ")");

  // Missing samples (skip_missing and a NaN in the record): the gapped
  // record; otherwise the phase record of every statistic.
  const std::size_t missing = options.skip_missing ? missing_samples(data) : 0;
  std::optional<GappedRecord> gapped;
  if (missing > 0) gapped.emplace(gapped_record(data, type, tau0));
  const double scale = gapped ? gapped->scale : power_of_two_scale(data);
  const std::vector<double> x = gapped                   ? std::vector<double>()
                                : type == DataType::freq ? freq_to_phase(data, tau0, scale)
                                                         : normalize_phase(data, scale);
  const std::span<const double> xs = gapped ? std::span<const double>(gapped->x) : std::span<const double>(x);

  DavarMatrix res = davar_axes(N, type, tau0, options, P, ms, missing);

  // Variances, then deviations (the OADEV of stats/kernels.cpp:
  // sum / (2 n tau^2), scaled back).
  res.dev.assign(res.m.size() * res.start.size(), 0.0);
  if (gapped)
    gapped_deviations(res, *gapped, options.method, scale);
  else
    deviations(res, xs, options.method, scale);

  if (!iv.enabled) return res;
  davar_intervals(res, data, xs, gapped, top, iv);
  return res;
}

}  // namespace cubecal
