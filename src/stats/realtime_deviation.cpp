#include "cubecal/stats/realtime_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

namespace cubecal {

namespace {

constexpr std::size_t kSlack = 4096;  // samples the history grows by before it is cut back

}  // namespace

RealtimeDeviation::RealtimeDeviation(Stat stat, std::span<const std::size_t> factors, bool keep_all)
    : stat_(stat), order_(stat == Stat::oadev ? 2 : 3), keep_all_(keep_all) {
  if (stat != Stat::oadev && stat != Stat::ohdev && stat != Stat::tdev)
    throw std::invalid_argument(std::string(to_string(stat)) + " is not computed in real time (oadev, ohdev, tdev)");
  for (std::size_t m : factors) {
    if (m == 0) throw std::invalid_argument("an averaging factor must be at least 1");
    m_.push_back(m);
    span_ = std::max(span_, static_cast<std::size_t>(order_) * m + 1);
  }
  state_.resize(m_.size());
}

double RealtimeDeviation::second_difference(std::size_t i, std::size_t m) const noexcept {
  return (at(i + 2 * m) - 2.0 * at(i + m)) + at(i);
}

double RealtimeDeviation::term(std::size_t i, std::size_t m) const noexcept {
  if (order_ == 2) return (at(i) - 2.0 * at(i - m)) + at(i - 2 * m);
  return ((at(i) - 3.0 * at(i - m)) + 3.0 * at(i - 2 * m)) - at(i - 3 * m);
}

void RealtimeDeviation::add_term(Factor& f, double t) noexcept {
  // Kahan: a sum over the whole record.
  const double y = t * t - f.energy_c;
  const double s = f.energy + y;
  f.energy_c = (s - f.energy) - y;
  f.energy = s;
  ++f.terms;
}

// The terms of factor j that end at the newest sample t.
void RealtimeDeviation::advance(std::size_t j) {
  const std::size_t m = m_[j];
  const std::size_t t = samples_ - 1;
  Factor& f = state_[j];
  if (stat_ != Stat::tdev) {
    if (t >= static_cast<std::size_t>(order_) * m) add_term(f, term(t, m));
    return;
  }
  // TDEV: the window sums m second differences, the last starting at t - 2m.
  if (t < 2 * m) return;
  const std::size_t last = t - 2 * m;
  if (last + 1 >= m && (last + 1) % m == 0) {
    // Summed anew every m samples: no rounding carried along the record.
    double w = 0.0;
    for (std::size_t i = last + 1 - m; i <= last; ++i) w += second_difference(i, m);
    f.window = w;
  } else {
    f.window += second_difference(last, m);
    if (last >= m) f.window -= second_difference(last - m, m);
  }
  if (last + 1 >= m) add_term(f, f.window);
}

void RealtimeDeviation::trim() {
  if (keep_all_ || hist_.size() < 2 * span_ + kSlack) return;
  const std::size_t drop = hist_.size() - span_;
  hist_.erase(hist_.begin(), hist_.begin() + static_cast<std::ptrdiff_t>(drop));
  first_ += drop;
}

void RealtimeDeviation::add_phase(double x) {
  if (!std::isfinite(x))
    throw std::invalid_argument("phase sample " + std::to_string(samples_) + " is not a finite number");
  if (samples_ == 0) origin_ = x;
  hist_.push_back(x - origin_);
  last_ = x;
  ++samples_;
  for (std::size_t j = 0; j < m_.size(); ++j) advance(j);
  trim();
}

void RealtimeDeviation::add_phase(std::span<const double> x) {
  for (double v : x) add_phase(v);
}

void RealtimeDeviation::add_factor(std::size_t m) {
  if (!keep_all_) throw std::logic_error("a factor is added only to a record kept whole");
  if (m == 0) throw std::invalid_argument("an averaging factor must be at least 1");
  m_.push_back(m);
  state_.emplace_back();
  span_ = std::max(span_, static_cast<std::size_t>(order_) * m + 1);
  // Its terms so far, as if it had been there from the first sample.
  const std::size_t n = samples_;
  const std::size_t j = m_.size() - 1;
  for (samples_ = 1; samples_ <= n; ++samples_) advance(j);
  samples_ = n;
}

double RealtimeDeviation::deviation(std::size_t j, double tau0) const noexcept {
  const Factor& f = state_[j];
  if (f.terms == 0) return 0.0;
  const double m = static_cast<double>(m_[j]);
  const double scale = stat_ == Stat::tdev ? 1.0 : tau0 * tau0;
  const double c = stat_ == Stat::oadev ? 2.0 : 6.0;
  return std::sqrt(std::max(f.energy, 0.0) / (c * m * m * scale * static_cast<double>(f.terms)));
}

}  // namespace cubecal
