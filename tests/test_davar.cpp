// The dynamic Allan deviation (stats/davar.hpp, docs/formulas/davar.md):
// the fast method against the definition (the OADEV kernel on every window,
// and `dev`'s own evaluation of a window's samples), the intervals on a
// stationary record, planted changes of the noise located in time, and the
// `cubecal davar` command (formats, errors, --out, --report).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "report_check.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/davar_pipeline.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"
#include "cubecal/report/plot.hpp"
#include "cubecal/stats/davar.hpp"
#include "cubecal/stats/gap_deviation.hpp"
#include "cubecal/stats/stability.hpp"

namespace cubecal {
namespace {

namespace fs = std::filesystem;
using test::one_error_line;
using test::run_cubecal;

std::vector<double> white(std::size_t n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<double> y(n);
  for (double& v : y) v = g(rng);
  return y;
}

// White noise of `sigma_w` plus a random walk whose increments have standard
// deviation `walk_before` per sample before sample `change` and `walk_after`
// from it on (increment s moves y[s] to y[s + 1]).
std::vector<double> white_plus_walk(std::size_t n, double sigma_w, double walk_before, double walk_after,
                                    std::size_t change, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> y(n);
  double b = 0.0;
  for (std::size_t s = 0; s < n; ++s) {
    y[s] = b + sigma_w * g(rng);
    b += (s < change ? walk_before : walk_after) * g(rng);
  }
  return y;
}

TauGrid grid_of(const std::string& spec) { return parse_tau_grid(spec); }

DavarMatrix run(std::span<const double> y, DataType type, double tau0, std::size_t window, std::size_t step,
                const TauGrid& grid, DavarMethod method, bool intervals = false, std::optional<int> alpha = {}) {
  DavarOptions o;
  o.window = window;
  o.step = step;
  o.grid = grid;
  o.method = method;
  o.intervals.enabled = intervals;
  o.intervals.alpha = alpha;
  return davar(y, type, tau0, o);
}

double max_relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]) / std::abs(b[i]));
  return worst;
}

// ---------------------------------------------------------------------------
// (a) The fast method is the definition.

TEST(Davar, FastEqualsDirectOnManyWindows) {
  // 200 000 samples: white noise and a random walk whose strength drops
  // 30-fold in mid-record (a running sum that subtracted the large terms of
  // the first half would carry their rounding into the quiet second half).
  const std::size_t n = 200'000;
  const auto y = white_plus_walk(n, 1.0, 0.3, 0.01, n / 2, 11);
  const DavarMatrix fast = run(y, DataType::freq, 0.01, 4000, 37, grid_of("log:20"), DavarMethod::fast, true);
  const DavarMatrix direct = run(y, DataType::freq, 0.01, 4000, 37, grid_of("log:20"), DavarMethod::direct, true);
  ASSERT_EQ(fast.windows(), (n - 4000) / 37 + 1);
  ASSERT_GT(fast.windows(), 5000u);
  ASSERT_EQ(fast.m, direct.m);
  EXPECT_EQ(fast.m.back(), 1000u) << "the grid runs to the OADEV limit of a window, (P - 1) / 4";
  const double worst = max_relative_difference(fast.dev, direct.dev);
  std::printf("fast vs direct, %zu windows x %zu taus: max relative difference %.3g\n", fast.windows(), fast.taus(),
              worst);
  EXPECT_LT(worst, 1e-12);
  // Intervals follow the deviation: the same noise type in every cell.
  EXPECT_EQ(fast.alpha, direct.alpha);
  EXPECT_LT(max_relative_difference(fast.lo, direct.lo), 1e-12);
  EXPECT_LT(max_relative_difference(fast.hi, direct.hi), 1e-12);
  for (std::size_t j = 0; j < fast.taus(); ++j) EXPECT_EQ(fast.n[j], 4001 - 2 * fast.m[j]);
}

TEST(Davar, FastEqualsDirectForEveryBlockLayout) {
  // Steps that divide the window's terms, that do not, of one sample, and
  // longer than a window (no whole block in a window); frequency and phase.
  const auto y = white_plus_walk(10'000, 0.5, 0.05, 0.2, 7'000, 5);
  struct Case {
    std::size_t window, step;
    const char* taus;
  };
  for (DataType type : {DataType::freq, DataType::phase})
    for (const Case& c : {Case{500, 1, "all"}, Case{1000, 7, "all"}, Case{1001, 100, "all"}, Case{999, 250, "all"},
                          Case{600, 900, "all"}, Case{64, 64, "all"}, Case{10'000, 5, "log:40"}}) {
      SCOPED_TRACE("window " + std::to_string(c.window) + ", step " + std::to_string(c.step) + ", " +
                   std::string(to_string(type)));
      const DavarMatrix fast = run(y, type, 0.1, c.window, c.step, grid_of(c.taus), DavarMethod::fast);
      const DavarMatrix direct = run(y, type, 0.1, c.window, c.step, grid_of(c.taus), DavarMethod::direct);
      ASSERT_EQ(fast.dev.size(), direct.dev.size());
      EXPECT_LT(max_relative_difference(fast.dev, direct.dev), 1e-12);
      EXPECT_EQ(fast.windows(), (10'000 - c.window) / c.step + 1);
    }
}

TEST(Davar, EveryWindowIsDevOnThatWindowsSamples) {
  // The cell (tau, window) is what `dev --stat oadev` gives for the window's
  // samples alone: deviation, number of terms, noise type, EDF and interval.
  const std::size_t n = 60'000, W = 6000, S = 1500;
  const auto y = white_plus_walk(n, 1.0, 0.002, 0.02, n / 3, 3);
  const DavarMatrix mx = run(y, DataType::freq, 0.1, W, S, grid_of("log:10"), DavarMethod::fast, true);
  StabilityOptions opt;  // 68.3 %, Greenhall, identified types: as davar's defaults
  double worst = 0.0;
  for (std::size_t k = 0; k < mx.windows(); ++k) {
    const std::span<const double> window(y.data() + k * S, W);
    const StabilityRecord rec(window, DataType::freq, 0.1, Stat::oadev);
    const auto pts = rec.evaluate(mx.m, opt);
    for (std::size_t j = 0; j < mx.taus(); ++j) {
      const std::size_t c = mx.cell(j, k);
      ASSERT_EQ(pts[j].n, mx.n[j]);
      worst = std::max(worst, std::abs(mx.dev[c] - pts[j].dev) / pts[j].dev);
      EXPECT_EQ(mx.alpha[c], pts[j].alpha) << "window " << k << ", m " << mx.m[j];
      EXPECT_EQ(mx.alpha_carried[c], pts[j].type_carried);
      EXPECT_EQ(mx.edf[c], pts[j].edf);
      EXPECT_NEAR(mx.lo[c] / pts[j].interval.lo, 1.0, 1e-12);
      EXPECT_NEAR(mx.hi[c] / pts[j].interval.hi, 1.0, 1e-12);
    }
  }
  std::printf("davar vs dev on each window's samples: max relative difference %.3g\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(Davar, WindowTimes) {
  const auto y = white(1000, 1.0, 1);
  const DavarMatrix f = run(y, DataType::freq, 0.5, 100, 30, grid_of("octave"), DavarMethod::fast);
  const DavarMatrix p = run(y, DataType::phase, 0.5, 100, 30, grid_of("octave"), DavarMethod::fast);
  ASSERT_EQ(f.windows(), 31u);
  EXPECT_EQ(f.window_points, 101u);
  EXPECT_EQ(p.window_points, 100u);
  // Window k: phase points [30k, 30k + P); frequency windows span 100
  // samples (50 s), phase windows 99 intervals (49.5 s).
  EXPECT_DOUBLE_EQ(f.start[3], 45.0);
  EXPECT_DOUBLE_EQ(f.centre[3], 45.0 + 25.0);
  EXPECT_DOUBLE_EQ(p.centre[3], 45.0 + 24.75);
  EXPECT_EQ(f.m.back(), 16u);  // octave up to (101 - 1) / 4 = 25
}

TEST(Davar, RefusesWhatItCannotDo) {
  const auto y = white(1000, 1.0, 1);
  auto option_of = [&](std::size_t window, std::size_t step, const std::string& taus, DataType type = DataType::freq) {
    try {
      run(y, type, 0.1, window, step, grid_of(taus), DavarMethod::fast);
    } catch (const UsageError& e) {
      return e.field() ? std::string(cubecal::field_name(*e.field())) : std::string();
    }
    return std::string("no error");
  };
  EXPECT_EQ(option_of(3, 1, "octave"), "window");
  EXPECT_EQ(option_of(4, 1, "octave"), "no error");
  EXPECT_EQ(option_of(4, 1, "octave", DataType::phase), "window");
  EXPECT_EQ(option_of(1001, 1, "octave"), "window");
  EXPECT_EQ(option_of(100, 0, "octave"), "step");
  EXPECT_EQ(option_of(100, 10, "1000"), "taus");
  std::vector<double> bad = y;
  bad[500] = NAN;
  EXPECT_THROW(run(bad, DataType::freq, 0.1, 100, 10, grid_of("octave"), DavarMethod::fast), std::invalid_argument);
}

// ---------------------------------------------------------------------------
// (a') Missing samples (DavarOptions::skip_missing, `davar --gaps skip`):
// each cell is `dev --gaps skip` (oadev_skipping_missing) on its window.

// `y` with samples missing (NaN): single samples, a run of 40, and from
// `dense` on every fifth sample for 600 samples (no term of 2m >= 5
// frequency samples is whole there, so windows inside it have cells without
// a whole term).
std::vector<double> with_missing(std::vector<double> y, std::size_t dense) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::size_t k : {std::size_t{0}, std::size_t{17}, std::size_t{18}, std::size_t{333}, y.size() - 1})
    y[k] = nan;
  for (std::size_t k = 2000; k < 2040; ++k) y[k] = nan;
  for (std::size_t k = dense; k < dense + 600; k += 5) y[k] = nan;
  return y;
}

DavarMatrix run_skipping(std::span<const double> y, DataType type, std::size_t window, std::size_t step,
                         const std::string& taus, DavarMethod method, bool intervals, std::optional<int> alpha = {}) {
  DavarOptions o;
  o.window = window;
  o.step = step;
  o.grid = grid_of(taus);
  o.method = method;
  o.intervals.enabled = intervals;
  o.intervals.alpha = alpha;
  o.skip_missing = true;
  return davar(y, type, 0.1, o);
}

// The fast method (sums and counts of the whole terms slid over blocks)
// against the direct one (every window's whole terms summed anew), for the
// block layouts of FastEqualsDirectForEveryBlockLayout, frequency and phase;
// and the direct one against its definition, oadev_skipping_missing on the
// window's samples (to the rounding of the two phase records, the record's
// and the window's own: docs/formulas/davar.md §4.3).
TEST(Davar, MissingSamplesFastEqualsDirect) {
  const auto y = with_missing(white_plus_walk(4'000, 0.5, 0.05, 0.2, 3'000, 5), 2'500);
  struct Case {
    std::size_t window, step;
    const char* taus;
  };
  std::size_t without_value = 0;
  for (DataType type : {DataType::freq, DataType::phase})
    for (const Case& c : {Case{300, 1, "all"}, Case{1000, 7, "all"}, Case{1001, 100, "all"}, Case{999, 250, "all"},
                          Case{600, 900, "all"}, Case{64, 64, "all"}, Case{4'000, 5, "log:40"}}) {
      SCOPED_TRACE("window " + std::to_string(c.window) + ", step " + std::to_string(c.step) + ", " +
                   std::string(to_string(type)));
      const DavarMatrix fast = run_skipping(y, type, c.window, c.step, c.taus, DavarMethod::fast, false);
      const DavarMatrix direct = run_skipping(y, type, c.window, c.step, c.taus, DavarMethod::direct, false);
      ASSERT_EQ(fast.dev.size(), direct.dev.size());
      EXPECT_EQ(fast.missing, missing_samples(y));
      EXPECT_EQ(fast.terms, direct.terms);
      double worst = 0.0;
      for (std::size_t i = 0; i < fast.dev.size(); ++i) {
        ASSERT_EQ(std::isnan(fast.dev[i]), fast.terms[i] == 0) << "cell " << i;
        ASSERT_EQ(std::isnan(direct.dev[i]), direct.terms[i] == 0) << "cell " << i;
        if (fast.terms[i] == 0) {
          ++without_value;
          continue;
        }
        worst = std::max(worst, std::abs(fast.dev[i] - direct.dev[i]) / direct.dev[i]);
      }
      EXPECT_LT(worst, 1e-12);
      // The definition, on a few windows.
      StabilityOptions bare;
      bare.intervals = false;
      double from_definition = 0.0;
      for (std::size_t k = 0; k < direct.windows(); k += std::max<std::size_t>(1, direct.windows() / 7)) {
        const auto pts =
            oadev_skipping_missing(std::span<const double>(y).subspan(k * c.step, c.window), type, 0.1, direct.m, bare);
        for (std::size_t j = 0; j < direct.taus(); ++j) {
          ASSERT_EQ(direct.terms_at(j, k), pts[j].n) << "window " << k << ", m " << direct.m[j];
          if (pts[j].n > 0)
            from_definition = std::max(from_definition, std::abs(direct.dev_at(j, k) - pts[j].dev) / pts[j].dev);
        }
      }
      std::printf("%s, window %zu, step %zu: fast vs direct %.3g, direct vs oadev_skipping_missing %.3g\n",
                  std::string(to_string(type)).c_str(), c.window, c.step, worst, from_definition);
      EXPECT_LT(from_definition, 1e-12);
    }
  EXPECT_GT(without_value, 0u) << "the dense stretch leaves cells without a whole term";
}

// Every cell, intervals included, is oadev_skipping_missing (what `dev
// --gaps skip` computes) on the window's samples: terms, deviation, noise
// type (identified, or fixed), EDF and interval; windows with and without a
// missing sample alike.
TEST(Davar, MissingSamplesEachCellIsDevGapsSkipOnItsWindow) {
  const std::size_t n = 12'000, W = 1200, S = 400;
  const auto y = with_missing(white_plus_walk(n, 1.0, 0.002, 0.02, n / 3, 9), 6'000);
  for (const std::optional<int> alpha : {std::optional<int>{}, std::optional<int>{0}}) {
    SCOPED_TRACE(alpha ? "alpha fixed at 0" : "alpha identified");
    const DavarMatrix mx = run_skipping(y, DataType::freq, W, S, "log:10", DavarMethod::fast, true, alpha);
    StabilityOptions opt;  // 68.3 %, Greenhall: as davar's defaults
    opt.alpha = alpha;
    double worst = 0.0;
    std::size_t gapped_windows = 0, without_value = 0;
    for (std::size_t k = 0; k < mx.windows(); ++k) {
      const std::span<const double> window(y.data() + k * S, W);
      gapped_windows += missing_samples(window) > 0 ? 1 : 0;
      const auto pts = oadev_skipping_missing(window, DataType::freq, 0.1, mx.m, opt);
      for (std::size_t j = 0; j < mx.taus(); ++j) {
        const std::size_t c = mx.cell(j, k);
        SCOPED_TRACE("window " + std::to_string(k) + ", m " + std::to_string(mx.m[j]));
        ASSERT_EQ(mx.terms_at(j, k), pts[j].n);
        if (pts[j].n == 0) {
          ++without_value;
          EXPECT_TRUE(std::isnan(mx.dev[c]) && std::isnan(mx.lo[c]) && std::isnan(mx.hi[c]) && std::isnan(mx.edf[c]));
          continue;
        }
        worst = std::max(worst, std::abs(mx.dev[c] - pts[j].dev) / pts[j].dev);
        EXPECT_EQ(mx.alpha[c], pts[j].alpha);
        EXPECT_EQ(mx.alpha_carried[c], pts[j].type_carried);
        EXPECT_NEAR(mx.edf[c] / pts[j].edf, 1.0, 1e-12);
        EXPECT_NEAR(mx.lo[c] / pts[j].interval.lo, 1.0, 1e-12);
        EXPECT_NEAR(mx.hi[c] / pts[j].interval.hi, 1.0, 1e-12);
      }
    }
    std::printf(
        "davar vs dev --gaps skip on each window's samples: max relative difference %.3g "
        "(%zu of %zu windows with missing samples, %zu cells without a whole term)\n",
        worst, gapped_windows, mx.windows(), without_value);
    EXPECT_LT(worst, 1e-12);
    EXPECT_GT(gapped_windows, 0u);
    EXPECT_LT(gapped_windows, mx.windows()) << "whole windows too";
    EXPECT_GT(without_value, 0u);
  }
}

// A record without a NaN takes the gap-free path whether or not missing
// samples are to be skipped: the same matrix to the bit, no per-cell terms.
// An infinite sample is refused either way.
TEST(Davar, MissingSamplesOnlyWhereThereAreSome) {
  const auto y = white_plus_walk(20'000, 1.0, 0.01, 0.01, 0, 4);
  const DavarMatrix plain = run(y, DataType::freq, 0.1, 2000, 150, grid_of("log:10"), DavarMethod::fast, true);
  const DavarMatrix skipping = run_skipping(y, DataType::freq, 2000, 150, "log:10", DavarMethod::fast, true);
  EXPECT_EQ(skipping.missing, 0u);
  EXPECT_TRUE(skipping.terms.empty());
  EXPECT_EQ(plain.dev, skipping.dev);
  EXPECT_EQ(plain.lo, skipping.lo);
  EXPECT_EQ(plain.alpha, skipping.alpha);
  std::vector<double> bad = with_missing(y, 10'000);
  bad[777] = INFINITY;
  EXPECT_THROW(run_skipping(bad, DataType::freq, 2000, 150, "octave", DavarMethod::fast, false), std::invalid_argument);
  EXPECT_THROW(run_skipping(bad, DataType::freq, 2000, 150, "octave", DavarMethod::direct, false),
               std::invalid_argument);
}

// ---------------------------------------------------------------------------
// (b) A stationary record: a flat surface, each cell's interval holding the
// true deviation in the expected share of cells.

// Windows that do not overlap (step = window) are independent, so in each
// row the number of intervals that hold the truth is binomial(K, ci); the
// rows are checked one by one within 4 binomial standard deviations.
void expect_coverage(const DavarMatrix& mx, double sigma, double ci, std::size_t max_m) {
  const double K = static_cast<double>(mx.windows());
  const double sd = std::sqrt(K * ci * (1.0 - ci));
  for (std::size_t j = 0; j < mx.taus() && mx.m[j] <= max_m; ++j) {
    // White FM, unit samples: AVAR(m) = sigma^2 / m exactly.
    const double truth = sigma / std::sqrt(static_cast<double>(mx.m[j]));
    std::size_t held = 0;
    double mean_var = 0.0;
    for (std::size_t k = 0; k < mx.windows(); ++k) {
      const std::size_t c = mx.cell(j, k);
      held += mx.lo[c] <= truth && truth <= mx.hi[c];
      mean_var += mx.dev[c] * mx.dev[c] / K;
    }
    std::printf("  m %4zu: %zu of %.0f intervals hold the truth (expected %.1f +- %.1f); mean variance / truth %.4f\n",
                mx.m[j], held, K, K * ci, sd, mean_var / (truth * truth));
    EXPECT_NEAR(static_cast<double>(held), K * ci, 4.0 * sd) << "m = " << mx.m[j];
  }
}

TEST(Davar, StationaryWhiteNoiseIsFlatWithinItsIntervals) {
  const std::size_t W = 4000, K = 250;
  const double sigma = 2.5;
  const auto y = white(W * K, sigma, 21);
  // Factors with at least 8 averages in a window; below m = 10 Greenhall's
  // continuous-time EDF runs high for sampled white FM
  // (docs/formulas/stability.md §5.5), so the check starts at 10.
  TauGrid g;
  g.kind = TauGrid::Kind::list;
  g.taus = {1.0, 2.0, 5.0, 10.0, 20.0, 50.0};  // m = 10 .. 500 at 10 Hz
  std::printf("fixed alpha = 0:\n");
  const DavarMatrix fixed = run(y, DataType::freq, 0.1, W, W, g, DavarMethod::fast, true, 0);
  ASSERT_EQ(fixed.windows(), K);
  expect_coverage(fixed, sigma, 0.683, 500);
  // Identified in each cell: where at least 30 averages remain (m <= 133),
  // the lag-1 method calls white FM and the coverage is the same; below, the
  // B1 ratio of 8 to 20 averages scatters over the neighbouring types
  // (docs/formulas/stability.md §4.6), and the share is not checked.
  std::printf("noise type identified in each cell:\n");
  const DavarMatrix identified = run(y, DataType::freq, 0.1, W, W, g, DavarMethod::fast, true);
  expect_coverage(identified, sigma, 0.683, W / 30);
  std::size_t white_fm = 0, cells = 0;
  for (std::size_t j = 0; j < identified.taus() && identified.m[j] <= W / 30; ++j)
    for (std::size_t k = 0; k < K; ++k, ++cells) white_fm += identified.alpha[identified.cell(j, k)] == 0;
  EXPECT_GE(static_cast<double>(white_fm), 0.95 * static_cast<double>(cells)) << white_fm << " of " << cells;
}

// ---------------------------------------------------------------------------
// (c), (d) A planted change located within one step.
//
// Located: at the chosen tau, the variance (dev^2) of a window is the
// term-weighted mean of its two parts, so it crosses the midpoint of the two
// levels (v_before + v_after) / 2 when the window is centred on the change.
// The located time is the crossing interpolated linearly between the centres
// of the two windows around the first (and only) crossing; it must lie within
// one step of the planted change.
struct Located {
  std::size_t crossings = 0;
  double time = NAN;
};

Located locate(const DavarMatrix& mx, std::size_t j, double v_before, double v_after) {
  const double mid = 0.5 * (v_before + v_after);
  Located out;
  auto side = [&](std::size_t k) { return (mx.dev_at(j, k) * mx.dev_at(j, k) - mid) * (v_after - v_before) >= 0.0; };
  for (std::size_t k = 1; k < mx.windows(); ++k)
    if (side(k) != side(k - 1)) {
      if (++out.crossings > 1) continue;
      const double a = mx.dev_at(j, k - 1) * mx.dev_at(j, k - 1) - mid, b = mx.dev_at(j, k) * mx.dev_at(j, k) - mid;
      out.time = mx.centre[k - 1] + (mx.centre[k] - mx.centre[k - 1]) * a / (a - b);
    }
  return out;
}

TEST(Davar, LocatesAChangeOfWhiteNoiseLevel) {
  // 2 h at 10 Hz; sigma 1 then 3 from 4321.7 s on; 10 min windows every
  // 60 s. (Over seeds 1 to 400 the located time was 10.8 s rms from the
  // planted one, 34.7 s at most.)
  const double tau0 = 0.1, sigma1 = 1.0, sigma2 = 3.0;
  const std::size_t n = 72'000, change = 43'217, W = 6000, S = 600;
  std::vector<double> y = white(n, 1.0, 33);
  for (std::size_t i = 0; i < n; ++i) y[i] *= i < change ? sigma1 : sigma2;
  const DavarMatrix mx = run(y, DataType::freq, tau0, W, S, grid_of("octave"), DavarMethod::fast);
  ASSERT_EQ(mx.m[0], 1u);
  // At m = 1: AVAR = sigma^2 on either side.
  const Located at = locate(mx, 0, sigma1 * sigma1, sigma2 * sigma2);
  const double planted = static_cast<double>(change) * tau0, step = static_cast<double>(S) * tau0;
  std::printf("white-noise level change at %.1f s located at %.1f s (%+.1f s, step %.0f s, %zu crossing)\n", planted,
              at.time, at.time - planted, step, at.crossings);
  EXPECT_EQ(at.crossings, 1u);
  EXPECT_LE(std::abs(at.time - planted), step);
}

TEST(Davar, LocatesAChangeOfRandomWalkStrength) {
  // White noise 0.01 and a rate random walk of 0.02 per sample, 0.06 from
  // 3987.3 s on; 5 min windows every 60 s. At m = 4 the walk dominates
  // (AVAR = q (2m^2 + 1) / (6m) + sigma^2 / m: 5.75e-4 then 4.98e-3) and
  // triples its deviation. (Over seeds 1 to 400 the located time was 12.2 s
  // rms from the planted one, 37.5 s at most.)
  const double tau0 = 0.1, sw = 0.01, q1 = 0.02 * 0.02, q2 = 0.06 * 0.06;
  const std::size_t n = 72'000, change = 39'873, W = 3000, S = 600;
  const auto y = white_plus_walk(n, sw, 0.02, 0.06, change, 44);
  const DavarMatrix mx = run(y, DataType::freq, tau0, W, S, grid_of("octave"), DavarMethod::fast);
  ASSERT_EQ(mx.m[2], 4u);
  const double m = 4.0;
  auto level = [&](double q) { return q * (2.0 * m * m + 1.0) / (6.0 * m) + sw * sw / m; };
  const Located at = locate(mx, 2, level(q1), level(q2));
  const double planted = static_cast<double>(change) * tau0, step = static_cast<double>(S) * tau0;
  std::printf("random-walk change at %.1f s located at %.1f s (%+.1f s, step %.0f s, %zu crossing)\n", planted, at.time,
              at.time - planted, step, at.crossings);
  EXPECT_EQ(at.crossings, 1u);
  EXPECT_LE(std::abs(at.time - planted), step);
  // Far from the change the surface sits at the two levels (within 4 times
  // the relative standard deviation sqrt(2 / EDF) of a window's variance).
  const double edf = edf_for(Stat::oadev, -2, 4, W + 1);
  const double tol = 4.0 * std::sqrt(2.0 / edf);
  for (std::size_t k : {std::size_t{0}, std::size_t{1}})
    EXPECT_NEAR(mx.dev_at(2, k) * mx.dev_at(2, k) / level(q1), 1.0, tol);
  const std::size_t last = mx.windows() - 1;
  EXPECT_NEAR(mx.dev_at(2, last) * mx.dev_at(2, last) / level(q2), 1.0, tol);
}

// ---------------------------------------------------------------------------
// (e) The command.

class DavarCli : public test::TempDirTest {
 protected:
  // t, gx, gy at 10 Hz: gx white 1 then 3 from the middle, gy white 0.5.
  std::string record(std::size_t n = 12'000) {
    gx_ = white(n, 1.0, 7);
    for (std::size_t i = n / 2; i < n; ++i) gx_[i] *= 3.0;
    gy_ = white(n, 0.5, 8);
    std::string s = "t,gx,gy\n";
    char line[128];
    for (std::size_t i = 0; i < n; ++i) {
      std::snprintf(line, sizeof line, "%.1f,%.17g,%.17g\n", 0.1 * static_cast<double>(i), gx_[i], gy_[i]);
      s += line;
    }
    return write("rec.csv", s);
  }
  std::vector<double> gx_, gy_;
};

TEST_F(DavarCli, CsvJsonAndTable) {
  const std::string f = record();
  // 1 200 s with 5 min windows every 60 s: 16 windows; octave taus up to m = 750.
  const auto csv = run_cubecal("davar " + f + " --window 5min --step 60s --taus octave --format csv");
  ASSERT_EQ(csv.code, 0) << csv.err;
  std::istringstream in(csv.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "channel,t,tau,dev,n,lo,hi,edf,alpha");
  std::size_t rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 2u * 16u * 10u);  // channels x windows x taus (m = 1 .. 512)

  const auto json = run_cubecal("davar " + f + " --window 3000 --step 600 --taus octave --format json --no-ci");
  ASSERT_EQ(json.code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["command"], "davar");
  EXPECT_EQ(j["window"]["samples"], 3000);
  EXPECT_EQ(j["step"]["samples"], 600);
  EXPECT_EQ(j["windows"], 16);
  ASSERT_EQ(j["channels"].size(), 2u);
  EXPECT_EQ(j["channels"][0]["name"], "gx");
  EXPECT_FALSE(j["channels"][0].contains("lo"));
  // The library call on the same numbers gives the same matrix.
  DavarOptions o;
  o.window = 3000;
  o.step = 600;
  o.grid = grid_of("octave");
  const DavarMatrix mx = davar(gx_, DataType::freq, 0.1, o);
  const auto& dev = j["channels"][0]["dev"];
  ASSERT_EQ(dev.size(), mx.taus());
  for (std::size_t t = 0; t < mx.taus(); ++t) {
    ASSERT_EQ(dev[t].size(), mx.windows());
    for (std::size_t k = 0; k < mx.windows(); ++k) EXPECT_DOUBLE_EQ(dev[t][k].get<double>(), mx.dev_at(t, k));
  }
  EXPECT_DOUBLE_EQ(j["channels"][0]["t"][1].get<double>(), mx.centre[1]);

  const auto table = run_cubecal("davar " + f + " --window 5min --step 1min --columns gy");
  ASSERT_EQ(table.code, 0) << table.err;
  EXPECT_NE(table.out.find("gy"), std::string::npos);
  EXPECT_NE(table.out.find("max/min"), std::string::npos);
  EXPECT_EQ(table.out.find("# " + f + ": gx"), std::string::npos) << "--columns gy only";
}

// `davar --gaps skip`: empty fields, NaN and rows never logged are missing
// samples; each column of the matrix is `dev --gaps skip` run on that
// window's samples (written to a file of their own), to 1e-12 relative,
// intervals included; a cell without a whole term is null in JSON (dev
// has no point there) and has empty fields in CSV.
TEST_F(DavarCli, GapsSkipEachColumnIsDevGapsSkipOnItsWindow) {
  const std::size_t n = 2400, W = 400, S = 250;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> gx = white(n, 1.0, 21), gy = white(n, 0.5, 22);
  gx[130] = nan;                                                  // an empty field
  gx[700] = gy[700] = nan;                                        // NaN
  for (std::size_t k = 1000; k < 1003; ++k) gx[k] = gy[k] = nan;  // rows never logged
  for (std::size_t k = 1500; k < 2000; k += 5) gx[k] = nan;       // every fifth sample, empty
  std::string text = "t,gx,gy\n";
  char line[160];
  const auto field = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return std::isnan(v) ? std::string() : std::string(b);
  };
  for (std::size_t k = 0; k < n; ++k) {
    if (k >= 1000 && k < 1003) continue;
    std::snprintf(line, sizeof line, "%.1f,%s,%s\n", 0.1 * static_cast<double>(k),
                  k == 700 ? "NaN" : field(gx[k]).c_str(), k == 700 ? "nan" : field(gy[k]).c_str());
    text += line;
  }
  const std::string f = write("holes.csv", text);
  const std::string args = " --window 400 --step 250 --taus octave --gaps skip";
  const auto r = run_cubecal("davar " + f + args + " --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::size_t missing = missing_samples(gx) + missing_samples(gy);
  EXPECT_NE(r.err.find(std::to_string(missing) + " missing sample(s)"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["missing_samples"], missing);
  ASSERT_EQ(j["windows"], (n - W) / S + 1);
  std::size_t nulls = 0, compared = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < (n - W) / S + 1; ++k) {
    std::string win = "gx,gy\n";
    for (std::size_t i = k * S; i < k * S + W; ++i) {
      std::snprintf(line, sizeof line, "%.17g,%.17g\n", gx[i], gy[i]);  // NaN as "nan"
      win += line;
    }
    const auto d = run_cubecal("dev " + write("w.csv", win) + " --rate 10 --taus octave --gaps skip --format json");
    ASSERT_EQ(d.code, 0) << d.err;
    const auto dj = nlohmann::json::parse(d.out);
    for (std::size_t c = 0; c < 2; ++c) {
      const auto& ch = j["channels"][c];
      const auto& col = dj["columns"][c];
      ASSERT_EQ(ch["name"], col["name"]);
      // dev's factors are among davar's (the same grid and limit on a window).
      for (const auto& af : col["af"])
        EXPECT_NE(std::find(ch["m"].begin(), ch["m"].end(), af), ch["m"].end()) << "dev's factor " << af;
      for (std::size_t t = 0; t < ch["m"].size(); ++t) {
        SCOPED_TRACE("window " + std::to_string(k) + ", " + ch["name"].get<std::string>() + ", m " +
                     std::to_string(ch["m"][t].get<std::size_t>()));
        const std::size_t terms =
            ch.contains("terms") ? ch["terms"][t][k].get<std::size_t>() : ch["n"][t].get<std::size_t>();
        // dev's point at this factor: none where the window has no whole term
        // (dev leaves the factor out, as for a factor no segment holds).
        std::size_t p = 0;
        while (p < col["af"].size() && col["af"][p] != ch["m"][t]) ++p;
        if (p == col["af"].size()) {
          ++nulls;
          EXPECT_EQ(terms, 0u);
          for (const char* key : {"dev", "lo", "hi", "edf", "alpha"}) EXPECT_TRUE(ch[key][t][k].is_null()) << key;
          continue;
        }
        ++compared;
        EXPECT_GT(col["n"][p].get<std::size_t>(), 0u) << "dev printed a factor without a term";
        EXPECT_EQ(terms, col["n"][p].get<std::size_t>());
        const double want = col["dev"][p].get<double>();
        worst = std::max(worst, std::abs(ch["dev"][t][k].get<double>() - want) / want);
        EXPECT_EQ(ch["alpha"][t][k], col["alpha"][p]);
        for (const char* key : {"lo", "hi", "edf"})
          EXPECT_NEAR(ch[key][t][k].get<double>() / col[key][p].get<double>(), 1.0, 1e-12) << key;
      }
    }
  }
  std::printf(
      "davar --gaps skip vs dev --gaps skip on each window: %zu cells, max relative difference %.3g, "
      "%zu cells without a whole term\n",
      compared, worst, nulls);
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(nulls, 0u);
  EXPECT_GT(compared, 100u);

  // CSV: the same cells without a value, as empty fields (n = 0).
  const auto csv = run_cubecal("davar " + f + args + " --format csv");
  ASSERT_EQ(csv.code, 0) << csv.err;
  std::istringstream in(csv.out);
  std::string row;
  std::size_t empty_rows = 0;
  while (std::getline(in, row)) {
    std::vector<std::string> cells;
    std::stringstream fields(row);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (row.back() == ',') cells.emplace_back();
    ASSERT_EQ(cells.size(), 9u) << row;
    if (cells[3].empty()) {
      ++empty_rows;
      EXPECT_EQ(cells[4], "0") << row;
      for (std::size_t i = 5; i < 9; ++i) EXPECT_TRUE(cells[i].empty()) << row;
    }
  }
  EXPECT_EQ(empty_rows, nulls);
  // The table takes cells without a value.
  EXPECT_EQ(run_cubecal("davar " + f + args).code, 0);
  // Without --gaps skip the empty field is refused at its place.
  const auto refused = run_cubecal("davar " + f + " --window 400 --step 250");
  EXPECT_TRUE(one_error_line(refused)) << refused.err;
  EXPECT_NE(refused.err.find(f + ":132:"), std::string::npos) << refused.err;
}

// The report's per-tau spread table on a gapped record: gx misses every
// fifth sample from 1000 to 1600, so a window inside that stretch has no
// whole term from m = 3 on (no 6 whole samples in a row). Such cells are
// left out of the smallest, median and largest and counted in a column of
// their own; the terms are the range of the counts of the other cells. gy,
// whole, keeps the table of a record without gaps.
TEST_F(DavarCli, GapsSkipSpreadTableLeavesOutCellsWithoutATerm) {
  const std::size_t n = 3000;
  std::vector<double> gx = white(n, 1.0, 31), gy = white(n, 0.5, 32);
  for (std::size_t k = 1000; k < 1600; k += 5) gx[k] = std::numeric_limits<double>::quiet_NaN();
  std::string text = "t,gx,gy\n";
  char line[128];
  for (std::size_t k = 0; k < n; ++k) {
    if (std::isnan(gx[k]))
      std::snprintf(line, sizeof line, "%.1f,,%.17g\n", 0.1 * static_cast<double>(k), gy[k]);  // an empty field
    else
      std::snprintf(line, sizeof line, "%.1f,%.17g,%.17g\n", 0.1 * static_cast<double>(k), gx[k], gy[k]);
    text += line;
  }
  const std::string f = write("holes.csv", text);
  io::SeriesOptions so;
  so.gaps = io::GapPolicy::skip;
  const io::Series series = io::read_series(f, so);
  pipeline::DavarRequest req;
  req.window = pipeline::parse_davar_span("600", cubecal::Field::window);
  req.step = pipeline::parse_davar_span("100", cubecal::Field::step);
  req.grid = grid_of("octave");
  const pipeline::DavarResult res = pipeline::run_davar(series, req);
  const report::CommandReport rep = report::davar_report(res, "cubecal davar holes.csv --gaps skip");
  ASSERT_EQ(rep.sections.size(), 2u);
  bool listed = false;
  for (const auto& field : rep.input) listed |= field.label == "missing samples" && field.value.rfind("120 ", 0) == 0;
  EXPECT_TRUE(listed) << "the input lists the 120 missing samples";
  std::size_t empty_total = 0;
  for (std::size_t c = 0; c < 2; ++c) {
    const DavarMatrix& mx = res.channels[c].matrix;
    const bool gapped = c == 0;
    ASSERT_EQ(mx.terms.empty(), !gapped);
    std::optional<report::ReportTable> table;
    for (const auto& block : rep.sections[c].blocks)
      if (block.table) table = block.table;
    ASSERT_TRUE(table) << res.channels[c].name;
    ASSERT_EQ(table->header.size(), gapped ? 9u : 8u);
    if (gapped) {
      EXPECT_EQ(table->header.back(), "windows without a term");
    }
    ASSERT_EQ(table->rows.size(), mx.taus());
    const std::size_t K = mx.windows();
    for (std::size_t j = 0; j < mx.taus(); ++j) {
      SCOPED_TRACE(res.channels[c].name + ", m " + std::to_string(mx.m[j]));
      const auto& row = table->rows[j];
      ASSERT_EQ(row.size(), table->header.size());
      // The cells with a value, ranked here by a full sort.
      std::vector<std::pair<double, std::size_t>> cells;
      std::size_t fewest = std::numeric_limits<std::size_t>::max(), most = 0;
      for (std::size_t k = 0; k < K; ++k) {
        const double d = mx.dev_at(j, k);
        if (std::isnan(d)) continue;
        cells.emplace_back(d, k);
        const std::size_t terms = gapped ? mx.terms[mx.cell(j, k)] : mx.n[j];
        fewest = std::min(fewest, terms);
        most = std::max(most, terms);
      }
      std::sort(cells.begin(), cells.end());
      const std::size_t empty = K - cells.size();
      empty_total += empty;
      if (gapped) {
        EXPECT_EQ(row.back(), std::to_string(empty));
      }
      ASSERT_FALSE(cells.empty());
      EXPECT_EQ(row[1], fewest == most ? std::to_string(most) : std::to_string(fewest) + "–" + std::to_string(most));
      if (!gapped) {
        EXPECT_EQ(row[1], std::to_string(mx.n[j]));
      }
      EXPECT_EQ(row[2], report::format_num(cells.front().first, 4));
      EXPECT_EQ(row[3], report::format_num(mx.centre[cells.front().second], 6));
      EXPECT_EQ(row[4], report::format_num(cells[cells.size() / 2].first, 4));
      EXPECT_EQ(row[5], report::format_num(cells.back().first, 4));
      EXPECT_EQ(row[6], report::format_num(mx.centre[cells.back().second], 6));
      EXPECT_EQ(row[7], report::format_num(cells.back().first / cells.front().first, 4));
      // Window 10 (samples 1000-1599) has no 6 whole gx samples in a row.
      if (gapped && mx.m[j] >= 3) {
        EXPECT_TRUE(std::isnan(mx.dev_at(j, 10)));
      } else {
        EXPECT_EQ(empty, 0u);
      }
    }
  }
  EXPECT_GT(empty_total, 0u);

  // The command writes the page with that table.
  if (!report::find_gnuplot()) return;
  const std::string dir = path("rep");
  const auto r = run_cubecal("davar " + f + " --gaps skip --window 600 --step 100 --taus octave --report " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = test::slurp(fs::path(dir) / "report.html");
  EXPECT_NE(html.find("windows without a term"), std::string::npos);
  EXPECT_NE(html.find("missing samples"), std::string::npos);
}

TEST_F(DavarCli, BadInputIsOneLineExitTwo) {
  const std::string f = record(2000);
  const std::string broken = write("broken.csv", "t,gx\n0,1\n0.1,2\n0.2,abc\n0.3,4\n");
  for (const std::string& args :
       {"davar " + path("missing.csv"), "davar " + f + " --window 0", "davar " + f + " --window abc",
        "davar " + f + " --window 2h", "davar " + f + " --step 0s", "davar " + f + " --step 0",
        "davar " + f + " --window 10s --taus 1000", "davar " + f + " --taus log:x", "davar " + broken,
        "davar " + f + " --alpha 3", "davar " + f + " --format xml"}) {
    const auto r = run_cubecal(args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_TRUE(one_error_line(r)) << args << "\n" << r.err;
  }
  EXPECT_NE(run_cubecal("davar " + f + " --window 2h").err.find("--window: "), std::string::npos);
  // A record cut at a gap: one window slides along one contiguous record.
  std::string gapped = "t,gx\n";
  for (int i = 0; i < 400; ++i)
    gapped += std::to_string(0.1 * (i < 200 ? i : i + 50)) + "," + std::to_string(i % 7) + "\n";
  const auto split = run_cubecal("davar " + write("gapped.csv", gapped) + " --gaps split --window 50");
  EXPECT_EQ(split.code, 2);
  EXPECT_TRUE(one_error_line(split)) << split.err;
  EXPECT_NE(split.err.find("--gaps: "), std::string::npos) << split.err;
  EXPECT_NE(run_cubecal("davar " + broken).err.find("broken.csv:4:"), std::string::npos);
}

TEST_F(DavarCli, OutNeedsForce) {
  const std::string f = record(2000);
  const std::string out = write("out.csv", "keep me\n");
  const auto r = run_cubecal("davar " + f + " --window 60s --format csv --out " + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(one_error_line(r)) << r.err;
  std::ifstream kept(out);
  std::string first;
  std::getline(kept, first);
  EXPECT_EQ(first, "keep me");
  const auto forced = run_cubecal("davar " + f + " --window 60s --format csv --out " + out + " --force");
  ASSERT_EQ(forced.code, 0) << forced.err;
  std::ifstream replaced(out);
  std::getline(replaced, first);
  EXPECT_EQ(first, "channel,t,tau,dev,n,lo,hi,edf,alpha");
}

TEST_F(DavarCli, ReportHeatMap) {
  if (!report::find_gnuplot()) GTEST_SKIP() << "gnuplot not installed: install gnuplot-nox (scripts/install-deps.sh)";
  const std::string f = record();
  const std::string dir = path("rep");
  const auto r = run_cubecal("davar " + f + " --window 2min --step 10s --taus octave --report " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path d(dir);
  for (const char* ch : {"gx", "gy"})
    for (const char* kind : {"davar_map_", "davar_time_"})
      for (const char* ext : {".dat", ".gp", ".svg", ".png"})
        EXPECT_TRUE(fs::exists(d / "plots" / (std::string(kind) + ch + ext))) << kind << ch << ext;
  std::ifstream page(d / "report.html");
  std::stringstream html;
  html << page.rdbuf();
  EXPECT_EQ(test::count(html.str(), "data:image/svg+xml;base64,"), 4u) << "the plots inline";
  EXPECT_NE(html.str().find("Dynamic Allan deviation"), std::string::npos);

  // The map: in the row of the smallest tau (0.1 s), every run of columns
  // at one colour level that reaches into the windows wholly before the
  // change (600 s) is of a lower level than every run that reaches into the
  // windows wholly after it (gx triples its noise there). A run is the pair
  // of rows x, y, lo, hi with hi > lo (its left and right edges) of a block.
  std::ifstream dat(d / "plots" / "davar_map_gx.dat");
  std::string line;
  int level = -1;
  int highest_before = -1, lowest_after = 1000;
  std::size_t before = 0, after = 0;
  std::vector<double> edges;
  while (std::getline(dat, line)) {
    if (line.rfind("# index ", 0) == 0) {
      const auto at = line.find(": level ");
      ASSERT_NE(at, std::string::npos) << line;
      level = std::stoi(line.substr(at + 8));
      edges.clear();
      continue;
    }
    if (line.empty() || line[0] == '#') continue;
    double x, y, lo, hi;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf %lf %lf %lf", &x, &y, &lo, &hi), 4) << line;
    if (!(hi > lo) || !(lo <= 0.1 && 0.1 <= hi)) continue;
    edges.push_back(x * 60.0);  // the axis is in minutes for a 20 min record
    if (edges.size() < 2) continue;
    const double left = edges[0], right = edges[1];
    edges.clear();
    ASSERT_LT(left, right);
    if (left < 600.0 - 60.0) {  // a window centred before 540 s ends before the change
      highest_before = std::max(highest_before, level);
      ++before;
    }
    if (right > 600.0 + 60.0) {
      lowest_after = std::min(lowest_after, level);
      ++after;
    }
  }
  EXPECT_GE(before, 1u);
  EXPECT_GE(after, 1u);
  EXPECT_LT(highest_before, lowest_after);

  // An existing report is not replaced without --force.
  const auto again = run_cubecal("davar " + f + " --window 2min --step 10s --report " + dir);
  EXPECT_EQ(again.code, 2);
  EXPECT_TRUE(one_error_line(again)) << again.err;
  EXPECT_EQ(run_cubecal("davar " + f + " --window 2min --step 10s --report " + dir + " --force").code, 0);
}

}  // namespace
}  // namespace cubecal
