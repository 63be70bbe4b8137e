// IEEE Std 952 slope read-offs from an Allan-deviation curve (what the paper
// and most lab notebooks do): the line of each term's slope tangent to the
// curve, read at the term's tau, and the bias instability from the minimum.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"

namespace cubecal {

namespace {

// A point belongs to a region of slope s0 when its local log-log slope is
// within this of s0. 0.15 is 30 % of the spacing between the IEEE 952
// slopes (-1, -1/2, 0, +1/2, +1), so neighbouring regions never share a
// point. A white-noise arm stays "white" until its neighbour carries 15 %
// (rate random walk) to 30 % (flicker floor) of the variance.
constexpr double kSlopeTolerance = 0.15;

// The local slope at a point is taken between neighbours at least this many
// decades away on each side, so that a dense grid (every m) does not give
// slopes between points 0.1 % apart in tau, which are pure estimator noise.
constexpr double kHalfBaselineDecades = 0.05;

// A region must span at least a factor of 2 in tau (and two points): a curve
// that merely turns through a slope on its way between two regions (white
// to rate ramp passes through +1/2) does not show that noise term.
constexpr double kMinRegionDecades = 0.30103;

std::vector<double> local_slopes(const AllanCurve& c) {
  const std::size_t n = c.size();
  std::vector<double> s(n, std::numeric_limits<double>::quiet_NaN());
  if (n < 2) return s;
  const double ratio = std::pow(10.0, kHalfBaselineDecades);
  // j: the last point at least `ratio` below tau_i (else the first point);
  // k: the first point at least `ratio` above it (else the last). Both only
  // move forward as i does.
  std::size_t j = 0, k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (j + 1 < i && c.tau[j + 1] * ratio <= c.tau[i]) ++j;
    k = std::max(k, std::min(i + 1, n - 1));
    while (k + 1 < n && c.tau[k] < c.tau[i] * ratio) ++k;
    s[i] = std::log(c.dev[k] / c.dev[j]) / std::log(c.tau[k] / c.tau[j]);
  }
  return s;
}

struct Run {
  std::size_t first = 0;
  std::size_t last = 0;  // inclusive
};

// Maximal runs of consecutive points whose slope is within tolerance of s0
// and that are wide enough to count as a region.
std::vector<Run> regions_of_slope(const AllanCurve& c, const std::vector<double>& slope, double s0) {
  std::vector<Run> runs;
  const std::size_t n = c.size();
  std::size_t i = 0;
  while (i < n) {
    if (!(std::abs(slope[i] - s0) <= kSlopeTolerance)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < n && std::abs(slope[j + 1] - s0) <= kSlopeTolerance) ++j;
    if (j > i && std::log10(c.tau[j] / c.tau[i]) >= kMinRegionDecades - 1e-12) runs.push_back({i, j});
    i = j + 1;
  }
  return runs;
}

// One IEEE 952 straight-line term: sigma(tau) = value * (tau / tau_read)^slope.
struct LineTerm {
  double slope;
  double tau_read;     // where the line's ordinate is the term's value
  bool at_short_taus;  // where the region sits on a typical curve
};

// The line of the term's slope that lies on or below the curve and touches
// it: for a sum of power laws the curve is convex in log-log, and the line
// through point i has ordinate dev_i (tau_read / tau_i)^slope, smallest at
// the point where the curve's own slope equals the line's. Taking the
// minimum over the region is the paper's "line tangent to the curve".
TermEstimate tangent_in(const AllanCurve& c, const Run& r, const std::vector<double>& rel_sigma, LineTerm term) {
  TermEstimate e;
  std::size_t best = r.first;
  double best_value = std::numeric_limits<double>::infinity();
  for (const std::size_t i : well_measured(c, r.first, r.last)) {
    const double v = c.dev[i] * std::pow(term.tau_read / c.tau[i], term.slope);
    if (v < best_value) {
      best_value = v;
      best = i;
    }
  }
  e.valid = true;
  e.value = best_value;
  e.sigma = best_value * rel_sigma[best];
  e.tau_lo = c.tau[r.first];
  e.tau_hi = c.tau[r.last];
  return e;
}

TermEstimate read_line(const AllanCurve& c, const std::vector<double>& slope, const std::vector<double>& rel_sigma,
                       LineTerm term) {
  const auto runs = regions_of_slope(c, slope, term.slope);
  if (runs.empty()) return {};
  return tangent_in(c, term.at_short_taus ? runs.front() : runs.back(), rel_sigma, term);
}

// IEEE 952 reads N where the white-noise line crosses tau = 1 s. Where the
// -1/2 region of the curve contains 1 s, the line is read from the curve's
// points within this factor of 1 s (0.5-2 s).
constexpr double kWhiteWindow = 2.0;
constexpr double kWhiteReadTau = 1.0;

// N. The region of slope -1/2 that contains tau = 1 s, else the one nearest
// to it (in log tau).
//
// Containing 1 s: N is the ordinate at 1 s of the line sigma = N / sqrt(tau)
// through the curve there: the weighted mean of sigma(tau) sqrt(tau) over the
// points of the region within kWhiteWindow of 1 s (weights 1/rel^2 from the
// intervals). Its uncertainty is the same weighted mean of the points'
// relative uncertainties, as if they were fully correlated (overlapping
// estimates over the same data nearly are). (A straight line in log-log
// through the same points, read at 1 s, follows each point's scatter more:
// on the ADIS16405 runs it lands up to 1.3 interval half-widths from
// sigma(1 s), the mean within 0.84; docs/validation.md.)
//
// Not containing 1 s: the tangent line from below (tangent_in), extended to
// 1 s. The tangent over the whole region is not used when 1 s lies inside
// it: a sensor's anti-alias or averaging filter lowers the curve at the
// shortest taus (the ADIS16405's by ~7 %), where the tangent would touch.
TermEstimate read_white(const AllanCurve& c, const std::vector<double>& slope, const std::vector<double>& rel_sigma) {
  const auto runs = regions_of_slope(c, slope, -0.5);
  if (runs.empty()) return {};
  const double at = kWhiteReadTau;
  const auto distance = [&](const Run& r) {
    if (c.tau[r.first] <= at && at <= c.tau[r.last]) return 0.0;
    return std::min(std::abs(std::log(c.tau[r.first] / at)), std::abs(std::log(c.tau[r.last] / at)));
  };
  const Run r = *std::min_element(runs.begin(), runs.end(),
                                  [&](const Run& a, const Run& b) { return distance(a) < distance(b); });
  if (distance(r) > 0.0) return tangent_in(c, r, rel_sigma, {-0.5, at, true});

  TermEstimate e;
  double sw = 0.0, swv = 0.0, swr = 0.0;
  for (std::size_t i = r.first; i <= r.last; ++i) {
    if (std::abs(std::log(c.tau[i] / at)) > std::log(kWhiteWindow) + 1e-9) continue;
    const double w = rel_sigma[i] > 0.0 ? 1.0 / (rel_sigma[i] * rel_sigma[i]) : 1.0;
    sw += w;
    swv += w * c.dev[i] * std::sqrt(c.tau[i] / at);
    swr += w * rel_sigma[i];
    if (!e.valid) e.tau_lo = c.tau[i];
    e.tau_hi = c.tau[i];
    e.valid = true;
  }
  // A sparse grid (decades) may have no point within the window.
  if (!e.valid) return tangent_in(c, r, rel_sigma, {-0.5, at, true});
  e.value = swv / sw;
  e.sigma = e.value * swr / sw;
  return e;
}

}  // namespace

SlopeReadOffs read_off_noise_terms(const AllanCurve& curve) {
  SlopeReadOffs out;
  const std::size_t n = curve.size();
  if (n == 0) return out;

  const auto slope = local_slopes(curve);
  const auto rel = running_relative_uncertainty(curve);
  out.Q = read_line(curve, slope, rel, {-1.0, std::sqrt(3.0), true});
  out.N = read_white(curve, slope, rel);
  out.K = read_line(curve, slope, rel, {+0.5, 3.0, false});
  out.R = read_line(curve, slope, rel, {+1.0, std::sqrt(2.0), false});

  // Bias instability: the lowest point of the curve, B = sigma_min / 0.664.
  const auto it = std::min_element(curve.dev.begin(), curve.dev.end());
  const auto imin = static_cast<std::size_t>(it - curve.dev.begin());
  out.sigma_min = curve.dev[imin];
  out.tau_min = curve.tau[imin];
  // The flat bottom: the contiguous points around the minimum whose interval
  // reaches down to sigma_min (their upper bound is above it by definition).
  // Without intervals a point's interval is the point itself.
  const auto reaches = [&](std::size_t i) {
    const double lo = curve.interval[i].hi > curve.interval[i].lo ? curve.interval[i].lo : curve.dev[i];
    return lo <= out.sigma_min;
  };
  std::size_t lo_i = imin;
  while (lo_i > 0 && reaches(lo_i - 1)) --lo_i;
  std::size_t hi_i = imin;
  while (hi_i + 1 < n && reaches(hi_i + 1)) ++hi_i;
  out.tau_min_lo = curve.tau[lo_i];
  out.tau_min_hi = curve.tau[hi_i];

  // Quoted with the interval of that point, as the paper reads it. (The
  // lowest of several scattered points sits a little below the curve they
  // sample.)
  out.B.value = out.sigma_min / kFlickerFloor;
  out.B.sigma = out.B.value * rel[imin];
  out.B.tau_lo = out.tau_min_lo;
  out.B.tau_hi = out.tau_min_hi;
  // A minimum at either end of the curve is no minimum: the curve is still
  // falling (bias instability not reached) or rises from the start.
  out.B.valid = imin > 0 && imin + 1 < n;
  return out;
}

}  // namespace cubecal
