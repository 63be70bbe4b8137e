// The deviations updated sample by sample against sums in long double and
// (OADEV, OHDEV) the in-memory kernels, at every factor and at points along
// the record, in memory bounded by the largest factor; a factor added later
// equal to one there from the start; bad arguments.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/realtime_deviation.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

constexpr double kTau0 = 0.5;

// A phase record: the integral of white plus random-walk frequency, on a
// large offset (the phase of a real clock is far from 0).
std::vector<double> phase(std::size_t n) {
  const auto y = test::white_plus_walk(n, kTau0, 1e-9, 1e-10, 20261128, 3e-7);
  std::vector<double> x(n + 1, 12.5);
  for (std::size_t i = 0; i < n; ++i) x[i + 1] = x[i] + y[i] * kTau0;
  return x;
}

// The deviation from sums in long double over the record: the reference.
double exact(Stat stat, const std::vector<double>& x, std::size_t m) {
  long double sum = 0.0L;
  std::size_t n = 0;
  const auto at = [&](std::size_t i) { return static_cast<long double>(x[i]); };
  const std::size_t order = stat == Stat::oadev ? 2 : 3;
  for (std::size_t i = 0; i + order * m < x.size() + (stat == Stat::tdev ? 1 : 0); ++i) {
    long double t = 0.0L;
    if (stat == Stat::oadev) {
      t = at(i + 2 * m) - 2.0L * at(i + m) + at(i);
    } else if (stat == Stat::ohdev) {
      t = at(i + 3 * m) - 3.0L * at(i + 2 * m) + 3.0L * at(i + m) - at(i);
    } else {
      for (std::size_t j = i; j < i + m; ++j) t += at(j + 2 * m) - 2.0L * at(j + m) + at(j);
    }
    sum += t * t;
    ++n;
  }
  const long double c = stat == Stat::oadev ? 2.0L : 6.0L;
  const long double scale = stat == Stat::tdev ? 1.0L : static_cast<long double>(kTau0) * kTau0;
  return static_cast<double>(std::sqrt(sum / (c * m * m * scale * n)));
}

TEST(RealtimeDeviation, EqualsExactSumsAlongTheRecord) {
  const std::vector<std::size_t> ms = {1, 3, 7, 64, 100, 1000};
  const auto x = phase(20000);
  for (Stat stat : {Stat::oadev, Stat::ohdev, Stat::tdev}) {
    RealtimeDeviation rt(stat, ms);
    std::size_t next = 0;
    for (std::size_t stop : {std::size_t{5}, std::size_t{301}, std::size_t{3001}, std::size_t{9000}, x.size()}) {
      rt.add_phase(std::span<const double>(x.data() + next, stop - next));
      next = stop;
      const std::vector<double> head(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(stop));
      for (std::size_t j = 0; j < ms.size(); ++j) {
        SCOPED_TRACE(std::string(to_string(stat)) + " m=" + std::to_string(ms[j]) + " N=" + std::to_string(stop));
        const std::size_t order = stat == Stat::oadev ? 2 : 3;
        const bool has = stat == Stat::tdev ? stop >= 3 * ms[j] : stop > order * ms[j];
        if (!has) {
          EXPECT_EQ(rt.terms(j), 0u);
          EXPECT_EQ(rt.deviation(j, kTau0), 0.0);
          continue;
        }
        EXPECT_EQ(rt.terms(j), stop - order * ms[j] + (stat == Stat::tdev ? 1 : 0));
        const double ref = exact(stat, head, ms[j]);
        EXPECT_NEAR(rt.deviation(j, kTau0), ref, 1e-10 * ref);
        if (stat != Stat::tdev) {
          // The kernels on the record less its first sample: at the offset,
          // their differences would round at 12.5's ulp.
          std::vector<double> shifted(head);
          for (double& v : shifted) v -= head[0];
          const VarianceTerm k = stat == Stat::oadev ? oavar(shifted, ms[j], kTau0) : ohvar(shifted, ms[j], kTau0);
          EXPECT_EQ(rt.terms(j), k.n);
          EXPECT_NEAR(rt.deviation(j, kTau0), std::sqrt(k.var), 1e-9 * ref);
        }
      }
    }
    EXPECT_EQ(rt.samples(), x.size());
    EXPECT_LE(rt.kept(), 2 * (3 * 1000 + 1) + 4096);
    EXPECT_EQ(rt.last_phase(), x.back());
  }
}

TEST(RealtimeDeviation, FactorAddedLaterTakesTheWholeRecord) {
  const auto x = phase(5000);
  for (Stat stat : {Stat::oadev, Stat::ohdev, Stat::tdev}) {
    const std::vector<std::size_t> ms = {2, 37};
    RealtimeDeviation from_start(stat, ms);
    RealtimeDeviation later(stat, std::vector<std::size_t>{2}, true);
    from_start.add_phase(std::span<const double>(x.data(), 2000));
    later.add_phase(std::span<const double>(x.data(), 2000));
    later.add_factor(37);
    from_start.add_phase(std::span<const double>(x.data() + 2000, x.size() - 2000));
    later.add_phase(std::span<const double>(x.data() + 2000, x.size() - 2000));
    ASSERT_EQ(later.factors(), ms);
    EXPECT_EQ(later.kept(), x.size());
    for (std::size_t j = 0; j < 2; ++j) {
      EXPECT_EQ(later.terms(j), from_start.terms(j));
      EXPECT_NEAR(later.deviation(j, kTau0), from_start.deviation(j, kTau0), 1e-12 * from_start.deviation(j, kTau0));
    }
  }
}

TEST(RealtimeDeviation, RefusesWhatItCannotDo) {
  const std::vector<std::size_t> ms = {1};
  EXPECT_THROW(RealtimeDeviation(Stat::mdev, ms), std::invalid_argument);
  EXPECT_THROW(RealtimeDeviation(Stat::oadev, std::vector<std::size_t>{0}), std::invalid_argument);
  RealtimeDeviation rt(Stat::oadev, ms);
  EXPECT_THROW(rt.add_phase(std::nan("")), std::invalid_argument);
  EXPECT_THROW(rt.add_phase(INFINITY), std::invalid_argument);
  EXPECT_EQ(rt.samples(), 0u);
  EXPECT_THROW(rt.add_factor(2), std::logic_error);
  RealtimeDeviation all(Stat::oadev, ms, true);
  EXPECT_THROW(all.add_factor(0), std::invalid_argument);
}

}  // namespace
}  // namespace cubecal
