#include "cubecal/stats/stability.hpp"

#include <algorithm>
#include <cmath>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"

namespace cubecal {

StabilityRecord::StabilityRecord(std::span<const double> data, DataType type, double tau0,
                                 Stat stat)
    : scale_(power_of_two_scale(data)),
      x_(type == DataType::freq ? freq_to_phase(data, tau0, scale_) : normalize_phase(data, scale_)),
      type_(type),
      tau0_(tau0),
      stat_(stat) {
  if (stat_ == Stat::totdev) ext_ = totvar_extend(x_);
}

std::size_t StabilityRecord::max_m() const noexcept {
  return max_averaging_factor(stat_, x_.size());
}

VarianceTerm StabilityRecord::variance(std::size_t m) const {
  switch (stat_) {
    case Stat::adev: return avar(x_, m, tau0_);
    case Stat::oadev: return oavar(x_, m, tau0_);
    case Stat::mdev:
    case Stat::tdev: return mvar(x_, m, tau0_);
    case Stat::hdev: return hvar(x_, m, tau0_);
    case Stat::ohdev: return ohvar(x_, m, tau0_);
    case Stat::totdev: return totvar(ext_, m, tau0_);
  }
  return {};
}

StabilityPoint StabilityRecord::evaluate(std::size_t m, const StabilityOptions& opt) const {
  StabilityPoint p = point(m, variance(m));
  if (p.n == 0 || !opt.intervals) return p;
  identify(p, opt);
  set_interval(p, opt);
  return p;
}

std::vector<StabilityPoint> StabilityRecord::evaluate(std::span<const std::size_t> ms, const StabilityOptions& opt,
                                                      StageTimes* times) const {
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
  if (!opt.intervals) return out;
  {
    StageTimer timer(times, Stage::noise_id);
    for (StabilityPoint& p : out)
      if (p.n > 0) identify(p, opt);
  }
  StageTimer timer(times, Stage::intervals);
  for (StabilityPoint& p : out)
    if (p.n > 0) set_interval(p, opt);
  carry_types(out, opt);
  return out;
}

StabilityPoint StabilityRecord::point(std::size_t m, VarianceTerm v) const {
  StabilityPoint p;
  p.m = m;
  p.tau = static_cast<double>(m) * tau0_;
  p.n = v.n;
  if (v.n == 0) return p;
  p.dev = std::sqrt(std::max(v.var, 0.0)) * scale_;
  if (stat_ == Stat::tdev) p.dev *= p.tau / std::sqrt(3.0);
  return p;
}

void StabilityRecord::identify(StabilityPoint& p, const StabilityOptions& opt) const {
  p.alpha = opt.alpha ? *opt.alpha : identify_noise(x_, p.m, stat_).alpha;
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
  const Interval ci = chi2_interval(p.dev, p.edf, opt.ci);
  p.lo = ci.lo;
  p.hi = ci.hi;
}

void StabilityRecord::carry_types(std::span<StabilityPoint> run, const StabilityOptions& opt) const {
  if (!opt.intervals || opt.alpha) return;
  const std::size_t top = max_m();
  for (std::size_t i = 1; i < run.size(); ++i) {
    StabilityPoint& p = run[i];
    const StabilityPoint& prev = run[i - 1];
    if (p.n == 0 || prev.n == 0 || 2 * p.m <= top) continue;
    p.alpha = prev.alpha;
    p.type_carried = true;
    set_interval(p, opt);
  }
}

std::vector<StabilityPoint> stability(std::span<const double> data, DataType type, double tau0,
                                      Stat stat, std::span<const std::size_t> ms,
                                      const StabilityOptions& opt) {
  const StabilityRecord rec(data, type, tau0, stat);
  return rec.evaluate(ms, opt);
}

}  // namespace cubecal
