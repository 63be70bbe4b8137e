#include "cubecal/stats/stability.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"
#include "cubecal/stats/theo.hpp"
#include "detail/time_error.hpp"
#include "detail/total_kernels.hpp"

namespace cubecal {

StabilityRecord::StabilityRecord(std::span<const double> data, DataType type, double tau0, Stat stat)
    : scale_(power_of_two_scale(data)),
      x_(type == DataType::phase ? normalize_phase(data, scale_)
         : has_intervals(stat)   ? freq_to_phase(data, tau0, scale_)
                                 : integrate_frequency(data, tau0, scale_)),
      type_(type),
      tau0_(tau0),
      stat_(stat) {
  if (stat_ == Stat::totdev) ext_ = totvar_extend(x_);
  if (stat_ == Stat::htotdev && x_.size() > 1) {
    d_.resize(x_.size() - 1);
    for (std::size_t k = 0; k + 1 < x_.size(); ++k) d_[k] = x_[k + 1] - x_[k];
  }
  if (stat_ == Stat::theobr || stat_ == Stat::theoh) {
    // The ratio takes Theo1 at N/6 factors up to 2N/3: about N^3/65 terms.
    if (x_.size() > kTheobrMaxPoints)
      throw std::invalid_argument(
          "theobr's bias ratio takes Theo1 at every fourth averaging factor up to 2N/3 "
          "(about N^3/65 terms): " +
          std::to_string(x_.size()) + " phase points is beyond the " + std::to_string(kTheobrMaxPoints) +
          " it is computed for; average the data first, or use theo1");
    theobr_ratio_ = theobr_ratio(x_);
  }
}

namespace {

// TOTVAR's bias (SP 1065 sec. 5.2.11; Howe, "Total variance explained",
// 1999, Table 1): E[TOTVAR] / AVAR = 1 - a tau / T, T the record length
// ((N - 1) tau0 for N phase points), a = 1 / (3 ln 2) = 0.481 for flicker FM,
// 0.750 for random-walk FM, 0 for white FM and phase noise. Stable32's TOTDEV
// divides by it (the ocxo octave table: docs/validation.md).
double totvar_bias(int alpha, std::size_t m, std::size_t n_phase) {
  const double a = alpha == -1 ? 1.0 / (3.0 * std::log(2.0)) : alpha == -2 ? 0.750 : 0.0;
  if (a == 0.0 || n_phase < 2) return 1.0;
  const double b = 1.0 - a * static_cast<double>(m) / static_cast<double>(n_phase - 1);
  return b > 0.0 ? b : 1.0;
}

// Variance bias of TOTDEV, MTOT (and TTOT) and of HTOT per noise type: the
// expected total variance over the variance it estimates (AVAR, MVAR, HVAR).
// SP 1065 sec. 5.2.11, 5.2.12 and 5.2.14; 1 where none is given.
double total_bias(Stat s, int alpha, std::size_t m, std::size_t n_phase) {
  if (s == Stat::totdev) return totvar_bias(alpha, m, n_phase);
  if (s == Stat::mtotdev || s == Stat::ttotdev) {
    switch (alpha) {
      case 2: return 0.94;
      case 1: return 0.83;
      case 0: return 0.73;
      case -1: return 0.70;
      case -2: return 0.69;
      default: return 1.0;
    }
  }
  if (s == Stat::htotdev) {
    switch (alpha) {
      case 0: return 0.995;
      case -1: return 0.851;
      case -2: return 0.771;
      case -3: return 0.717;
      case -4: return 0.679;
      default: return 1.0;
    }
  }
  return 1.0;
}

bool has_bias(Stat s) { return s == Stat::totdev || s == Stat::mtotdev || s == Stat::ttotdev || s == Stat::htotdev; }

// Whether the statistic's points are corrected: Stable32 corrects TOTDEV and
// HTOTDEV (its octave tables of the ocxo record, PHASE.DAT and the Sr87
// record), not MTOT and TTOT (PHASE.DAT's and Sr87's octave tables).
bool corrected(Stat s, BiasCorrection b) {
  switch (b) {
    case BiasCorrection::on: return has_bias(s);
    case BiasCorrection::off: return false;
    case BiasCorrection::stable32: return s == Stat::totdev || s == Stat::htotdev;
  }
  return false;
}

// HTOT at m = 1 is the overlapping Hadamard variance, which has no bias.
bool biased_at(Stat s, std::size_t m) { return has_bias(s) && !(s == Stat::htotdev && m == 1); }

}  // namespace

std::size_t StabilityRecord::max_m() const noexcept { return max_averaging_factor(stat_, x_.size()); }

VarianceTerm StabilityRecord::variance(std::size_t m) const {
  switch (stat_) {
    case Stat::adev: return avar(x_, m, tau0_);
    case Stat::oadev: return oavar(x_, m, tau0_);
    case Stat::mdev:
    case Stat::tdev: return mvar(x_, m, tau0_);
    case Stat::hdev: return hvar(x_, m, tau0_);
    case Stat::ohdev: return ohvar(x_, m, tau0_);
    case Stat::totdev: return totvar(ext_, m, tau0_);
    case Stat::tierms: return tie_mean_square(x_, m);
    case Stat::mtie: return mtie_square(x_, m);
    case Stat::mtotdev:
    case Stat::ttotdev: return mtotvar(x_, m, tau0_);
    // Riley's HTOT (and Stable32) take the overlapping Hadamard variance at m = 1.
    case Stat::htotdev: return m == 1 ? ohvar(x_, 1, tau0_) : htotvar(d_, m, tau0_);
    case Stat::theo1: return theo1var(x_, m, tau0_);
    case Stat::theobr: {
      if (!(theobr_ratio_ > 0.0)) return {};
      VarianceTerm v = theo1var(x_, m, tau0_);
      v.var *= theobr_ratio_;
      return v;
    }
    case Stat::theoh: return theohvar(x_, m, tau0_, theobr_ratio_);
  }
  return {};
}

bool StabilityRecord::needs_type(const StabilityOptions& opt) const noexcept {
  if (!has_intervals(stat_)) return false;
  // A correction asked for outright needs the type even without intervals.
  return opt.intervals || (opt.bias_correction == BiasCorrection::on && has_bias(stat_));
}

void StabilityRecord::describe(StabilityPoint& p, const StabilityOptions& opt) const {
  if (corrected(stat_, opt.bias_correction) && biased_at(stat_, p.m))
    p.dev /= std::sqrt(total_bias(stat_, p.alpha, p.m, x_.size()));
  if (opt.intervals) set_interval(p, opt);
}

StabilityPoint StabilityRecord::evaluate(std::size_t m, const StabilityOptions& opt) const {
  StabilityPoint p = point(m, variance(m));
  if (p.n == 0 || !needs_type(opt)) return p;
  identify(p, opt);
  describe(p, opt);
  return p;
}

std::vector<StabilityPoint> StabilityRecord::evaluate(std::span<const std::size_t> ms, const StabilityOptions& opt,
                                                      StageTimes* times) const {
  if (needs_type(opt)) check_noise_type(stat_, opt.alpha);
  std::vector<StabilityPoint> out;
  out.reserve(ms.size());
  {
    StageTimer timer(times, Stage::kernels);
    std::vector<VarianceTerm> v(ms.size());
    switch (stat_) {
      case Stat::oadev: oavar(x_, ms, tau0_, v); break;
      case Stat::ohdev: ohvar(x_, ms, tau0_, v); break;
      case Stat::totdev: totvar(ext_, ms, tau0_, v); break;
      default:
        for (std::size_t j = 0; j < ms.size(); ++j) v[j] = variance(ms[j]);
    }
    for (std::size_t j = 0; j < ms.size(); ++j) out.push_back(point(ms[j], v[j]));
  }
  if (!needs_type(opt)) return out;
  {
    StageTimer timer(times, Stage::noise_id);
    if (!opt.alpha && stat_ != Stat::theoh) {  // one walk over the record for every factor
      std::vector<std::size_t> at, m;
      for (std::size_t j = 0; j < out.size(); ++j)
        if (out[j].n > 0) {
          at.push_back(j);
          m.push_back(out[j].m);
        }
      const std::vector<NoiseId> id = identify_noise(x_, m, stat_);
      for (std::size_t k = 0; k < at.size(); ++k) out[at[k]].alpha = id[k].alpha;
    } else {
      for (StabilityPoint& p : out)
        if (p.n > 0) identify(p, opt);
    }
  }
  StageTimer timer(times, Stage::intervals);
  for (StabilityPoint& p : out)
    if (p.n > 0) describe(p, opt);
  carry_types(out, opt);
  return out;
}

StabilityPoint StabilityRecord::point(std::size_t m, VarianceTerm v) const {
  StabilityPoint p;
  p.m = m;
  p.tau = static_cast<double>(m) * tau_per_factor(stat_, m, x_.size()) * tau0_;
  p.n = v.n;
  if (v.n == 0) return p;
  p.dev = std::sqrt(std::max(v.var, 0.0)) * scale_;
  if (stat_ == Stat::tdev || stat_ == Stat::ttotdev) p.dev *= p.tau / std::sqrt(3.0);
  return p;
}

void StabilityRecord::identify(StabilityPoint& p, const StabilityOptions& opt) const {
  // TheoH: as the part it takes at m (OADEV or TheoBR).
  p.alpha =
      opt.alpha ? *opt.alpha : identify_noise(x_, p.m, theoh_stat_at(stat_, p.m, x_.size()).value_or(stat_)).alpha;
}

void StabilityRecord::set_interval(StabilityPoint& p, const StabilityOptions& opt) const {
  const std::size_t m = p.m;
  p.edf = edf_for(stat_, p.alpha, m, x_.size(), opt.edf);
  // Fewer than 30 averages: the type came from the B1 ratio (or was carried).
  const bool short_series = (x_.size() - 1) / m < 30;
  if (opt.conservative_short && !opt.alpha && short_series) {
    const int lowest = difference_order(stat_) == 3 ? -4 : -2;
    // The neighbouring B1 classes: alpha +-1, and white FM beside a PM call
    // (B1 sees white and flicker PM as one class; R(n) splits them).
    const int wfm = p.alpha >= 1 ? 0 : p.alpha;
    for (int a : {p.alpha - 1, p.alpha + 1, wfm})
      if (a >= lowest && a <= 2) p.edf = std::min(p.edf, edf_for(stat_, a, m, x_.size(), opt.edf));
  }
  p.interval = chi2_interval(p.dev, p.edf, opt.ci);
}

void StabilityRecord::carry_types(std::span<StabilityPoint> run, const StabilityOptions& opt) const {
  if (!needs_type(opt) || opt.alpha) return;
  const std::size_t top = max_m();
  for (std::size_t i = 1; i < run.size(); ++i) {
    StabilityPoint& p = run[i];
    const StabilityPoint& prev = run[i - 1];
    if (p.n == 0 || prev.n == 0 || 2 * p.m <= top) continue;
    if (corrected(stat_, opt.bias_correction) && biased_at(stat_, p.m))  // the bias of the type it had
      p.dev *= std::sqrt(total_bias(stat_, p.alpha, p.m, x_.size()));
    p.alpha = prev.alpha;
    p.type_carried = true;
    describe(p, opt);
  }
}

std::vector<StabilityPoint> stability(std::span<const double> data, DataType type, double tau0, Stat stat,
                                      std::span<const std::size_t> ms, const StabilityOptions& opt) {
  const StabilityRecord rec(data, type, tau0, stat);
  return rec.evaluate(ms, opt);
}

}  // namespace cubecal
