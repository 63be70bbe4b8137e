#include "cubecal/stats/streaming_deviation.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "../detail/simd.hpp"
#include "detail/difference_energy.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMinAcfAverages = 30;  // as identify_noise
constexpr std::size_t kMinBlock = 4096;      // values a level takes per pass at least
constexpr std::size_t kTile = 1024;          // starts of overlapping terms per tile
constexpr std::size_t kZBlock = 2048;        // non-overlapping window sums per block

bool overlapping(Stat s) noexcept { return s == Stat::oadev || s == Stat::ohdev; }

// Level-0 copy less the offset; false when a value is not finite.
CUBECAL_VECTOR_CLONES
bool shift(const double* y, std::size_t count, double offset, double* out) noexcept {
  bool ok = true;
  for (std::size_t i = 0; i < count; ++i) {
    ok &= std::abs(y[i]) <= std::numeric_limits<double>::max();
    out[i] = y[i] - offset;
  }
  return ok;
}

// Sum of x[0 .. n): eight independent add chains (the loop runs
// vectorized instead of waiting on one chain's latency).
CUBECAL_VECTOR_CLONES
double sum_of(const double* x, std::size_t n) noexcept {
  double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (std::size_t j = 0; j < 8; ++j) s[j] += x[i + j];
  double tail = 0.0;
  for (; i < n; ++i) tail += x[i];
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail;
}

// The local prefix sums of a pass, cut into kSegments segments: their
// sums first (vectorized; their total gives the mean c), then the
// segments' prefix sums run interleaved, each from the sum of those before
// it (that many independent add chains instead of one).
constexpr std::size_t kSegments = 8;

struct CentredPrefix {
  double c = 0.0;
  double start[kSegments + 1] = {};  // P at each segment's start
};

CentredPrefix centre(const double* x, std::size_t n) noexcept {
  CentredPrefix r;
  const std::size_t q = n / kSegments;
  double seg[kSegments];
  double total = 0.0;
  for (std::size_t s = 0; s < kSegments; ++s) {
    const std::size_t end = s + 1 < kSegments ? (s + 1) * q : n;
    seg[s] = sum_of(x + s * q, end - s * q);
    total += seg[s];
  }
  r.c = total / static_cast<double>(n);
  for (std::size_t s = 0; s < kSegments; ++s) {
    const std::size_t end = s + 1 < kSegments ? (s + 1) * q : n;
    r.start[s + 1] = r.start[s] + (seg[s] - static_cast<double>(end - s * q) * r.c);
  }
  return r;
}

// P[j + 1] = P[0] + (x[0] - c) + .. + (x[j] - c), P[0] given.
void centred_prefix(const double* x, std::size_t n, const CentredPrefix& cp, double* P) noexcept {
  const double c = cp.c;
  const std::size_t q = n / kSegments;
  double acc[kSegments];
  for (std::size_t s = 0; s < kSegments; ++s) acc[s] = P[0] + cp.start[s];
  for (std::size_t i = 0; i < q; ++i)
    for (std::size_t s = 0; s < kSegments; ++s) {
      acc[s] += x[s * q + i] - c;
      P[s * q + i + 1] = acc[s];
    }
  // The remainder continues the last segment.
  double last = acc[kSegments - 1];
  for (std::size_t j = kSegments * q; j < n; ++j) {
    last += x[j] - c;
    P[j + 1] = last;
  }
}

// P[j + 1] = kept[j] - (j + 1) dc for j < n: the prefix sums kept from
// the pass before, taken about its mean, moved to this pass's mean (dc the
// change).
CUBECAL_VECTOR_CLONES
void recentre(const double* kept, std::size_t n, double dc, double* P) noexcept {
  // A 32-bit index converts to double in vector registers (a span is far
  // below 2^31).
  if (n < (std::size_t{1} << 31)) {
    const auto m = static_cast<std::int32_t>(n);
    for (std::int32_t j = 0; j < m; ++j) P[j + 1] = kept[j] - static_cast<double>(j + 1) * dc;
  } else {
    for (std::size_t j = 0; j < n; ++j) P[j + 1] = kept[j] - static_cast<double>(j + 1) * dc;
  }
}

// out[j] = P[j + 1] - P[0] for j < n: prefix sums to keep, from 0.
CUBECAL_VECTOR_CLONES
void rebase(const double* P, std::size_t n, double* out) noexcept {
  const double p0 = P[0];
  for (std::size_t j = 0; j < n; ++j) out[j] = P[j + 1] - p0;
}

// o[i] = x[2i] + x[2i + 1] for i < n.
CUBECAL_VECTOR_CLONES
void pair_sums(const double* x, std::size_t n, double* o) noexcept {
  for (std::size_t i = 0; i < n; ++i) o[i] = x[2 * i] + x[2 * i + 1];
}

// d[i] = z[i + 1] - z[i] for i < n - 1.
CUBECAL_VECTOR_CLONES
void adjacent_differences(const double* z, std::size_t n, double* d) noexcept {
  for (std::size_t i = 0; i + 1 < n; ++i) d[i] = z[i + 1] - z[i];
}

// z[i] = (P[b0 + (i + 1) k] - P[b0 + i k]) + k c: the window sums of the
// values behind P, the pass mean restored.
CUBECAL_VECTOR_CLONES
void window_sums(const double* P, std::size_t b0, std::size_t k, std::size_t n, double kc, double* z) noexcept {
  if (k == 1) {
    for (std::size_t i = 0; i < n; ++i) z[i] = (P[b0 + i + 1] - P[b0 + i]) + kc;
  } else {
    for (std::size_t i = 0; i < n; ++i) z[i] = (P[b0 + (i + 1) * k] - P[b0 + i * k]) + kc;
  }
}

// The overlapping terms of a pass over a level's len values (prefix sums
// P): each factor's new terms, those whose last prefix index is past the
// processed part, summed into its energy. (Level and Factor are
// StreamingDeviation's: deduced, as they are its own.)
template <class Level, class Factor>
void add_overlapping_energies(const Level& lv, std::vector<Factor>& state, const double* P, std::size_t len,
                              int order) {
  // New terms: those whose last prefix index is past the processed part,
  // starts first .. last of each factor. Taken in tiles of kTile starts,
  // every factor of the level on one tile before the next: the prefix
  // values a tile reads (near kTile starts and at +k, +2k, .. of each
  // factor, and the octave grid shares these) stay in the cache.
  std::size_t lo_all = len, hi_all = 0;
  for (std::size_t idx : lv.factors) {
    Factor& f = state[idx];
    const std::size_t span = static_cast<std::size_t>(order) * f.k;
    f.pass_energy = 0.0;
    f.first = 1;
    f.last = 0;
    if (len < span) continue;
    f.first = lv.kept + 1 > span ? lv.kept + 1 - span : 0;
    f.last = len - span;
    if (f.last < f.first) continue;
    lo_all = std::min(lo_all, f.first);
    hi_all = std::max(hi_all, f.last + 1);
  }
  for (std::size_t t0 = lo_all; t0 < hi_all; t0 += kTile) {
    const std::size_t t1 = std::min(hi_all, t0 + kTile);
    for (std::size_t idx : lv.factors) {
      Factor& f = state[idx];
      const std::size_t from = std::max(t0, f.first), to = std::min(t1, f.last + 1);
      if (f.last < f.first || from >= to) continue;
      f.pass_energy += order == 2 ? second_difference_energy(P + from, to - from, f.k)
                                  : third_difference_energy(P + from, to - from, f.k);
    }
  }
  for (std::size_t idx : lv.factors) {
    Factor& f = state[idx];
    if (f.last < f.first) continue;
    // Kahan: the record's sum over many passes.
    const double yk = f.pass_energy - f.energy_c;
    const double t = f.energy + yk;
    f.energy_c = (t - f.energy) - yk;
    f.energy = t;
    f.terms += f.last - f.first + 1;
  }
}

// Pair sums of a pass over a level's len values for the next level,
// aligned on even indices of this one: lv.out[0 .. out_n).
template <class Level>
void pair_sums_for_next(Level& lv, std::size_t len) {
  lv.out_n = 0;
  std::size_t j = lv.kept;
  if (lv.out.size() < (len - j) / 2 + 1) lv.out.resize((len - j) / 2 + 1);
  if (lv.odd && j < len) {
    lv.out[lv.out_n++] = lv.pending + lv.buf[j];
    lv.odd = false;
    ++j;
  }
  const std::size_t pairs = (len - j) / 2;
  pair_sums(lv.buf.data() + j, pairs, lv.out.data() + lv.out_n);
  lv.out_n += pairs;
  j += 2 * pairs;
  if (j < len) {
    lv.odd = true;
    lv.pending = lv.buf[j];
  }
}

}  // namespace

bool streams(Stat stat) noexcept {
  return stat == Stat::adev || stat == Stat::oadev || stat == Stat::hdev || stat == Stat::ohdev;
}

std::vector<StreamedFactor> streamed_factors(Stat stat, std::span<const std::size_t> ms, std::size_t window_bound) {
  const std::size_t order = static_cast<std::size_t>(difference_order(stat));
  // The values a factor's terms span on its level: order windows for the
  // overlapping statistics, one window (the averages) for the others.
  const std::size_t per_k = overlapping(stat) ? order : 1;
  std::vector<StreamedFactor> out;
  for (std::size_t m : ms) {
    if (m == 0) continue;
    StreamedFactor f;
    std::size_t level = 0;
    std::size_t k = m;
    while (k * per_k > window_bound) {
      ++level;
      const std::size_t unit = std::size_t{1} << level;
      k = std::max<std::size_t>(1, (m + unit / 2) >> level);  // nearest multiple of 2^level
    }
    f.level = level;
    f.m = k << level;
    f.stride = overlapping(stat) ? (std::size_t{1} << level) : f.m;
    if (!out.empty() && out.back().m >= f.m) continue;  // merged with the one before
    out.push_back(f);
  }
  return out;
}

std::size_t streaming_bytes(std::size_t window_bound) noexcept {
  // A full level holds its span plus a pass (two bounds) and its pair sums;
  // levels above 2^40 / bound receive fewer values than that.
  const std::size_t full_levels = 41 - static_cast<std::size_t>(std::countr_zero(window_bound));
  return (full_levels * 3 + 4) * window_bound * sizeof(double);
}

void StreamingDeviation::Factor::push_averages(double* z, std::size_t count, int dmax, double* scratch) noexcept {
  averages += count;
  for (int d = 0; d <= dmax && count > 0; ++d) {
    Lag& l = lag[d];
    const bool had = l.n > 0;
    const double before = l.last;
    l.add(z, count);
    if (d == dmax) break;
    // The next order: differences, the first against the last value before.
    std::size_t at = 0;
    if (had) scratch[at++] = z[0] - before;
    adjacent_differences(z, count, scratch + at);
    count = at + count - 1;
    std::swap(z, scratch);
  }
}

StreamingDeviation::StreamingDeviation(Stat stat, std::span<const std::size_t> ms, std::size_t window_bound)
    : stat_(stat), order_(difference_order(stat)), overlapping_(overlapping(stat)) {
  if (!streams(stat)) throw std::invalid_argument(std::string(to_string(stat)) + " is not computed in a stream");
  if (window_bound < 16 || (window_bound & (window_bound - 1)) != 0)
    throw std::invalid_argument("the window bound must be a power of two of at least 16");
  factors_ = streamed_factors(stat, ms, window_bound);
  state_.resize(factors_.size());
  std::size_t top = 0;
  for (const auto& f : factors_) top = std::max(top, f.level);
  levels_.resize(factors_.empty() ? 1 : top + 1);
  const std::size_t per_k = overlapping_ ? static_cast<std::size_t>(order_) : 1;
  for (std::size_t j = 0; j < factors_.size(); ++j) {
    Level& lv = levels_[factors_[j].level];
    state_[j].k = factors_[j].m >> factors_[j].level;
    lv.factors.push_back(j);
    lv.span = std::max(lv.span, per_k * state_[j].k);
  }
  for (Level& lv : levels_) lv.capacity = lv.span + std::max(lv.span, kMinBlock);
}

// A level's buffer grows to its capacity as values come: the top levels of
// a short record stay small.
void StreamingDeviation::grow(Level& lv, std::size_t need) {
  if (lv.buf.size() >= need) return;
  lv.buf.resize(std::min(lv.capacity, std::max(need, 2 * lv.buf.size())));
}

void StreamingDeviation::push(std::span<const double> y) {
  if (y.empty()) return;
  if (!have_offset_) {
    // A constant offset leaves every difference as it is; removing about the
    // mean keeps the window sums (and their rounding) at the size of the noise.
    const std::size_t n = std::min<std::size_t>(y.size(), 1 << 16);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += y[i];
    offset_ = std::isfinite(sum) ? sum / static_cast<double>(n) : 0.0;
    have_offset_ = true;
  }
  Level& lv = levels_[0];
  std::size_t done = 0;
  while (done < y.size()) {
    const std::size_t room = lv.capacity - lv.fill;
    const std::size_t take = std::min(room, y.size() - done);
    grow(lv, lv.fill + take);
    const std::size_t at = lv.fill;
    lv.fill += take;
    if (!shift(y.data() + done, take, offset_, lv.buf.data() + at)) {
      for (std::size_t i = 0; i < take; ++i)
        if (!std::isfinite(y[done + i]))
          throw std::invalid_argument("sample " + std::to_string(samples_ + done + i) + " is not a finite number");
    }
    done += take;
    lv.total += take;
    if (lv.fill == lv.capacity) process(0);
  }
  samples_ += y.size();
}

void StreamingDeviation::append(std::size_t level, const double* v, std::size_t count) {
  Level& lv = levels_[level];
  std::size_t done = 0;
  while (done < count) {
    const std::size_t take = std::min(lv.capacity - lv.fill, count - done);
    grow(lv, lv.fill + take);
    std::copy(v + done, v + done + take, lv.buf.begin() + static_cast<std::ptrdiff_t>(lv.fill));
    lv.fill += take;
    done += take;
    lv.total += take;
    if (lv.fill == lv.capacity) process(level);
  }
}

void StreamingDeviation::process(std::size_t level) {
  Level& lv = levels_[level];
  const std::size_t len = lv.fill;
  if (len == lv.kept) return;
  // Local prefix sums of the pass less a mean c: P[j] = (v[0] - c) + .. +
  // (v[j-1] - c) over the level's values v of the pass. Each term is a
  // difference of equal windows of the pass, so c cancels in it, and P
  // stays at the size of the noise: no phase is summed over the record.
  // The span kept from the pass before holds its prefix sums (from 0, about
  // that pass's mean), not its values: they are moved to the mean c of the
  // new values, and the new ones continue from there.
  const std::size_t kept = lv.kept;
  const CentredPrefix cp = centre(lv.buf.data() + kept, len - kept);
  const double c = cp.c;
  if (prefix_.size() < len + 1) prefix_.resize(len + 1);
  prefix_[0] = 0.0;
  recentre(lv.buf.data(), kept, c - lv.mean, prefix_.data());
  centred_prefix(lv.buf.data() + kept, len - kept, cp, prefix_.data() + kept);
  const double* P = prefix_.data();
  if (overlapping_) add_overlapping_energies(lv, state_, P, len, order_);
  for (std::size_t idx : lv.factors) {
    Factor& f = state_[idx];
    const std::size_t k = f.k;
    // Non-overlapping window sums ending in the new part (boundaries at
    // multiples of k on the level).
    const std::size_t lo = lv.base + lv.kept;  // boundaries > lo
    const std::size_t b1 = (lo / k + 1) * k;   // the first boundary
    if (b1 <= lv.base + len) {
      // In blocks that stay in the cache; the lag sums take them in turn.
      std::size_t count = (lv.base + len - b1) / k + 1;
      std::size_t b0 = b1 - k - lv.base;
      if (zs_.size() < kZBlock + 1) {
        zs_.resize(kZBlock + 1);
        diff_.resize(kZBlock + 1);
      }
      while (count > 0) {
        const std::size_t n = std::min(count, kZBlock);
        window_sums(P, b0, k, n, static_cast<double>(k) * c, zs_.data());
        f.push_averages(zs_.data(), n, order_, diff_.data());
        b0 += n * k;
        count -= n;
      }
    }
  }
  // Pair sums for the next level, aligned on even indices of this one.
  if (level + 1 < levels_.size()) pair_sums_for_next(lv, len);
  // Keep the span's prefix sums for the terms that end in the next pass.
  const std::size_t keep = std::min(lv.span, len);
  rebase(P + (len - keep), keep, lv.buf.data());
  lv.mean = c;
  lv.fill = keep;
  lv.base += len - keep;
  lv.kept = keep;
  // The next level touches only its own buffers.
  if (level + 1 < levels_.size() && lv.out_n > 0) append(level + 1, lv.out.data(), lv.out_n);
}

StreamingDeviation::Result StreamingDeviation::finish(double tau0, const StabilityOptions& opt) {
  if (opt.intervals && has_intervals(stat_)) check_noise_type(stat_, opt.alpha);
  for (std::size_t l = 0; l < levels_.size(); ++l) process(l);
  Result res;
  const std::size_t n_phase = samples_ + 1;
  const std::size_t top = max_averaging_factor(stat_, n_phase);
  const double c = order_ == 2 ? 2.0 : 6.0;
  const bool short_rule = opt.conservative_short && !opt.alpha;
  int last_alpha = 0;
  bool have_alpha = false;
  for (std::size_t j = 0; j < factors_.size(); ++j) {
    const StreamedFactor& fa = factors_[j];
    const Factor& f = state_[j];
    if (fa.m > top) continue;
    double sum = 0.0;
    std::size_t n = 0;
    if (overlapping_) {
      sum = f.energy;
      n = f.terms;
    } else {
      const Lag& d = f.lag[order_ - 1];  // first (ADEV) or second (HDEV) differences
      sum = d.s2;
      n = d.n;
    }
    if (n == 0) continue;
    StabilityPoint p;
    p.m = fa.m;
    p.tau = static_cast<double>(fa.m) * tau0;
    p.n = n;
    const double md = static_cast<double>(fa.m);
    p.dev = std::sqrt(std::max(sum, 0.0) / (c * md * md * static_cast<double>(n)));
    if (opt.intervals) {
      // The phase points the level's values cover.
      const std::size_t level_values = levels_[fa.level].total;
      const std::size_t covered = (level_values << fa.level) + 1;
      if (opt.alpha) {
        p.alpha = *opt.alpha;
      } else if (2 * fa.m > top && have_alpha) {  // Stable32's run rule
        p.alpha = last_alpha;
        p.type_carried = true;
      } else if (f.averages >= kMinAcfAverages) {
        double r1[4];
        for (int d = 0; d <= order_; ++d) r1[d] = f.lag[d].r1();
        p.alpha = noise_from_lag1(std::span<const double>(r1, static_cast<std::size_t>(order_) + 1), stat_).alpha;
      } else if (f.averages >= 2 && f.lag[1].s2 > 0.0) {
        // Barnes' B1 from the same sums: the sample variance of the averages
        // over their two-sample variance (R(n), which separates white from
        // flicker PM, needs the record: flicker PM is kept).
        const Lag& z = f.lag[0];
        const double na = static_cast<double>(z.n);
        const double svar = (z.s2 - z.s1 * z.s1 / na) / (na - 1.0);
        const double avar2 = f.lag[1].s2 / (2.0 * (na - 1.0));
        p.alpha = noise_from_b1(svar / avar2, n_phase, fa.m, z.n, stat_).alpha;
      } else {
        p.alpha = have_alpha ? last_alpha : 0;
        p.type_carried = true;
      }
      last_alpha = p.alpha;
      have_alpha = true;
      p.edf = edf_for_stride(stat_, p.alpha, fa.m, covered, fa.stride, opt.edf);
      if (short_rule && f.averages < kMinAcfAverages) {
        const int lowest = order_ == 3 ? -4 : -2;
        const int wfm = p.alpha >= 1 ? 0 : p.alpha;
        for (int a : {p.alpha - 1, p.alpha + 1, wfm})
          if (a >= lowest && a <= 2)
            p.edf = std::min(p.edf, edf_for_stride(stat_, a, fa.m, covered, fa.stride, opt.edf));
      }
      p.interval = chi2_interval(p.dev, p.edf, opt.ci);
    }
    res.points.push_back(p);
    res.strides.push_back(fa.stride);
  }
  return res;
}

}  // namespace cubecal
