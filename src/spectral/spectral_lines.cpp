// Periodic lines in a Welch spectrum (spectral/spectral_lines.hpp;
// docs/formulas/noise-terms.md §8f).
#include "cubecal/spectral/spectral_lines.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <stdexcept>

namespace cubecal {

namespace {

// The median of d over [k - half, k + half] less the guard band around k,
// from at most about 1024 of its bins taken at an even stride (the median of
// a wide window is known to a percent from them).
double background(const std::vector<double>& d, std::size_t k, std::size_t half, std::size_t guard,
                  std::vector<double>& scratch) {
  scratch.clear();
  const std::size_t lo = k > half ? k - half : 0;
  const std::size_t hi = std::min(d.size(), k + half + 1);
  const std::size_t stride = std::max<std::size_t>(1, (hi - lo) / 1024);
  for (std::size_t i = lo; i < hi; i += stride)
    if (i + guard < k || i > k + guard) scratch.push_back(d[i]);
  if (scratch.empty()) return d[k];
  const auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  return *mid;
}

}  // namespace

std::vector<SpectralLine> find_spectral_lines(const Psd& psd, const LineSearchOptions& options) {
  if (psd.bins_per_decade != 0)
    throw std::invalid_argument("find_spectral_lines: needs the raw bins of a Welch spectrum, not log bands");
  const std::vector<double>& d = psd.density;
  const std::size_t n = d.size();
  std::vector<SpectralLine> lines;
  if (n < 4 * options.min_bin || psd.segment_length == 0) return lines;
  const double df = psd.resolution_hz();
  // A Hann-like window's main lobe spans +-2 bins: keep +-4 out of the background.
  constexpr std::size_t kGuard = 4;
  // The background: the median over a window of half its frequency each
  // side, so that a resonance a few hertz wide (not a pure tone) stands out
  // of it as a line does; a power-law background stays within a factor
  // 1.5^|slope| across it. Computed on a grid of 64 points per octave and
  // interpolated between them.
  std::vector<double> bg(n, 0.0), ratio(n, 0.0), scratch;
  std::vector<std::size_t> grid;
  for (std::size_t k = options.min_bin; k + 1 < n; k += std::max<std::size_t>(1, k / 64)) grid.push_back(k);
  grid.push_back(n - 2);
  std::vector<double> at(grid.size());
  for (std::size_t g = 0; g < grid.size(); ++g)
    at[g] = background(d, grid[g], std::max<std::size_t>(16, grid[g] / 2), kGuard, scratch);
  for (std::size_t g = 0; g + 1 < grid.size(); ++g)
    for (std::size_t k = grid[g]; k <= grid[g + 1]; ++k) {
      const double w =
          grid[g + 1] > grid[g] ? static_cast<double>(k - grid[g]) / static_cast<double>(grid[g + 1] - grid[g]) : 0.0;
      bg[k] = at[g] + w * (at[g + 1] - at[g]);
    }
  for (std::size_t k = options.min_bin; k + 1 < n; ++k) ratio[k] = bg[k] > 0.0 ? d[k] / bg[k] : 0.0;
  // The threshold: the chi-square quantile of a bin's EDF at the false-alarm
  // probability spread over the bins searched (the background median is
  // near its mean for the EDFs of an averaged spectrum).
  const double searched = static_cast<double>(n - 1 - options.min_bin);
  const double edf = psd.edf.empty() ? 2.0 : std::max(psd.edf[n / 2], 2.0);
  const boost::math::chi_squared law(edf);
  const double q = boost::math::quantile(boost::math::complement(law, options.false_alarm / searched)) / edf;
  const double threshold = std::max(q, options.min_ratio);
  // Half-way back to the background: where a peak's bins end.
  const double edge = 1.0 + 2.0 * std::sqrt(2.0 / edf);

  for (std::size_t k = options.min_bin; k + 1 < n;) {
    if (ratio[k] < threshold) {
      ++k;
      continue;
    }
    std::size_t lo = k, hi = k;
    while (lo > options.min_bin && ratio[lo - 1] > edge) --lo;
    while (hi + 2 < n && (ratio[hi + 1] > edge || (hi + 2 < n && ratio[hi + 2] >= threshold))) ++hi;
    SpectralLine l;
    double w = 0.0, wf = 0.0;
    for (std::size_t i = lo; i <= hi; ++i) {
      const double excess = std::max(d[i] - bg[i], 0.0);
      w += excess;
      wf += excess * psd.frequency[i];
      l.peak_ratio = std::max(l.peak_ratio, ratio[i]);
    }
    if (w > 0.0) {
      l.frequency_hz = wf / w;
      l.power = w * df;
      l.width_hz = static_cast<double>(hi - lo + 1) * df;
      lines.push_back(l);
    }
    k = hi + 1;
  }
  std::sort(lines.begin(), lines.end(), [](const SpectralLine& a, const SpectralLine& b) { return a.power > b.power; });
  if (lines.size() > options.max_lines) lines.resize(options.max_lines);
  return lines;
}

}  // namespace cubecal
