#include "cubecal/pipeline/dev_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/error.hpp"

namespace cubecal::pipeline {

namespace {

// Terms the kernel of `stat` sums at averaging factor m on n phase points,
// plus a share for noise identification (a pass over the n/m averaged
// points) and the EDF: the unit of work of the estimate and the progress.
double terms_at(Stat stat, std::size_t m, std::size_t n, bool intervals) {
  const double N = static_cast<double>(n);
  const double md = static_cast<double>(m);
  double t = 0.0;
  switch (stat) {
    case Stat::adev:
    case Stat::hdev: t = N / md; break;
    case Stat::oadev: t = N - 2.0 * md; break;
    case Stat::mdev:
    case Stat::tdev:
    case Stat::ohdev: t = N - 3.0 * md; break;
    case Stat::totdev: t = N; break;
  }
  t = std::max(t, 0.0) + 64.0;
  if (intervals) t += N / md + 256.0;
  return t;
}

unsigned thread_count(const DevRequest& req) {
  return req.threads > 0 ? req.threads : static_cast<unsigned>(std::max(1, omp_get_max_threads()));
}

// Averaging factors per parallel task: whole groups of the grouped kernels
// (stats/kernels.hpp, eight factors) on a dense grid, single factors on a
// sparse one so that a few taus still spread over the threads.
std::size_t block_size(std::size_t factors, std::size_t pieces, unsigned threads) {
  const std::size_t groups = factors * pieces / (64 * static_cast<std::size_t>(threads));
  return groups == 0 ? 1 : 8 * std::min<std::size_t>(groups, 4);
}

std::size_t phase_points(const io::Segment& seg, DataType type) {
  return type == DataType::freq ? seg.size() + 1 : seg.size();
}

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
  std::size_t longest = 0;
  for (const auto& s : segments) longest = std::max(longest, s.size());
  res.tau_list = tau_list_outcome(req.grid, req.stat, req.type, longest, res.tau0,
                                  nseg > 1 ? "the longest segment" : "the record");
  if (ms.empty())
    throw UsageError("series too short for " + std::string(to_string(req.stat)) + ": " +
                         std::to_string(longest) +
                         " samples in the longest segment, and no averaging factor of the tau "
                         "grid fits (record longer data or choose smaller taus)" +
                         (res.tau_list.excluded.empty() ? "" : ": " + res.tau_list.excluded.front().reason));

  // Every (piece, block of factors) evaluation is independent. The caller's
  // thread (OpenMP thread 0) reports the progress between its blocks.
  const std::size_t nm = ms.size();
  const std::size_t block = block_size(nm, pieces.size(), static_cast<unsigned>(threads));
  // Ranges of the grid per task; a kernel group is never cut, so a point is
  // the same bits for any thread count and as the front door's.
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  for (std::size_t j = 0; j < nm;) {
    const std::size_t start = j;
    while (j < nm && j - start < block) j += kernel_group_at(ms, j) ? kKernelGroup : 1;
    ranges.emplace_back(start, j);
  }
  const std::size_t tasks = pieces.size() * ranges.size();
  auto task_terms = [&](std::size_t k) {
    const auto& rec = *pieces[k / ranges.size()].record;
    const auto [j0, j1] = ranges[k % ranges.size()];
    double t = 0.0;
    for (std::size_t j = j0; j < j1; ++j)
      if (ms[j] <= rec.max_m())
        t += terms_at(req.stat, ms[j], rec.phase_points(), req.options.intervals);
    return t;
  };
  double total = 0.0;
  for (std::size_t k = 0; k < tasks; ++k) total += task_terms(k);
  std::atomic<double> done{0.0};
  std::vector<StabilityPoint> evals(pieces.size() * nm);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t k = 0; k < tasks; ++k) {
    const std::size_t piece = k / ranges.size();
    const auto& rec = *pieces[piece].record;
    const std::size_t j0 = ranges[k % ranges.size()].first;
    std::size_t j1 = ranges[k % ranges.size()].second;
    while (j1 > j0 && ms[j1 - 1] > rec.max_m()) --j1;  // ms ascending
    if (j1 > j0) {
      const auto points =
          rec.evaluate(std::span<const std::size_t>(ms.data() + j0, j1 - j0), req.options);
      std::copy(points.begin(), points.end(),
                evals.begin() + static_cast<std::ptrdiff_t>(piece * nm + j0));
    }
    const double now = done.fetch_add(task_terms(k)) + task_terms(k);
    if (req.progress && omp_get_thread_num() == 0 && total > 0.0)
      req.progress(std::min(now / total, 1.0));  // the sum may round past the total
  }
  if (req.progress) req.progress(1.0);
  // The blocks above ran apart: Stable32's run rule over each whole run.
  for (std::size_t k = 0; k < pieces.size(); ++k)
    pieces[k].record->carry_types(
        std::span<StabilityPoint>(evals.data() + static_cast<std::ptrdiff_t>(k * nm), nm), req.options);

  for (std::size_t c = 0; c < channels.size(); ++c) {
    DevChannel ch{names[c], {}, {}};
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

// The grid as run() builds it, from the segments' sizes alone.
std::vector<std::size_t> grid_for(const std::vector<io::Segment>& segments, double tau0,
                                  const DevRequest& req) {
  std::size_t max_m = 0;
  for (const auto& seg : segments)
    max_m = std::max(max_m, max_averaging_factor(req.stat, phase_points(seg, req.type)));
  return averaging_factors(req.grid, max_m, tau0);
}

}  // namespace

DevWorkEstimate estimate_dev(const io::Series& series, const DevRequest& req) {
  DevWorkEstimate e;
  e.threads = thread_count(req);
  if (series.channels.empty() || series.segments.empty() || !(series.rate_hz > 0.0)) return e;
  const double tau0 = 1.0 / series.rate_hz;
  const std::vector<std::size_t> ms = grid_for(series.segments, tau0, req);
  e.taus = ms.size();
  if (ms.empty()) return e;
  for (const auto& seg : series.segments) {
    const std::size_t n = phase_points(seg, req.type);
    const std::size_t top = max_averaging_factor(req.stat, n);
    for (std::size_t m : ms)
      if (m <= top) e.terms += terms_at(req.stat, m, n, req.options.intervals);
  }
  e.terms *= static_cast<double>(series.channels.size());

  // The trial: a block of the grid's middle factors on (a prefix of) the
  // longest segment of the first channel, timed for a few milliseconds (a prefix of 2^18 samples: 2 MB, in the
  // same cache level as the records the estimate matters for).
  const auto longest = *std::max_element(
      series.segments.begin(), series.segments.end(),
      [](const io::Segment& a, const io::Segment& b) { return a.size() < b.size(); });
  constexpr std::size_t kTrialSamples = std::size_t{1} << 18;
  const std::size_t len = std::min(longest.size(), kTrialSamples);
  std::span<const double> data(series.channels[0].data() + longest.begin, len);
  double trial_terms = 0.0, seconds = 0.0;
  try {
    const StabilityRecord rec(data, req.type, tau0, req.stat);
    const std::vector<std::size_t> trial_grid = averaging_factors(req.grid, rec.max_m(), tau0);
    if (!trial_grid.empty()) {
      const std::size_t count = std::min<std::size_t>(8, trial_grid.size());
      const std::size_t first = (trial_grid.size() - count) / 2;
      const std::span<const std::size_t> block(trial_grid.data() + first, count);
      double per_pass = 0.0;
      for (std::size_t m : block)
        per_pass += terms_at(req.stat, m, rec.phase_points(), req.options.intervals);
      const auto start = std::chrono::steady_clock::now();
      do {
        (void)rec.evaluate(block, req.options);
        trial_terms += per_pass;
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      } while (seconds < 0.004 && trial_terms < 64.0 * per_pass);
    }
  } catch (const std::exception&) {
    // A bad sample: run_dev will say which; the estimate stays at zero seconds.
  }
  if (trial_terms > 0.0 && seconds > 0.0) {
    e.terms_per_second = trial_terms / seconds;
    const std::size_t pieces = series.channels.size() * series.segments.size();
    const std::size_t block = block_size(ms.size(), pieces, e.threads);
    const std::size_t tasks = pieces * ((ms.size() + block - 1) / block);  // about
    const double parallel = static_cast<double>(std::min<std::size_t>(e.threads, tasks));
    e.seconds = e.terms / (e.terms_per_second * parallel);
  }
  return e;
}

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
