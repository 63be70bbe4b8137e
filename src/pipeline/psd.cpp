// `cubecal psd`: docs/formulas/spectral.md.
#include "cubecal/pipeline/psd.hpp"

#include <omp.h>

#include <algorithm>
#include <exception>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/welch_psd.hpp"
#include "cubecal/spectral/log_bins.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

PsdResult run_psd(const std::vector<std::string>& names, const std::vector<std::span<const double>>& channels,
                  double rate_hz, const std::vector<IndexRange>& segments, const PsdRequest& request) {
  if (names.size() != channels.size()) throw std::invalid_argument("run_psd: a name per channel");
  const std::size_t n = channels.empty() ? 0 : channels[0].size();
  for (const auto& c : channels)
    if (c.size() != n) throw std::invalid_argument("run_psd: channels of different lengths");
  const std::size_t units = request.units.size();
  if (units > 1 && units != channels.size())
    throw UsageError(Field::units, "give one unit for all channels or one per channel (" + std::to_string(units) +
                                       " units for " + std::to_string(channels.size()) + " channels)");
  std::vector<IndexRange> pieces = segments;
  if (pieces.empty()) pieces.push_back({0, n});
  for (const auto& p : pieces)
    if (p.end > n || p.begin > p.end) throw std::invalid_argument("run_psd: a segment outside the record");

  PsdResult r;
  r.rate_hz = rate_hz;
  r.samples = n;
  r.pieces = pieces.size();
  r.overlap = request.welch.overlap;
  r.bins_per_decade = request.bins_per_decade;
  r.fitted = request.fit;
  r.channels.resize(channels.size());
  // The plan first, so that a bad request fails before any work and the
  // pieces used are counted once.
  std::size_t longest = 0;
  for (const auto& p : pieces) longest = std::max(longest, p.size());
  const WelchPlan plan = plan_welch(request.welch, longest, rate_hz);
  r.pieces_used = 0;
  for (const auto& p : pieces)
    if (welch_segments(p.size(), plan) > 0) ++r.pieces_used;

  const int threads = request.threads > 0 ? static_cast<int>(request.threads) : omp_get_max_threads();
  cubecal::detail::for_channels(channels.size(), cubecal::detail::Team{threads}, [&](std::size_t c) {
    std::vector<std::span<const double>> views;
    for (const auto& p : pieces) views.push_back(channels[c].subspan(p.begin, p.size()));
    const Psd raw = welch_psd(std::span<const std::span<const double>>(views), rate_hz, request.welch);
    PsdChannel& out = r.channels[c];
    out.name = names[c];
    if (units == 1) out.unit = request.units[0];
    if (units > 1) out.unit = request.units[c];
    if (request.fit) {
      try {
        out.fit = fit_power_law(raw, request.fit_options);
        out.allan_terms = psd_allan_terms(out.fit, out.unit, rate_hz);
      } catch (const UsageError& e) {
        const bool band_asked =
            request.fit_options.min_frequency_hz > 0.0 || request.fit_options.max_frequency_hz > 0.0;
        if (e.field() != Field::fit_range || band_asked) throw;
        out.fit_error = face_words(e.text());  // a short record: the spectrum without its fit
      }
    }
    out.spectrum = request.bins_per_decade > 0 ? log_bin(raw, request.bins_per_decade) : raw;
  });
  return r;
}

PsdResult run_psd(const io::Series& series, const PsdRequest& request) {
  std::vector<std::span<const double>> views;
  for (const auto& c : series.channels) views.emplace_back(c);
  PsdResult r = run_psd(series.names, views, series.rate_hz, series.segments, request);
  r.file = series.file;
  return r;
}

}  // namespace cubecal::pipeline
