// docs/formulas/spectral.md §3.
#include "detail/bin_covariance.hpp"

#include <algorithm>
#include <stdexcept>

namespace cubecal {

BinCovariance::BinCovariance(const Psd& raw) : length_(raw.segment_length) {
  if (raw.bin_covariance.empty() || length_ == 0 || raw.bin_covariance.size() != length_ / 2 + 1)
    throw std::invalid_argument("BinCovariance: the spectrum carries no bin covariance");
  prefix_.assign(raw.bin_covariance.size() + 1, 0.0);
  for (std::size_t d = 0; d < raw.bin_covariance.size(); ++d) prefix_[d + 1] = prefix_[d] + raw.bin_covariance[d];
}

double BinCovariance::range_sum(std::size_t d0, std::size_t d1) const {
  if (d1 <= d0) return 0.0;
  const std::size_t half = length_ / 2;  // g is stored for d = 0..half
  double s = 0.0;
  // d <= half: g(d) itself.
  const std::size_t lo_end = std::min(d1, half + 1);
  if (d0 < lo_end) s += prefix_[lo_end] - prefix_[d0];
  // d > half: g(L - d), L - d running over (L - d1, L - max(d0, half + 1)].
  const std::size_t hi_begin = std::max(d0, half + 1);
  if (hi_begin < d1) s += prefix_[length_ - hi_begin + 1] - prefix_[length_ - d1 + 1];
  return s;
}

double BinCovariance::abs_sum(long long lo, long long hi) const {
  double s = 0.0;
  if (lo < 0) {
    const long long neg_hi = std::min(hi, 0LL);  // e in [lo, neg_hi): |e| in [1 - neg_hi, 1 - lo)
    s += range_sum(static_cast<std::size_t>(1 - neg_hi), static_cast<std::size_t>(1 - lo));
    lo = 0;
  }
  if (hi > lo) s += range_sum(static_cast<std::size_t>(lo), static_cast<std::size_t>(hi));
  return s;
}

double BinCovariance::between(std::size_t a, std::size_t m, std::size_t b, std::size_t n) const {
  if (m == 0 || n == 0) throw std::invalid_argument("BinCovariance::between: an empty run of bins");
  double s = 0.0;
  for (std::size_t j = a; j < a + m; ++j) {
    const auto jj = static_cast<long long>(j);
    // k - j over [b - j, b + n - j): g(|j - k|) ...
    s += abs_sum(static_cast<long long>(b) - jj, static_cast<long long>(b + n) - jj);
    // ... and j + k over [j + b, j + b + n): g((j + k) mod L), j + k <= L.
    s += range_sum(j + b, j + b + n);
  }
  return s / (static_cast<double>(m) * static_cast<double>(n));
}

double BinCovariance::edf(std::size_t a, std::size_t m) const { return 2.0 / between(a, m, a, m); }

}  // namespace cubecal
