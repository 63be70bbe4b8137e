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

StabilityPoint StabilityRecord::evaluate(std::size_t m, const StabilityOptions& opt) const {
  VarianceTerm v;
  switch (stat_) {
    case Stat::adev: v = avar(x_, m, tau0_); break;
    case Stat::oadev: v = oavar(x_, m, tau0_); break;
    case Stat::mdev:
    case Stat::tdev: v = mvar(x_, m, tau0_); break;
    case Stat::hdev: v = hvar(x_, m, tau0_); break;
    case Stat::ohdev: v = ohvar(x_, m, tau0_); break;
    case Stat::totdev: v = totvar(ext_, m, tau0_); break;
  }
  return finish(m, v, opt);
}

std::vector<StabilityPoint> StabilityRecord::evaluate(std::span<const std::size_t> ms,
                                                      const StabilityOptions& opt) const {
  std::vector<StabilityPoint> out;
  out.reserve(ms.size());
  std::vector<VarianceTerm> v(ms.size());
  switch (stat_) {
    case Stat::oadev: oavar(x_, ms, tau0_, v); break;
    case Stat::ohdev: ohvar(x_, ms, tau0_, v); break;
    case Stat::totdev: totvar(ext_, ms, tau0_, v); break;
    default:
      for (std::size_t j = 0; j < ms.size(); ++j) out.push_back(evaluate(ms[j], opt));
      carry_types(out, opt);
      return out;
  }
  for (std::size_t j = 0; j < ms.size(); ++j) out.push_back(finish(ms[j], v[j], opt));
  carry_types(out, opt);
  return out;
}

StabilityPoint StabilityRecord::finish(std::size_t m, VarianceTerm v,
                                       const StabilityOptions& opt) const {
  StabilityPoint p;
  p.m = m;
  p.tau = static_cast<double>(m) * tau0_;
  p.n = v.n;
  if (v.n == 0) return p;
  p.dev = std::sqrt(std::max(v.var, 0.0)) * scale_;
  if (stat_ == Stat::tdev) p.dev *= p.tau / std::sqrt(3.0);
  if (!opt.intervals) return p;

  p.alpha = opt.alpha ? *opt.alpha : identify_noise(x_, m, stat_).alpha;
  set_interval(p, opt);
  return p;
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
