#include "cubecal/pipeline/dev_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/error.hpp"

namespace cubecal::pipeline {

namespace {

struct Piece {
  std::size_t channel;
  std::unique_ptr<StabilityRecord> record;
};

// With gaps split off, each segment is analysed on its own; a deviation over
// several segments pools their squared differences (weights n_k), which is
// the statistic of the whole record with every difference that would span a
// gap left out. Segments are independent, so their EDFs add.
StabilityPoint combine(const std::vector<StabilityPoint>& parts, std::size_t m, double tau0,
                       Stat stat, const StabilityOptions& opt) {
  StabilityPoint out;
  out.m = m;
  out.tau = static_cast<double>(m) * tau0;
  double sum = 0.0;
  std::size_t longest = 0;
  for (const auto& p : parts) {
    if (p.n == 0) continue;
    double var = p.dev * p.dev;
    if (stat == Stat::tdev) var *= 3.0 / (out.tau * out.tau);  // back to MVAR
    sum += var * static_cast<double>(p.n);
    out.n += p.n;
    out.edf += p.edf;
    if (p.n > longest) {
      longest = p.n;
      out.alpha = p.alpha;
    }
  }
  if (out.n == 0) return out;
  out.dev = std::sqrt(sum / static_cast<double>(out.n));
  if (stat == Stat::tdev) out.dev *= out.tau / std::sqrt(3.0);
  if (opt.intervals) {
    const Interval ci = chi2_interval(out.dev, out.edf, opt.ci);
    out.lo = ci.lo;
    out.hi = ci.hi;
  }
  return out;
}

DevResult run(const std::vector<std::string>& names,
              const std::vector<std::vector<double>>& channels, double rate_hz,
              const std::vector<io::Segment>& segments, const DevRequest& req) {
  DevResult res;
  res.stat = req.stat;
  res.type = req.type;
  res.rate_hz = rate_hz;
  res.tau0 = 1.0 / rate_hz;
  res.samples = channels.empty() ? 0 : channels[0].size();
  res.segments = segments.size();
  res.options = req.options;

  const int threads = req.threads > 0 ? static_cast<int>(req.threads) : omp_get_max_threads();

  // Phase records per (channel, segment), built in parallel.
  std::vector<Piece> pieces;
  for (std::size_t c = 0; c < channels.size(); ++c)
    for (std::size_t s = 0; s < segments.size(); ++s) pieces.push_back({c, nullptr});
  const std::size_t nseg = segments.size();
  // Exceptions must not leave an OpenMP region: keep the first and rethrow.
  std::vector<std::string> errors(pieces.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const auto& seg = segments[k % nseg];
    const auto& ch = channels[pieces[k].channel];
    std::span<const double> data(ch.data() + seg.begin, seg.size());
    try {
      pieces[k].record = std::make_unique<StabilityRecord>(data, req.type, res.tau0, req.stat);
    } catch (const std::exception& e) {
      errors[k] = e.what();
    }
  }
  for (std::size_t k = 0; k < pieces.size(); ++k)
    if (!errors[k].empty())
      throw UsageError("column " + names[pieces[k].channel] + ": " + errors[k] +
                           " (remove or repair it before the analysis)");

  std::size_t max_m = 0;
  res.segments_used = 0;
  for (std::size_t s = 0; s < nseg; ++s) {
    const std::size_t mm = pieces[s].record->max_m();
    max_m = std::max(max_m, mm);
    if (mm > 0) ++res.segments_used;
  }
  const std::vector<std::size_t> ms = averaging_factors(req.grid, max_m, res.tau0);
  if (ms.empty()) {
    std::size_t longest = 0;
    for (const auto& s : segments) longest = std::max(longest, s.size());
    throw UsageError("series too short for " + std::string(to_string(req.stat)) + ": " +
                         std::to_string(longest) +
                         " samples in the longest segment, and no averaging factor of the tau "
                         "grid fits (record longer data or choose smaller taus)");
  }

  // Every (piece, m) evaluation is independent.
  const std::size_t nm = ms.size();
  std::vector<StabilityPoint> evals(pieces.size() * nm);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < evals.size(); ++k) {
    const auto& rec = *pieces[k / nm].record;
    const std::size_t m = ms[k % nm];
    if (m <= rec.max_m()) evals[k] = rec.evaluate(m, req.options);
  }

  for (std::size_t c = 0; c < channels.size(); ++c) {
    DevChannel ch{names[c], {}};
    for (std::size_t j = 0; j < nm; ++j) {
      StabilityPoint p;
      if (nseg == 1) {
        p = evals[(c * nseg) * nm + j];
      } else {
        std::vector<StabilityPoint> parts;
        for (std::size_t s = 0; s < nseg; ++s) parts.push_back(evals[(c * nseg + s) * nm + j]);
        p = combine(parts, ms[j], res.tau0, req.stat, req.options);
      }
      if (p.n > 0) ch.points.push_back(p);
    }
    res.channels.push_back(std::move(ch));
  }
  return res;
}

}  // namespace

DevResult run_dev(const io::Series& series, const DevRequest& request) {
  DevResult r = run(series.names, series.channels, series.rate_hz, series.segments, request);
  r.file = series.file;
  return r;
}

DevResult run_dev(const std::vector<std::string>& names,
                  const std::vector<std::vector<double>>& channels, double rate_hz,
                  const DevRequest& request) {
  const std::size_t n = channels.empty() ? 0 : channels[0].size();
  return run(names, channels, rate_hz, {io::Segment{0, n}}, request);
}

}  // namespace cubecal::pipeline
