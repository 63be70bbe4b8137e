// Haar wavelet variance from the OADEV kernels (stats/wavelet_variance.hpp).
#include "cubecal/stats/wavelet_variance.hpp"

#include <algorithm>
#include <cmath>

#include "cubecal/error.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/phase.hpp"

namespace cubecal {

WaveletVariance wavelet_variance(std::span<const double> y, double ci, std::size_t max_scales) {
  const std::size_t N = y.size();
  if (N < 4)
    throw UsageError(Field::samples, "the wavelet variance needs at least 4 samples, not " + std::to_string(N));
  std::vector<std::size_t> ms;
  for (std::size_t tau = 2; tau <= N / 2; tau *= 2) {
    if (max_scales > 0 && ms.size() == max_scales) break;
    ms.push_back(tau / 2);
  }
  return wavelet_variance_at(y, ms, ci);
}

WaveletVariance wavelet_variance_at(std::span<const double> y, std::span<const std::size_t> factors, double ci) {
  const std::size_t N = y.size();
  if (N < 4)
    throw UsageError(Field::samples, "the wavelet variance needs at least 4 samples, not " + std::to_string(N));
  if (!(ci > 0.0 && ci < 1.0)) throw UsageError(Field::ci, "the confidence must lie between 0 and 1");
  for (std::size_t j = 0; j < factors.size(); ++j)
    if (factors[j] < 1 || 4 * factors[j] > N || (j > 0 && factors[j] <= factors[j - 1]))
      throw UsageError(Field::scales, "the wavelet variance's averaging factors must ascend from 1 to N / 4 = " +
                                          std::to_string(N / 4));
  // The phase (running sum) of the scaled samples, as the deviations take it:
  // its second differences at m are the differences of adjacent m-sums.
  const double scale = power_of_two_scale(y);
  const std::vector<double> x = freq_to_phase(y, 1.0, scale);
  const std::vector<std::size_t> ms(factors.begin(), factors.end());
  std::vector<VarianceTerm> v(ms.size());
  oavar(x, ms, 1.0, v);
  WaveletVariance wv;
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const double tau = 2.0 * static_cast<double>(ms[j]);
    const double nu2 = 0.5 * v[j].var * scale * scale;
    const double edf = std::max(static_cast<double>(v[j].n) / tau, 1.0);
    const Interval band = chi2_interval(std::sqrt(nu2), edf, ci);
    wv.tau.push_back(tau);
    wv.nu2.push_back(nu2);
    wv.n.push_back(v[j].n);
    wv.edf.push_back(edf);
    wv.interval.push_back({band.lo * band.lo, band.hi * band.hi});
  }
  return wv;
}

std::vector<std::size_t> octave_and_half_factors(std::size_t max_m) {
  std::vector<std::size_t> ms;
  for (std::size_t m = 1; m <= max_m; m *= 2) {
    ms.push_back(m);
    if (m >= 2 && m + m / 2 <= max_m) ms.push_back(m + m / 2);
  }
  return ms;
}

}  // namespace cubecal
