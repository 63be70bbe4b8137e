#include "cubecal/calib/plateaus.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

// A half-open range of samples [begin, end).
struct Range {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const noexcept { return end - begin; }
};

std::string fmt_s(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", seconds);
  return buf;
}

std::size_t samples(const TriadRecord& rec) { return rec.axes[0].size(); }

void check_record(const TriadRecord& rec) {
  const std::size_t n = samples(rec);
  if (rec.axes[1].size() != n || rec.axes[2].size() != n)
    throw CalibrationError(CalibrationReason::bad_data, "plateaus: the three gyro axes have different lengths");
  if (!rec.time.empty() && rec.time.size() != n)
    throw CalibrationError(CalibrationReason::bad_data,
                           "plateaus: the time column and the gyro have different lengths");
  if (!(rec.dt > 0.0) || !std::isfinite(rec.dt))
    throw CalibrationError(CalibrationReason::bad_data, "plateaus: the sampling period must be positive");
  for (std::size_t i = 0; i < rec.breaks.size(); ++i)
    if (rec.breaks[i] > n || (i > 0 && rec.breaks[i] <= rec.breaks[i - 1]))
      throw CalibrationError(CalibrationReason::bad_data, "plateaus: gap positions must be ascending sample indices");
}

void check_options(const PlateauOptions& opt) {
  if (!(opt.margin_s >= 0.0) || !(opt.min_plateau_s >= 0.0) || !(opt.ref_tolerance >= 0.0) || !(opt.window_s > 0.0) ||
      !(opt.steady_factor > 0.0) || !(opt.jump_sigma > 0.0) || !std::isfinite(opt.margin_s) ||
      !std::isfinite(opt.min_plateau_s) || !std::isfinite(opt.window_s))
    throw CalibrationError(CalibrationReason::bad_option,
                           "plateaus: margin, minimum length and tolerance must be >= 0, window and thresholds > 0");
}

double time_at(const TriadRecord& rec, std::size_t k) {
  return rec.time.empty() ? static_cast<double>(k) * rec.dt : rec.time[k];
}

// First sample at or after t, assuming time stamps increase.
std::size_t first_at_or_after(const TriadRecord& rec, double t) {
  if (!rec.time.empty())
    return static_cast<std::size_t>(std::lower_bound(rec.time.begin(), rec.time.end(), t) - rec.time.begin());
  if (t <= 0.0) return 0;
  return std::min(samples(rec), static_cast<std::size_t>(std::ceil(t / rec.dt - 1e-9)));
}

// One past the last sample at or before t.
std::size_t end_at_or_before(const TriadRecord& rec, double t) {
  if (!rec.time.empty())
    return static_cast<std::size_t>(std::upper_bound(rec.time.begin(), rec.time.end(), t) - rec.time.begin());
  if (t < 0.0) return 0;
  return std::min(samples(rec), static_cast<std::size_t>(std::floor(t / rec.dt + 1e-9)) + 1);
}

// The contiguous pieces of the record (split at the gaps).
std::vector<Range> pieces(const TriadRecord& rec) {
  std::vector<Range> out;
  std::size_t begin = 0;
  for (std::size_t b : rec.breaks) {
    if (b > begin) out.push_back({begin, b});
    begin = b;
  }
  if (samples(rec) > begin) out.push_back({begin, samples(rec)});
  return out;
}

// Drops `margin_s` of samples from the front and the back of a plateau made
// of `parts` (time-ordered ranges); empty when nothing is left.
std::vector<Range> trim(const TriadRecord& rec, std::vector<Range> parts, double margin_s) {
  if (parts.empty()) return parts;
  // A small slack so that a margin of exactly k periods drops k samples
  // despite rounding in the time stamps.
  const double slack = 1e-6 * rec.dt;
  const double t_first = time_at(rec, parts.front().begin) + margin_s - slack;
  const double t_last = time_at(rec, parts.back().end - 1) - margin_s + slack;
  std::vector<Range> out;
  for (Range r : parts) {
    while (r.begin < r.end && time_at(rec, r.begin) < t_first) ++r.begin;
    while (r.end > r.begin && time_at(rec, r.end - 1) > t_last) --r.end;
    if (r.size() > 0) out.push_back(r);
  }
  return out;
}

std::size_t count(const std::vector<Range>& parts) {
  std::size_t n = 0;
  for (const Range& r : parts) n += r.size();
  return n;
}

bool long_enough(const TriadRecord& rec, const std::vector<Range>& parts, double min_plateau_s) {
  // n samples cover n periods; the slack keeps 300 samples at 10 Hz = 30 s.
  return !parts.empty() && static_cast<double>(count(parts)) * rec.dt >= min_plateau_s * (1.0 - 1e-9);
}

// Mean, standard deviation and covariance of the gyro over `parts`
// (two passes: plateaus at 100 deg/s with mdeg/s noise would lose digits in
// a one-pass sum of squares).
Plateau make_plateau(const TriadRecord& rec, const std::vector<Range>& parts) {
  Plateau p;
  p.begin = parts.front().begin;
  p.end = parts.back().end;
  p.t_begin = time_at(rec, p.begin);
  p.t_end = time_at(rec, p.end - 1);
  p.n = count(parts);
  const double n = static_cast<double>(p.n);
  for (int a = 0; a < 3; ++a) {
    double s = 0.0;
    for (const Range& r : parts)
      for (std::size_t k = r.begin; k < r.end; ++k) s += rec.axes[a][k];
    p.mean[a] = s / n;
  }
  if (p.n > 1) {
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) {
        double s = 0.0;
        for (const Range& r : parts)
          for (std::size_t k = r.begin; k < r.end; ++k)
            s += (rec.axes[a][k] - p.mean[a]) * (rec.axes[b][k] - p.mean[b]);
        p.cov[a][b] = p.cov[b][a] = s / (n - 1.0);
      }
  }
  for (int a = 0; a < 3; ++a) p.stddev[a] = std::sqrt(p.cov[a][a]);
  return p;
}

// The moving-window statistics behind signal detection, for one axis of one
// contiguous piece.
class AxisWindows {
 public:
  AxisWindows(std::span<const double> x, Range piece, std::size_t window)
      : x_(x), piece_(piece), w_(window), prefix_(piece.size() + 1, 0.0) {
    // Prefix sums of x minus the piece's first value: window means without
    // re-summing, and no loss of digits to a large common offset.
    const double shift = x_[piece_.begin];
    for (std::size_t k = piece_.begin; k < piece_.end; ++k)
      prefix_[k - piece_.begin + 1] = prefix_[k - piece_.begin] + (x_[k] - shift);
  }

  // Variance over the centred window of every sample of the piece. The sums
  // slide, and restart from a fresh shift every window so that rounding
  // never accumulates and a constant signal gives exactly zero.
  std::vector<double> moving_variance() const {
    std::vector<double> var(piece_.size(), 0.0);
    const std::size_t half = w_ / 2;
    std::size_t lo = piece_.begin, hi = piece_.begin, reset = piece_.begin;
    double shift = 0.0, s1 = 0.0, s2 = 0.0;
    for (std::size_t k = piece_.begin; k < piece_.end; ++k) {
      const std::size_t new_lo = k >= piece_.begin + half ? k - half : piece_.begin;
      const std::size_t new_hi = std::min(piece_.end, k + (w_ - half));
      if (k == piece_.begin || k - reset >= w_) {
        reset = k;
        shift = x_[k];
        s1 = s2 = 0.0;
        for (std::size_t j = new_lo; j < new_hi; ++j) add(j, shift, s1, s2, 1.0);
      } else {
        for (std::size_t j = hi; j < new_hi; ++j) add(j, shift, s1, s2, 1.0);
        for (std::size_t j = lo; j < new_lo; ++j) add(j, shift, s1, s2, -1.0);
      }
      lo = new_lo;
      hi = new_hi;
      const double m = static_cast<double>(hi - lo);
      if (hi - lo > 1) var[k - piece_.begin] = std::max(0.0, (s2 - s1 * s1 / m) / (m - 1.0));
    }
    return var;
  }

  // |mean of the window after k - mean of the window before k| and the
  // standard error factor sqrt(1/n_before + 1/n_after) of that difference.
  std::pair<double, double> jump(std::size_t k) const {
    const std::size_t lo = k >= piece_.begin + w_ ? k - w_ : piece_.begin;
    const std::size_t hi = std::min(piece_.end, k + w_);
    if (lo == k || hi == k) return {0.0, 1.0};
    const double nl = static_cast<double>(k - lo), nr = static_cast<double>(hi - k);
    const double ml = (sum(k) - sum(lo)) / nl, mr = (sum(hi) - sum(k)) / nr;
    return {std::fabs(mr - ml), std::sqrt(1.0 / nl + 1.0 / nr)};
  }

  double mean(Range r) const { return (sum(r.end) - sum(r.begin)) / static_cast<double>(r.size()) + x_[piece_.begin]; }

 private:
  void add(std::size_t j, double shift, double& s1, double& s2, double sign) const {
    const double d = x_[j] - shift;
    s1 += sign * d;
    s2 += sign * d * d;
  }
  double sum(std::size_t k) const { return prefix_[k - piece_.begin]; }

  std::span<const double> x_;
  Range piece_;
  std::size_t w_;
  std::vector<double> prefix_;
};

// Quiet noise level of one axis: the 25th percentile of the standard
// deviations of non-overlapping windows. Plateaus fill most of a rate-table
// run, so the quietest quarter of the windows is plateau noise even when
// transitions are frequent.
double quiet_level(std::span<const double> x, const std::vector<Range>& parts, std::size_t window) {
  std::vector<double> sd;
  for (const Range& piece : parts)
    for (std::size_t b = piece.begin; b + window <= piece.end; b += window) {
      double m = 0.0;
      for (std::size_t k = b; k < b + window; ++k) m += x[k];
      m /= static_cast<double>(window);
      double s = 0.0;
      for (std::size_t k = b; k < b + window; ++k) s += (x[k] - m) * (x[k] - m);
      sd.push_back(std::sqrt(s / static_cast<double>(window - 1)));
    }
  if (sd.empty()) return -1.0;
  auto q = sd.begin() + static_cast<std::ptrdiff_t>(sd.size() / 4);
  std::nth_element(sd.begin(), q, sd.end());
  return *q;
}

[[noreturn]] void throw_none_found(const std::string& what, const PlateauOptions& opt) {
  throw CalibrationError(CalibrationReason::no_plateaus, "no plateau found: " + what + " lasts " +
                                                             fmt_s(opt.min_plateau_s) + " after dropping " +
                                                             fmt_s(opt.margin_s) + " at both ends");
}

}  // namespace

std::optional<ScheduleProblem> check_schedule(std::span<const ScheduleRow> rows) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ScheduleRow& r = rows[i];
    if (!std::isfinite(r.t_begin) || !std::isfinite(r.t_end) || !std::isfinite(r.rate[0]) ||
        !std::isfinite(r.rate[1]) || !std::isfinite(r.rate[2]))
      return ScheduleProblem{i, "schedule row " + std::to_string(i + 1) + " holds a value that is not finite"};
    if (!(r.t_end > r.t_begin))
      return ScheduleProblem{i, "schedule row " + std::to_string(i + 1) + " ends before it begins (t_end <= t_begin)"};
  }
  std::vector<std::size_t> order(rows.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return rows[a].t_begin < rows[b].t_begin; });
  for (std::size_t i = 1; i < order.size(); ++i) {
    const ScheduleRow& prev = rows[order[i - 1]];
    const ScheduleRow& cur = rows[order[i]];
    if (cur.t_begin < prev.t_end) {
      const std::size_t a = std::min(order[i - 1], order[i]), b = std::max(order[i - 1], order[i]);
      return ScheduleProblem{b, "schedule rows " + std::to_string(a + 1) + " and " + std::to_string(b + 1) +
                                    " overlap: the table cannot hold two rates at once"};
    }
  }
  return std::nullopt;
}

PlateauDetection plateaus_from_reference(const TriadRecord& rec, const std::array<std::span<const double>, 3>& ref,
                                         const PlateauOptions& opt) {
  check_record(rec);
  check_options(opt);
  for (const auto& r : ref)
    if (r.size() != samples(rec))
      throw CalibrationError(CalibrationReason::bad_data,
                             "plateaus: the reference columns and the gyro have different lengths");

  PlateauDetection out;
  for (const Range& piece : pieces(rec)) {
    std::size_t k = piece.begin;
    while (k < piece.end) {
      // A run holds the samples within tolerance of its first one: a slow
      // ramp cannot creep along a chain of small steps.
      const std::size_t start = k;
      auto same = [&](std::size_t j) {
        for (int a = 0; a < 3; ++a)
          if (!(std::fabs(ref[a][j] - ref[a][start]) <= opt.ref_tolerance)) return false;
        return true;
      };
      while (k < piece.end && same(k)) ++k;
      if (k == start) ++k;  // a non-finite reference: skip the sample
      const std::vector<Range> kept = trim(rec, {{start, k}}, opt.margin_s);
      if (!long_enough(rec, kept, opt.min_plateau_s)) {
        if (!kept.empty()) ++out.dropped_short;  // not the single samples of a ramp
        continue;
      }
      Plateau p = make_plateau(rec, kept);
      for (int a = 0; a < 3; ++a) {
        double s = 0.0;
        for (std::size_t j = p.begin; j < p.end; ++j) s += ref[a][j];
        p.ref[a] = s / static_cast<double>(p.end - p.begin);
      }
      p.has_ref = true;
      out.plateaus.push_back(p);
    }
  }
  if (out.plateaus.empty()) throw_none_found("no run of constant reference rate", opt);
  return out;
}

PlateauDetection plateaus_from_signal(const TriadRecord& rec, const PlateauOptions& opt) {
  check_record(rec);
  check_options(opt);
  const std::size_t window = std::max<std::size_t>(5, static_cast<std::size_t>(std::lround(opt.window_s / rec.dt)));
  const std::vector<Range> parts = pieces(rec);

  PlateauDetection out;
  // Thresholds per axis. The floor keeps a noise-free (simulated) constant
  // signal steady despite rounding in the window sums.
  std::array<double, 3> floor{};
  for (int a = 0; a < 3; ++a) {
    out.noise[a] = quiet_level(rec.axes[a], parts, window);
    if (out.noise[a] < 0.0)
      throw CalibrationError(CalibrationReason::no_plateaus,
                             "no plateau found: the record is shorter than one detection window (" +
                                 fmt_s(static_cast<double>(window) * rec.dt) + ")");
    double peak = 0.0;
    for (double v : rec.axes[a]) peak = std::max(peak, std::fabs(v));
    floor[a] = 1e-9 * peak;
  }

  // Steady samples, then runs of them per piece.
  std::vector<std::vector<Range>> groups;  // plateaus as lists of steady runs
  std::vector<std::array<double, 3>> group_mean;
  std::vector<std::size_t> group_n, group_piece;
  for (std::size_t pi = 0; pi < parts.size(); ++pi) {
    const Range& piece = parts[pi];
    std::vector<AxisWindows> axes;
    std::vector<char> steady(piece.size(), 1);
    for (int a = 0; a < 3; ++a) {
      axes.emplace_back(rec.axes[a], piece, window);
      const std::vector<double> var = axes[a].moving_variance();
      const double sd_limit = opt.steady_factor * out.noise[a] + floor[a];
      for (std::size_t k = piece.begin; k < piece.end; ++k) {
        const auto [diff, se] = axes[a].jump(k);
        if (var[k - piece.begin] > sd_limit * sd_limit || diff > opt.jump_sigma * out.noise[a] * se + floor[a])
          steady[k - piece.begin] = 0;
      }
    }
    std::size_t k = piece.begin;
    while (k < piece.end) {
      if (!steady[k - piece.begin]) {
        ++k;
        continue;
      }
      std::size_t e = k;
      while (e < piece.end && steady[e - piece.begin]) ++e;
      const Range r{k, e};
      std::array<double, 3> m{};
      for (int a = 0; a < 3; ++a) m[a] = axes[a].mean(r);
      // Merge with the previous run of this piece when only a short
      // disturbance (up to about one window on each side of it, which is
      // what it makes unsteady) separates two runs at the same rate.
      bool merged = false;
      if (!groups.empty() && group_piece.back() == pi && r.begin - groups.back().back().end <= 3 * window) {
        const double n1 = static_cast<double>(group_n.back()), n2 = static_cast<double>(r.size());
        bool same = true;
        for (int a = 0; a < 3; ++a)
          same = same && std::fabs(m[a] - group_mean.back()[a]) <=
                             opt.jump_sigma * out.noise[a] * std::sqrt(1.0 / n1 + 1.0 / n2) + floor[a];
        if (same) {
          for (int a = 0; a < 3; ++a) group_mean.back()[a] = (n1 * group_mean.back()[a] + n2 * m[a]) / (n1 + n2);
          group_n.back() += r.size();
          groups.back().push_back(r);
          merged = true;
        }
      }
      if (!merged) {
        groups.push_back({r});
        group_mean.push_back(m);
        group_n.push_back(r.size());
        group_piece.push_back(pi);
      }
      k = e;
    }
  }

  for (const auto& g : groups) {
    const std::vector<Range> kept = trim(rec, g, opt.margin_s);
    if (!long_enough(rec, kept, opt.min_plateau_s)) {
      if (!kept.empty()) ++out.dropped_short;  // not the steady blips of a ramp
      continue;
    }
    out.plateaus.push_back(make_plateau(rec, kept));
  }
  if (out.plateaus.empty()) throw_none_found("no steady segment of the gyro signal", opt);
  return out;
}

PlateauDetection plateaus_from_schedule(const TriadRecord& rec, std::span<const ScheduleRow> rows,
                                        const PlateauOptions& opt) {
  check_record(rec);
  check_options(opt);
  if (const auto problem = check_schedule(rows)) throw CalibrationError(CalibrationReason::bad_data, problem->what);
  if (rows.empty())
    throw CalibrationError(CalibrationReason::no_plateaus, "no plateau found: the schedule has no rows");

  PlateauDetection out;
  const std::vector<Range> parts = pieces(rec);
  for (const ScheduleRow& row : rows) {
    const std::size_t first = first_at_or_after(rec, row.t_begin), last = end_at_or_before(rec, row.t_end);
    if (first >= last) {
      ++out.skipped_rows;  // e.g. a schedule of three runs applied to the run of one axis
      continue;
    }
    const std::size_t b = first_at_or_after(rec, row.t_begin + opt.margin_s);
    const std::size_t e = end_at_or_before(rec, row.t_end - opt.margin_s);
    bool any = false;
    for (const Range& piece : parts) {
      const Range r{std::max(b, piece.begin), std::min(e, piece.end)};
      if (r.begin >= r.end || !long_enough(rec, {r}, opt.min_plateau_s)) continue;
      Plateau p = make_plateau(rec, {r});
      p.ref = row.rate;
      p.has_ref = true;
      out.plateaus.push_back(p);
      any = true;
    }
    if (!any) ++out.dropped_short;
  }
  std::sort(out.plateaus.begin(), out.plateaus.end(),
            [](const Plateau& a, const Plateau& b) { return a.begin < b.begin; });
  if (out.plateaus.empty()) throw_none_found("no schedule interval inside the record", opt);
  return out;
}

PlateauDetection label_with_schedule(PlateauDetection found, std::span<const ScheduleRow> rows) {
  if (const auto problem = check_schedule(rows)) throw CalibrationError(CalibrationReason::bad_data, problem->what);
  const std::size_t detected = found.plateaus.size();
  std::vector<Plateau> labelled;
  for (Plateau p : found.plateaus) {
    const double length = p.t_end - p.t_begin;
    const ScheduleRow* best = nullptr;
    double best_overlap = -1.0;
    for (const ScheduleRow& row : rows) {
      const double overlap = std::min(p.t_end, row.t_end) - std::max(p.t_begin, row.t_begin);
      if (overlap > best_overlap) {
        best_overlap = overlap;
        best = &row;
      }
    }
    if (best != nullptr && best_overlap >= 0.5 * length) {
      p.ref = best->rate;
      p.has_ref = true;
      labelled.push_back(p);
    } else {
      ++found.unmatched;
    }
  }
  found.plateaus = std::move(labelled);
  if (found.plateaus.empty())
    throw CalibrationError(CalibrationReason::no_plateaus,
                           "no plateau found: none of the " + std::to_string(detected) +
                               " plateaus found in the gyro signal lies within a schedule interval");
  return found;
}

}  // namespace cubecal
