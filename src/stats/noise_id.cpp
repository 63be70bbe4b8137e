// Power-law noise identification as Stable32 does it (Riley, "Handbook of
// Frequency Stability Analysis", NIST SP 1065 sec. 5.6; Riley & Greenhall,
// EFTF 2004; Howe, Beard, Greenhall, Riley, PTTI 2000). Each choice below
// was checked against the Stable32 tables in ../shared/data/stable32
// (tests/test_stable32.cpp prints the agreement per dataset):
//
// 1. The data at averaging factor m are the non-overlapping averages of
//    frequency, for phase input as well (differences of the phase decimated
//    by m). Only the mean is removed. Decimated phase instead, with its line
//    or quadratic removed, calls white PM at the long taus of a white-FM
//    Cs clock record (5071A, 47 AFs per statistic) where Stable32 says white
//    FM; removing a frequency drift moves rows off Stable32 at the +-0.5
//    rounding boundary.
// 2. With at least 30 averages: lag-1 autocorrelation r1, differencing
//    until delta = r1/(1+r1) < 0.25 or the statistic's maximum order d
//    (2 for the Allan, 3 for the Hadamard statistics); alpha =
//    -round(2 delta) - 2d. r1 is the lag-1 sum over N divided by the sum of
//    squares over N - 1 (a sample variance): (N-1)/N times Riley's r1. This
//    decides only rows at the rounding boundary, and it is the variant that
//    reproduces every such row of the tables (14 of them).
// 3. Fewer than 30 averages: Barnes' B1 ratio, the sample variance of the
//    averages over their two-sample variance, against its expected value
//    for each mu (Howe et al. Table 3) with boundaries at the geometric
//    means. Stable32 evaluates the expected values at the statistic's own
//    number of terms (the "#" of its tables: averages - 1 for ADEV,
//    N - 2m for OADEV, ...), not at the number of averages: with the count
//    of averages 65 of the 314 5071A OADEV rows and 27 of the 261 ocxo
//    ADEV rows are off, with the number of terms none and 0.
// 4. B1 cannot separate white from flicker PM (both mu = -2): the ratio
//    R(n) = MVAR/AVAR does, for every statistic.
// 5. Beyond half the largest averaging factor Stable32 does not identify
//    anew: each factor keeps the previous one's type in the run
//    (StabilityRecord::carry_types). This is what makes an octave run and
//    an all-tau run of the same data differ at their last AFs.
#include "cubecal/stats/noise_id.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/lag_sums.hpp"
#include "../detail/simd.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMinAcfPoints = 30;

int clamp_alpha(int alpha, Stat stat) {
  const int lowest = difference_order(stat) == 3 ? -4 : -2;
  return std::clamp(alpha, lowest, 2);
}

int alpha_from_mu(int mu) {
  // mu = -alpha - 1 for -4 <= alpha <= 0; white and flicker PM share mu = -2.
  return mu == -2 ? 2 : -mu - 1;
}

// The N at which Stable32 evaluates the expected B1: the statistic's own
// number of terms at m (the "#" column of its tables), from the phase
// record's length and the number of averages (point 3 above).
double b1_points(Stat stat, std::size_t phase_points, std::size_t m, std::size_t averages) {
  const double np = static_cast<double>(phase_points), mm = static_cast<double>(m);
  const double na = static_cast<double>(averages);
  switch (stat) {
    case Stat::adev: return na - 1.0;
    case Stat::hdev: return na - 2.0;
    case Stat::oadev: return np - 2.0 * mm;
    case Stat::mdev:
    case Stat::tdev: return np - 3.0 * mm + 1.0;
    case Stat::ohdev: return np - 3.0 * mm;
    case Stat::totdev: return np - 2.0;
    case Stat::mtotdev:
    case Stat::ttotdev: return np - 3.0 * mm + 1.0;
    case Stat::htotdev: return np - 3.0 * mm;
    case Stat::theo1:
    case Stat::theobr: return np - mm;
    case Stat::theoh: return np - 2.0 * mm;  // identified as its part (StabilityRecord)
    case Stat::tierms:
    case Stat::mtie: return np - mm;  // not identified (no interval)
  }
  return na - 1.0;
}

}  // namespace

NoiseId noise_from_lag1(std::span<const double> r1, Stat stat) {
  NoiseId out;
  const int dmax = std::min(difference_order(stat), static_cast<int>(r1.size()) - 1);
  for (int d = 0; d <= dmax; ++d) {
    const double delta = r1[static_cast<std::size_t>(d)] / (1.0 + r1[static_cast<std::size_t>(d)]);
    if (delta < 0.25 || d >= dmax) {
      out.alpha_est = -2.0 * (delta + d);
      out.alpha = clamp_alpha(static_cast<int>(-std::lround(2.0 * delta)) - 2 * d, stat);
      out.method = NoiseId::Method::acf;
      return out;
    }
  }
  return out;
}

NoiseId noise_from_b1(double b1, std::size_t phase_points, std::size_t m, std::size_t averages, Stat stat) {
  NoiseId out;
  out.method = NoiseId::Method::b1;
  out.b1 = b1;
  const double N = b1_points(stat, phase_points, m, averages);
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
  return out;
}

namespace {

// The lag-1 sums of the averages at one factor and of their differences up
// to the statistic's order, fed a block of kAcfBlock averages at a time: the
// same blocks, and so the same bits, whether one factor's averages come
// from a walk of its own (identify_noise at m) or from the walk all factors
// share (identify_noise at a grid). w0 holds the block after its carry: w0[0]
// is the last average of the previous block, carry[d] the last d-th
// difference.
constexpr std::size_t kAcfBlock = 1024;
static_assert(kAcfBlock > 3);

struct AcfSums {
  int dmax = 0;
  std::size_t k0 = 0;  // averages taken before the current block
  LagSums sums[4];
  double carry[4] = {0.0, 0.0, 0.0, 0.0};

  // The block w0[1 .. len] (w0[0] is overwritten with the carry); scratch
  // holds 3 (kAcfBlock + 1) doubles.
  void add(double* w0, std::size_t len, double* scratch) noexcept {
    w0[0] = carry[0];
    sums[0].add(w0 + 1, len);
    const double* src = w0;
    for (int d = 1; d <= dmax; ++d) {
      double* buf = scratch + static_cast<std::size_t>(d - 1) * (kAcfBlock + 1);
      buf[0] = carry[d];
      double* dst = buf + 1;
      for (std::size_t j = 0; j < len; ++j) dst[j] = src[j + 1] - src[j];
      // The d-th difference starts at index d of the sequence.
      const std::size_t start = k0 == 0 ? static_cast<std::size_t>(d) : 0;
      if (len > start) sums[d].add(dst + start, len - start);
      carry[d] = buf[len];
      src = buf;
    }
    carry[0] = w0[len];
    k0 += len;
  }

  NoiseId identify(Stat stat) const {
    double r1[4];
    for (int d = 0; d <= dmax; ++d) r1[d] = sums[d].r1();
    return noise_from_lag1(std::span<const double>(r1, static_cast<std::size_t>(dmax) + 1), stat);
  }
};

}  // namespace

NoiseId identify_noise(std::span<const double> x, std::size_t m, Stat stat) {
  NoiseId out;
  if (m == 0 || x.size() < m + 1) return out;
  // Non-overlapping averages of frequency, unscaled (x[(k+1)m] - x[km]: the
  // 1/(m tau0) factor cancels in every ratio below).
  const std::size_t count = (x.size() - 1) / m;
  auto z = [&](std::size_t k) { return x[(k + 1) * m] - x[k * m]; };

  if (count >= kMinAcfPoints) {
    AcfSums acf;
    acf.dmax = difference_order(stat);
    std::vector<double> storage(4 * (kAcfBlock + 1), 0.0);
    double* w0 = storage.data();
    for (std::size_t k0 = 0; k0 < count; k0 += kAcfBlock) {
      const std::size_t len = std::min(kAcfBlock, count - k0);
      for (std::size_t j = 0; j < len; ++j) w0[j + 1] = z(k0 + j);
      acf.add(w0, len, w0 + kAcfBlock + 1);
    }
    return acf.identify(stat);
  }

  // B1 ratio on the averages.
  out.method = NoiseId::Method::b1;
  if (count < 2) return out;
  const double b1 = b1_ratio(x, m);  // 0 when the Allan variance of the averages is 0
  if (!(b1 > 0.0)) return out;
  out = noise_from_b1(b1, x.size(), m, count, stat);
  if (out.alpha == alpha_from_mu(-2)) {  // B1 said white or flicker PM
    // R(n) = MVAR/AVAR: 1/m for white PM, 3.37/(1.04 + 3 ln(pi m)) for flicker PM.
    const VarianceTerm mv = mvar(x, m, 1.0);
    const VarianceTerm av = oavar(x, m, 1.0);
    if (mv.n > 0 && av.n > 0 && av.var > 0.0) {
      out.rn = mv.var / av.var;
      const double md = static_cast<double>(m);
      const double r_fpm = 3.37 / (1.04 + 3.0 * std::log(std::numbers::pi * md));
      const double r_wpm = 1.0 / md;
      out.alpha = out.rn > std::sqrt(r_fpm * r_wpm) ? 1 : 2;
      out.method = NoiseId::Method::b1_rn;
    }
  }
  return out;
}

std::vector<NoiseId> identify_noise(std::span<const double> x, std::span<const std::size_t> ms, Stat stat) {
  std::vector<NoiseId> out(ms.size());
  // The factors with enough averages for the lag-1 method share one walk
  // over x in pieces that stay in the cache: taken one factor at a time,
  // the points x[km] of a factor beyond a few samples each sit in a cache
  // line of their own, and the walk waits on memory for every one.
  struct Factor {
    std::size_t j, m, count, next;  // next: the index k of the next point x[km]
    double prev;
    std::size_t len;
    AcfSums acf;
    std::vector<double> w0;
  };
  std::vector<Factor> acf;
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const std::size_t m = ms[j];
    if (m == 0 || x.size() < m + 1 || (x.size() - 1) / m < kMinAcfPoints) {
      out[j] = identify_noise(x, m, stat);
      continue;
    }
    Factor f{j, m, (x.size() - 1) / m, 0, 0.0, 0, AcfSums{}, {}};
    f.acf.dmax = difference_order(stat);
    acf.push_back(std::move(f));
  }
  if (acf.empty()) return out;
  std::vector<double> scratch(3 * (kAcfBlock + 1));
  constexpr std::size_t kPiece = std::size_t{1} << 13;  // 64 KiB of phase
  // At most kWalkFactors share a walk (8 KiB of block each), so that an
  // all-tau grid of a long record does not hold a block for every factor.
  constexpr std::size_t kWalkFactors = 64;
  for (std::size_t g0 = 0; g0 < acf.size(); g0 += kWalkFactors) {
    const std::span<Factor> group(acf.data() + g0, std::min(kWalkFactors, acf.size() - g0));
    for (Factor& f : group) f.w0.assign(kAcfBlock + 1, 0.0);
    for (std::size_t p0 = 0; p0 < x.size(); p0 += kPiece) {
      const std::size_t p1 = std::min(x.size(), p0 + kPiece);
      for (Factor& f : group) {
        // Points x[km] for k <= count (count averages need count + 1 points),
        // the state in locals so that the loop carries nothing through memory.
        const std::size_t m = f.m, count = f.count;
        const std::size_t stop = std::min(count, (p1 - 1) / m);  // the last k with km in this piece
        std::size_t k = f.next, len = f.len;
        double prev = f.prev;
        double* w = f.w0.data();
        if (k == 0) {  // the first point starts the averages
          prev = x[0];
          k = 1;
        }
        while (k <= stop) {
          // Up to the end of the block or of the piece, whichever comes first.
          const std::size_t run = std::min(kAcfBlock - len, stop - k + 1);
          if (m == 1) {
            const double* xs = x.data() + k;
            for (std::size_t i = 0; i < run; ++i) w[len + 1 + i] = xs[i] - xs[i - 1];
            prev = xs[run - 1];
          } else {
            const double* xs = x.data() + k * m;
            for (std::size_t i = 0; i < run; ++i, xs += m) {
              const double v = *xs;
              w[len + 1 + i] = v - prev;
              prev = v;
            }
          }
          len += run;
          k += run;
          if (len == kAcfBlock || k > count) {
            f.acf.add(w, len, scratch.data());
            len = 0;
          }
        }
        f.next = k;
        f.len = len;
        f.prev = prev;
      }
    }
    for (Factor& f : group) {
      out[f.j] = f.acf.identify(stat);
      f.w0 = {};
    }
  }
  return out;
}

}  // namespace cubecal
