#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/dev_missing.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/theo.hpp"
#include "cubecal/error.hpp"
#include "../detail/for_channels.hpp"

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
    case Stat::tierms: t = N - md; break;
    case Stat::mtie:
      t = 4.0 * N;
      break;  // running max and min, forward and back
    // A subsequence of 3m points costs about 12m operations; TheoBR's ratio
    // is paid once per record, not per factor.
    case Stat::mtotdev:
    case Stat::ttotdev:
    case Stat::htotdev: t = std::max(N - 3.0 * md, 0.0) * 12.0 * md; break;
    case Stat::theo1:
    case Stat::theobr: t = factor_allowed(stat, m) ? std::max(N - md, 0.0) * md / 2.0 : 0.0; break;
    case Stat::theoh: {
      const auto part = theoh_stat_at(stat, m, n);
      t = !part ? 0.0 : *part == Stat::oadev ? N - 2.0 * md : std::max(N - md, 0.0) * md / 2.0;
      break;
    }
  }
  t = std::max(t, 0.0) + 64.0;
  if (intervals) t += N / md + 256.0;
  return t;
}

unsigned thread_count(const DevRequest& req) {
  return req.threads > 0 ? req.threads : static_cast<unsigned>(std::max(1, omp_get_max_threads()));
}

// Averaging factors per parallel task: about four tasks per thread, and no
// more than 32 factors, so that the factors of a task share their passes
// over the record (stats/kernels.hpp: groups of eight on a dense grid, tiles
// on a sparse one) while a few taus still spread over the threads. A group
// is never cut whatever the size, and a tiled factor is the bits of its own
// pass: the points do not depend on the size.
std::size_t block_size(std::size_t factors, std::size_t pieces, unsigned threads) {
  const std::size_t per_task = factors * pieces / (4 * static_cast<std::size_t>(threads));
  return std::clamp<std::size_t>(per_task, 1, 32);
}

std::size_t phase_points(const IndexRange& seg, DataType type) {
  return type == DataType::freq ? seg.size() + 1 : seg.size();
}

// With gaps split off, each segment is analysed on its own; a deviation over
// several segments pools their squared differences (weights n_k), which is
// the statistic of the whole record with every difference that would span a
// gap left out. Segments are independent, so their EDFs add.
StabilityPoint combine(const std::vector<StabilityPoint>& parts, std::size_t m, double tau0, Stat stat,
                       const StabilityOptions& opt) {
  StabilityPoint out;
  out.m = m;
  out.tau = static_cast<double>(m) * tau0;
  double sum = 0.0;
  std::size_t longest = 0;
  if (stat == Stat::theo1 || stat == Stat::theobr) out.tau *= 0.75;
  const bool time_scaled = stat == Stat::tdev || stat == Stat::ttotdev;
  if (stat == Stat::mtie) {
    // The largest excursion of any segment's windows.
    for (const auto& p : parts)
      if (p.n > 0) {
        out.n += p.n;
        out.dev = std::max(out.dev, p.dev);
      }
    return out;
  }
  for (const auto& p : parts) {
    if (p.n == 0) continue;
    double var = p.dev * p.dev;
    if (time_scaled) var *= 3.0 / (out.tau * out.tau);  // back to MVAR
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
  if (time_scaled) out.dev *= out.tau / std::sqrt(3.0);
  if (opt.intervals && has_intervals(stat)) {
    out.interval = chi2_interval(out.dev, out.edf, opt.ci);
  }
  return out;
}

// The result's settings, without its channels.
DevResult dev_settings(const std::vector<std::span<const double>>& channels, double rate_hz,
                       const std::vector<IndexRange>& segments, const DevRequest& req) {
  DevResult res;
  res.stat = req.stat;
  res.type = req.type;
  res.rate_hz = rate_hz;
  res.tau0 = 1.0 / rate_hz;
  res.samples = channels.empty() ? 0 : channels[0].size();
  res.segments = segments.size();
  res.options = req.options;
  if (!has_intervals(req.stat)) res.options.intervals = false;  // TIE rms, MTIE
  return res;
}

// The averaging factors of the grid the segments allow (res.segments_used
// and res.tau_list set on the way); throws for a record that allows none
// or that the statistic cannot take.
std::vector<std::size_t> dev_factors(DevResult& res, const std::vector<IndexRange>& segments, const DevRequest& req) {
  const std::size_t nseg = segments.size();
  std::size_t max_m = 0;
  res.segments_used = 0;
  for (const auto& seg : segments) {
    const std::size_t mm = max_averaging_factor(req.stat, phase_points(seg, req.type));
    max_m = std::max(max_m, mm);
    if (mm > 0) ++res.segments_used;
  }
  std::size_t longest = 0;
  for (const auto& s : segments) longest = std::max(longest, s.size());
  // TheoH's switch and its factors of listed taus follow the record length.
  if (req.stat == Stat::theoh && res.segments_used > 1)
    throw UsageError(Field::stat,
                     "theoh switches from OADEV to TheoBR at 20 % of the record's length: it takes one "
                     "contiguous record, and this one has " +
                         std::to_string(res.segments_used) +
                         " segments (fill or cut the gaps, or use oadev and theobr)");
  const TauGrid grid = req.stat == Stat::theoh
                           ? theoh_factor_grid(req.grid, phase_points(IndexRange{0, longest}, req.type), res.tau0)
                           : req.grid;
  const std::vector<std::size_t> ms = averaging_factors(grid, max_m, res.tau0 * tau_per_factor(req.stat));
  if ((req.stat == Stat::theobr || req.stat == Stat::theoh) &&
      phase_points(IndexRange{0, longest}, req.type) > StabilityRecord::kTheobrMaxPoints)
    throw UsageError(Field::stat,
                     "theobr's bias ratio takes Theo1 at every fourth averaging factor up to 2N/3 (about "
                     "N^3/65 terms): " +
                         std::to_string(longest) + " samples is beyond the " +
                         std::to_string(StabilityRecord::kTheobrMaxPoints) +
                         " phase points it is computed for; average the data first, or use theo1");
  res.tau_list = tau_list_outcome(req.grid, req.stat, req.type, longest, res.tau0,
                                  nseg > 1 ? "the longest segment" : "the record");
  if (ms.empty())
    throw UsageError("series too short for " + std::string(to_string(req.stat)) + ": " + std::to_string(longest) +
                     " samples in the longest segment, and no averaging factor of the tau "
                     "grid fits (record longer data or choose smaller taus)" +
                     (res.tau_list.excluded.empty() ? "" : ": " + res.tau_list.excluded.front().reason));
  return ms;
}

// Ranges of the grid per task; a kernel group is never cut, so a point is
// the same bits for any thread count and as the front door's.
std::vector<std::pair<std::size_t, std::size_t>> factor_ranges(const std::vector<std::size_t>& ms, std::size_t nseg,
                                                               int threads) {
  const std::size_t nm = ms.size();
  const std::size_t block = block_size(nm, nseg, static_cast<unsigned>(threads));  // cut for one channel
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  for (std::size_t j = 0; j < nm;) {
    const std::size_t start = j;
    while (j < nm && j - start < block) j += kernel_group_at(ms, j) ? kKernelGroup : 1;
    ranges.emplace_back(start, j);
  }
  return ranges;
}

// The evaluation of every (channel, segment, range of factors): the
// channels' phase records built a batch at a time and evaluated on the
// threads, with the progress reported from the caller's thread.
class BatchedEvaluation {
 public:
  BatchedEvaluation(const std::vector<std::string>& names, const std::vector<std::span<const double>>& channels,
                    const std::vector<IndexRange>& segments, const DevRequest& req, double tau0,
                    const std::vector<std::size_t>& ms, int threads)
      : names_(names),
        channels_(channels),
        segments_(segments),
        req_(req),
        tau0_(tau0),
        ms_(ms),
        threads_(threads),
        nseg_(segments.size()),
        nm_(ms.size()),
        ranges_(factor_ranges(ms, segments.size(), threads)) {}

  // Every point, [(channel * segments + segment) * factors + factor].
  std::vector<StabilityPoint> run();

 private:
  // Records of the batch starting at channel c0, one per (channel, segment).
  // Exceptions must not leave an OpenMP region: build() keeps the message
  // and check() rethrows it.
  struct Batch {
    std::size_t c0 = 0;
    std::vector<std::unique_ptr<StabilityRecord>> records;
    std::vector<std::string> errors;
  };

  double range_terms(std::size_t seg, std::size_t r) const {
    const std::size_t n = phase_points(segments_[seg], req_.type);
    const std::size_t top = max_averaging_factor(req_.stat, n);
    double t = 0.0;
    for (std::size_t j = ranges_[r].first; j < ranges_[r].second; ++j)
      if (ms_[j] <= top) t += terms_at(req_.stat, ms_[j], n, req_.options.intervals);
    return t;
  }
  Batch batch_at(std::size_t c0) const {
    Batch b;
    b.c0 = c0;
    const std::size_t size = c0 < channels_.size() ? (std::min(channels_.size(), c0 + batch_) - c0) * nseg_ : 0;
    b.records.resize(size);
    b.errors.resize(size);
    return b;
  }
  void build(Batch& b, std::size_t k) const {
    const auto& seg = segments_[k % nseg_];
    const auto& ch = channels_[b.c0 + k / nseg_];
    try {
      const StageTimer timer(req_.times, Stage::phase);
      b.records[k] = std::make_unique<StabilityRecord>(std::span<const double>(ch.data() + seg.begin, seg.size()),
                                                       req_.type, tau0_, req_.stat);
    } catch (const std::exception& e) {
      b.errors[k] = e.what();
    }
  }
  void check(const Batch& b) const {
    for (std::size_t k = 0; k < b.errors.size(); ++k)
      if (!b.errors[k].empty())
        throw UsageError("column " + names_[b.c0 + k / nseg_] + ": " + b.errors[k] +
                         " (remove or repair it before the analysis)");
  }
  // Task k of the batch's evaluations: one piece over one range of factors.
  void evaluate(const Batch& cur, std::size_t k, std::atomic<double>& batch_done);

  const std::vector<std::string>& names_;
  const std::vector<std::span<const double>>& channels_;
  const std::vector<IndexRange>& segments_;
  const DevRequest& req_;
  const double tau0_;
  const std::vector<std::size_t>& ms_;
  const int threads_;
  const std::size_t nseg_;
  const std::size_t nm_;
  const std::vector<std::pair<std::size_t, std::size_t>> ranges_;
  std::size_t batch_ = 1;
  double total_ = 0.0;
  std::vector<StabilityPoint> evals_;
  double done_ = 0.0;
  double reported_ = 0.0;  // thread 0's last report: rounding must not make the next one smaller
};

void BatchedEvaluation::evaluate(const Batch& cur, std::size_t k, std::atomic<double>& batch_done) {
  const std::size_t piece = k / ranges_.size();
  const auto& rec = *cur.records[piece];
  const std::size_t j0 = ranges_[k % ranges_.size()].first;
  std::size_t j1 = ranges_[k % ranges_.size()].second;
  while (j1 > j0 && ms_[j1 - 1] > rec.max_m()) --j1;  // ms ascending
  if (j1 > j0) {
    const auto points = rec.evaluate(std::span<const std::size_t>(ms_.data() + j0, j1 - j0), req_.options, req_.times);
    std::copy(points.begin(), points.end(),
              evals_.begin() + static_cast<std::ptrdiff_t>((cur.c0 * nseg_ + piece) * nm_ + j0));
  }
  const double t = range_terms(piece % nseg_, k % ranges_.size());
  const double now = done_ + batch_done.fetch_add(t) + t;
  if (req_.progress && omp_get_thread_num() == 0 && total_ > 0.0) {
    reported_ = std::max(reported_, std::min(now / total_, 1.0));  // the sum may round past the total
    req_.progress(reported_);
  }
}

std::vector<StabilityPoint> BatchedEvaluation::run() {
  for (std::size_t s = 0; s < nseg_; ++s)
    for (std::size_t r = 0; r < ranges_.size(); ++r) total_ += range_terms(s, r);
  total_ *= static_cast<double>(channels_.size());

  // A phase record is a copy of its channel: the channels are analysed a
  // batch at a time, so that the records alive at once hold two batches of
  // one channel (or, when one channel gives too few tasks to keep the
  // threads busy, one channel per thread) rather than a second copy of the
  // whole record.
  const std::size_t tasks_per_channel = nseg_ * ranges_.size();
  batch_ = tasks_per_channel >= 4 * static_cast<std::size_t>(threads_)
               ? 1
               : std::min<std::size_t>(channels_.size(), static_cast<std::size_t>(threads_));
  evals_.resize(channels_.size() * nseg_ * nm_);

  Batch cur = batch_at(0);
  cubecal::detail::for_channels(cur.records.size(), cubecal::detail::Team{threads_},
                                [&](std::size_t k) { build(cur, k); });
  check(cur);
  for (; cur.c0 < channels_.size();) {
    // Every (piece, range of factors) evaluation is independent; the next
    // batch's records are built among them (first, so that a thread builds
    // while the others evaluate), which keeps two batches alive for a
    // while rather than leaving threads idle while one is built. The
    // caller's thread (OpenMP thread 0) reports the progress between its
    // tasks.
    Batch next = batch_at(cur.c0 + batch_);
    const std::size_t builds = next.records.size();
    const std::size_t tasks = builds + cur.records.size() * ranges_.size();
    std::atomic<double> batch_done{0.0};
    cubecal::detail::for_channels(tasks, cubecal::detail::Team{threads_}, [&](std::size_t task) {
      if (task < builds)
        build(next, task);
      else
        evaluate(cur, task - builds, batch_done);
    });
    done_ += batch_done.load();
    // The ranges above ran apart: Stable32's run rule over each whole run.
    StageTimer carrying(req_.times, Stage::intervals);
    for (std::size_t k = 0; k < cur.records.size(); ++k)
      cur.records[k]->carry_types(
          std::span<StabilityPoint>(evals_.data() + static_cast<std::ptrdiff_t>((cur.c0 * nseg_ + k) * nm_), nm_),
          req_.options);
    carrying.stop();
    check(next);
    cur = std::move(next);
  }
  if (req_.progress) req_.progress(1.0);
  return std::move(evals_);
}

DevResult run(const std::vector<std::string>& names, const std::vector<std::span<const double>>& channels,
              double rate_hz, const std::vector<IndexRange>& segments, const DevRequest& req) {
  DevResult res = dev_settings(channels, rate_hz, segments, req);
  const int threads = req.threads > 0 ? static_cast<int>(req.threads) : omp_get_max_threads();
  const std::size_t nseg = segments.size();
  const std::vector<std::size_t> ms = dev_factors(res, segments, req);
  const std::size_t nm = ms.size();
  const std::vector<StabilityPoint> evals =
      BatchedEvaluation(names, channels, segments, req, res.tau0, ms, threads).run();

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
std::vector<std::size_t> grid_for(const std::vector<IndexRange>& segments, double tau0, const DevRequest& req) {
  std::size_t max_m = 0, longest = 0;
  for (const auto& seg : segments) {
    max_m = std::max(max_m, max_averaging_factor(req.stat, phase_points(seg, req.type)));
    longest = std::max(longest, phase_points(seg, req.type));
  }
  const TauGrid grid = req.stat == Stat::theoh ? theoh_factor_grid(req.grid, longest, tau0) : req.grid;
  return averaging_factors(grid, max_m, tau0 * tau_per_factor(req.stat));
}

}  // namespace

DevWorkEstimate estimate_dev(const io::Series& series, const DevRequest& req) {
  DevWorkEstimate e;
  e.threads = thread_count(req);
  if (series.channels.empty() || series.segments.empty() || !(series.rate_hz > 0.0)) return e;
  // Missing samples (--gaps skip): one pass per factor of a single thread's
  // kernel, no trial on the record (its NaNs are for dev_missing alone).
  if (series.gaps == io::GapPolicy::skip) return e;
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
  // TheoBR's bias ratio (once per record) would dominate a trial: none.
  if (req.stat == Stat::theobr || req.stat == Stat::theoh) return e;

  // The trial: a block of the grid's middle factors on (a prefix of) the
  // longest segment of the first channel, timed for a few milliseconds (a prefix of 2^18 samples: 2 MB, in the
  // same cache level as the records the estimate matters for).
  const auto longest = *std::max_element(series.segments.begin(), series.segments.end(),
                                         [](const IndexRange& a, const IndexRange& b) { return a.size() < b.size(); });
  constexpr std::size_t kTrialSamples = std::size_t{1} << 18;
  const std::size_t len = std::min(longest.size(), kTrialSamples);
  std::span<const double> data(series.channels[0].data() + longest.begin, len);
  double trial_terms = 0.0, seconds = 0.0;
  try {
    const StabilityRecord rec(data, req.type, tau0, req.stat);
    const std::vector<std::size_t> trial_grid =
        averaging_factors(req.grid, rec.max_m(), tau0 * tau_per_factor(req.stat));
    if (!trial_grid.empty()) {
      const std::size_t count = std::min<std::size_t>(8, trial_grid.size());
      const std::size_t first = (trial_grid.size() - count) / 2;
      const std::span<const std::size_t> block(trial_grid.data() + first, count);
      double per_pass = 0.0;
      for (std::size_t m : block) per_pass += terms_at(req.stat, m, rec.phase_points(), req.options.intervals);
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
  // Read with --gaps skip: missing samples in the channels (dev_missing.hpp).
  if (series.gaps == io::GapPolicy::skip) return run_dev_skipping_missing(series, request);
  DevResult r =
      run(series.names, {series.channels.begin(), series.channels.end()}, series.rate_hz, series.segments, request);
  r.file = series.file;
  return r;
}

DevResult run_dev(const std::vector<std::string>& names, const std::vector<std::vector<double>>& channels,
                  double rate_hz, const DevRequest& request) {
  const std::size_t n = channels.empty() ? 0 : channels[0].size();
  return run(names, {channels.begin(), channels.end()}, rate_hz, {IndexRange{0, n}}, request);
}

DevResult run_dev(const std::vector<std::string>& names, const std::vector<std::span<const double>>& channels,
                  double rate_hz, const std::vector<IndexRange>& segments, const DevRequest& request) {
  if (names.size() != channels.size())
    throw std::invalid_argument("run_dev: " + std::to_string(names.size()) + " names for " +
                                std::to_string(channels.size()) + " channels");
  for (const auto& c : channels)
    if (c.size() != channels.front().size()) throw std::invalid_argument("run_dev: channels of different lengths");
  if (segments.empty()) {
    const std::size_t n = channels.empty() ? 0 : channels[0].size();
    return run(names, channels, rate_hz, {IndexRange{0, n}}, request);
  }
  for (const auto& seg : segments)
    if (seg.begin > seg.end || (!channels.empty() && seg.end > channels[0].size()))
      throw std::invalid_argument("run_dev: a segment outside the channels");
  return run(names, channels, rate_hz, segments, request);
}

}  // namespace cubecal::pipeline
