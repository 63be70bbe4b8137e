// docs/formulas/spectral.md §4.
#include "cubecal/spectral/log_bins.hpp"

#include <cmath>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "detail/bin_covariance.hpp"

namespace cubecal {

std::vector<BinRun> log_band_runs(const Psd& raw, std::size_t bins_per_decade, double f_lo, double f_hi) {
  if (bins_per_decade == 0) throw UsageError(Field::bins_per_decade, "give at least one band per decade");
  if (raw.bins_per_decade != 0) throw std::invalid_argument("log_band_runs: the spectrum is binned already");
  const std::size_t n = raw.frequency.size();
  // The Nyquist bin of an even L, like DC, holds half a density.
  const std::size_t end = (raw.segment_length % 2 == 0 && n > 1) ? n - 1 : n;
  const double k = static_cast<double>(bins_per_decade);
  std::vector<BinRun> runs;
  long long band = 0;
  for (std::size_t i = 1; i < end; ++i) {
    const double f = raw.frequency[i];
    if (f < f_lo || f > f_hi) continue;
    const auto b = static_cast<long long>(std::floor(k * std::log10(f)));
    if (runs.empty() || b != band || runs.back().first + runs.back().count != i) {
      runs.push_back({i, 0});
      band = b;
    }
    ++runs.back().count;
  }
  return runs;
}

Psd log_bin(const Psd& raw, std::size_t bins_per_decade) {
  const auto runs = log_band_runs(raw, bins_per_decade, 0.0, raw.rate_hz);
  const BinCovariance cov(raw);
  Psd out = raw;
  out.bins_per_decade = bins_per_decade;
  out.frequency.clear();
  out.density.clear();
  out.edf.clear();
  out.first_bin.clear();
  out.bins.clear();
  for (const BinRun& r : runs) {
    double sum = 0.0;
    double log_f = 0.0;
    for (std::size_t i = r.first; i < r.first + r.count; ++i) {
      sum += raw.density[i];
      log_f += std::log(raw.frequency[i]);
    }
    const double m = static_cast<double>(r.count);
    out.frequency.push_back(std::exp(log_f / m));
    out.density.push_back(sum / m);
    out.edf.push_back(cov.edf(r.first, r.count));
    out.first_bin.push_back(r.first);
    out.bins.push_back(r.count);
  }
  return out;
}

}  // namespace cubecal
