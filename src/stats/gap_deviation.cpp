#include "cubecal/stats/gap_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"

namespace cubecal {

std::size_t missing_samples(std::span<const double> data) noexcept {
  return static_cast<std::size_t>(std::count_if(data.begin(), data.end(), [](double v) { return std::isnan(v); }));
}

namespace {

// The phase points and, per point, the number of missing samples before it
// (frequency) or whether it is missing (phase), so that a term's validity is
// one comparison.
struct GappedPhase {
  std::vector<double> x;
  std::vector<std::size_t> missing_before;  // frequency: missing samples among y[0..k)
  bool frequency = false;

  bool valid(std::size_t i, std::size_t m) const noexcept {
    if (frequency) return missing_before[i] == missing_before[i + 2 * m];
    return !std::isnan(x[i]) && !std::isnan(x[i + m]) && !std::isnan(x[i + 2 * m]);
  }
};

GappedPhase gapped_phase(std::span<const double> data, DataType type, double tau0) {
  GappedPhase p;
  for (const double v : data)
    if (std::isinf(v)) throw std::invalid_argument("oadev_skipping_missing: an infinite sample");
  if (type == DataType::phase) {
    p.x.assign(data.begin(), data.end());
    return p;
  }
  p.frequency = true;
  // The mean frequency taken out first keeps the phase small (it cancels
  // in every second difference).
  double sum = 0.0;
  std::size_t count = 0;
  for (const double v : data)
    if (!std::isnan(v)) {
      sum += v;
      ++count;
    }
  const double mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
  p.x.resize(data.size() + 1);
  p.missing_before.resize(data.size() + 1);
  p.x[0] = 0.0;
  p.missing_before[0] = 0;
  for (std::size_t k = 0; k < data.size(); ++k) {
    const bool gone = std::isnan(data[k]);
    p.x[k + 1] = p.x[k] + (gone ? 0.0 : (data[k] - mean) * tau0);
    p.missing_before[k + 1] = p.missing_before[k] + (gone ? 1 : 0);
  }
  return p;
}

// The longest stretch of data without a missing sample: [begin, end).
std::pair<std::size_t, std::size_t> longest_whole_stretch(std::span<const double> data) {
  std::size_t best_begin = 0, best_end = 0, begin = 0;
  for (std::size_t k = 0; k <= data.size(); ++k) {
    if (k < data.size() && !std::isnan(data[k])) continue;
    if (k - begin > best_end - best_begin) {
      best_begin = begin;
      best_end = k;
    }
    begin = k + 1;
  }
  return {best_begin, best_end};
}

}  // namespace

std::vector<GapNoiseType> noise_types_skipping_missing(std::span<const double> data, DataType type, double tau0,
                                                       std::span<const std::size_t> ms,
                                                       const StabilityOptions& options) {
  for (const double v : data)
    if (std::isinf(v)) throw std::invalid_argument("noise_types_skipping_missing: an infinite sample");
  check_noise_type(Stat::oadev, options.alpha);
  // The noise type: fixed, or identified on the longest whole stretch.
  const auto [begin, end] = longest_whole_stretch(data);
  std::optional<StabilityRecord> stretch;
  if (!options.alpha && end - begin >= 3) stretch.emplace(data.subspan(begin, end - begin), type, tau0, Stat::oadev);
  // The stretch's types over the factors it holds, as a grid evaluation
  // gives them (with Stable32's run rule, carry_types); beyond, the last.
  std::vector<StabilityPoint> typed;
  if (stretch) {
    std::vector<std::size_t> held;
    for (const std::size_t m : ms)
      if (m <= stretch->max_m()) held.push_back(m);
    StabilityOptions with_types = options;
    with_types.intervals = true;
    typed = stretch->evaluate(held, with_types);
  }
  int alpha = options.alpha.value_or(0);
  bool carried = false;
  std::size_t next = 0;
  std::vector<GapNoiseType> out;
  out.reserve(ms.size());
  for (const std::size_t m : ms) {
    if (next < typed.size() && typed[next].m == m) {
      if (typed[next].n > 0) {
        alpha = typed[next].alpha;
        carried = typed[next].type_carried;
      }
      ++next;
    } else if (stretch) {
      carried = true;
    }
    out.push_back({alpha, carried});
  }
  return out;
}

std::vector<StabilityPoint> oadev_skipping_missing(std::span<const double> data, DataType type, double tau0,
                                                   std::span<const std::size_t> ms, const StabilityOptions& options) {
  const GappedPhase p = gapped_phase(data, type, tau0);
  const std::size_t n_phase = p.x.size();
  std::vector<StabilityPoint> out;
  out.reserve(ms.size());
  for (const std::size_t m : ms) {
    StabilityPoint pt;
    pt.m = m;
    pt.tau = static_cast<double>(m) * tau0;
    if (m > 0 && n_phase > 2 * m) {
      double sum = 0.0;
      std::size_t n = 0;
      for (std::size_t i = 0; i + 2 * m < n_phase; ++i) {
        if (!p.valid(i, m)) continue;
        const double d = p.x[i + 2 * m] - 2.0 * p.x[i + m] + p.x[i];
        sum += d * d;
        ++n;
      }
      if (n > 0) {
        pt.n = n;
        pt.dev = std::sqrt(sum / (2.0 * static_cast<double>(n))) / pt.tau;
      }
    }
    out.push_back(pt);
  }
  if (!options.intervals) return out;

  const std::vector<GapNoiseType> types = noise_types_skipping_missing(data, type, tau0, ms, options);
  for (std::size_t j = 0; j < out.size(); ++j) {
    StabilityPoint& pt = out[j];
    if (pt.n == 0) continue;
    pt.alpha = types[j].alpha;
    pt.type_carried = types[j].carried;
    // The EDF of a whole record with as many terms: n + 2m phase points.
    pt.edf = edf_for(Stat::oadev, pt.alpha, pt.m, pt.n + 2 * pt.m, options.edf);
    pt.interval = chi2_interval(pt.dev, pt.edf, options.ci);
  }
  return out;
}

}  // namespace cubecal
