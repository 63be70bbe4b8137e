// The streamed deviations against the in-memory ones on a record both can
// hold: exact (up to rounding) where the stride is 1 or the statistic is
// non-overlapping, within the in-memory interval where the stride is larger;
// the EDF with a stride against the overlapping and non-overlapping EDF.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/streaming_deviation.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "white_plus_walk.hpp"

namespace cubecal {
namespace {

constexpr double kTau0 = 0.01;

const std::vector<double>& record() {
  static const std::vector<double> y = test::white_plus_walk(std::size_t{1} << 22, kTau0, 0.02, 0.05, 20261123, 1.5);
  return y;
}

// The deviation at m from sums in long double over the whole record (terms
// every `step` samples): the reference both paths are held to.
double exact_dev(Stat stat, std::size_t m, std::size_t step) {
  const auto& y = record();
  static const std::vector<long double> P = [&] {
    std::vector<long double> p(y.size() + 1, 0.0L);
    for (std::size_t i = 0; i < y.size(); ++i) p[i + 1] = p[i] + static_cast<long double>(y[i]);
    return p;
  }();
  const std::size_t order = static_cast<std::size_t>(difference_order(stat));
  long double sum = 0.0L;
  std::size_t n = 0;
  for (std::size_t i = 0; i + order * m <= y.size(); i += step) {
    const long double d =
        order == 2 ? P[i + 2 * m] - 2 * P[i + m] + P[i] : P[i + 3 * m] - 3 * P[i + 2 * m] + 3 * P[i + m] - P[i];
    sum += d * d;
    ++n;
  }
  const long double md = static_cast<long double>(m);
  return static_cast<double>(std::sqrt(sum / ((order == 2 ? 2 : 6) * md * md * static_cast<long double>(n))));
}

// Pushed in uneven pieces, as a reader delivers them.
StreamingDeviation::Result streamed(Stat stat, const std::vector<std::size_t>& ms, std::size_t bound,
                                    const StabilityOptions& opt) {
  StreamingDeviation acc(stat, ms, bound);
  const auto& y = record();
  std::size_t at = 0, piece = 1;
  while (at < y.size()) {
    const std::size_t n = std::min(piece, y.size() - at);
    acc.push(std::span<const double>(y.data() + at, n));
    at += n;
    piece = piece * 7 % 100003 + 1;
  }
  EXPECT_EQ(acc.samples(), y.size());
  return acc.finish(kTau0, opt);
}

void compare(Stat stat, const char* grid, std::size_t bound) {
  SCOPED_TRACE(std::string(to_string(stat)) + " " + grid);
  const auto& y = record();
  const StabilityOptions opt;
  const StabilityRecord rec(y, DataType::freq, kTau0, stat);
  const std::vector<std::size_t> ms = averaging_factors(parse_tau_grid(grid), std::size_t{1} << 40, kTau0);
  const auto res = streamed(stat, ms, bound, opt);
  ASSERT_EQ(res.points.size(), res.strides.size());
  // The in-memory run at the factors the stream computed.
  std::vector<std::size_t> got;
  for (const auto& p : res.points) got.push_back(p.m);
  const std::vector<std::size_t> expect_ms = [&] {
    std::vector<std::size_t> v;
    for (const auto& f : streamed_factors(stat, ms, bound))
      if (f.m <= rec.max_m()) v.push_back(f.m);
    return v;
  }();
  ASSERT_EQ(got, expect_ms);
  const auto ref = rec.evaluate(got, opt);
  std::size_t exact = 0, strided = 0;
  for (std::size_t j = 0; j < ref.size(); ++j) {
    const auto& s = res.points[j];
    const auto& r = ref[j];
    SCOPED_TRACE("m = " + std::to_string(r.m) + " stride " + std::to_string(res.strides[j]));
    EXPECT_DOUBLE_EQ(s.tau, r.tau);
    const bool whole = res.strides[j] == 1 || stat == Stat::adev || stat == Stat::hdev;
    if (whole) {
      ++exact;
      EXPECT_EQ(s.n, r.n);
      const bool nonoverlapping = stat == Stat::adev || stat == Stat::hdev;
      const double want = exact_dev(stat, r.m, nonoverlapping ? r.m : 1);
      EXPECT_NEAR(s.dev, want, 1e-13 * want);
      // The in-memory kernels sum a phase over the whole record (their own
      // error is a few 1e-13 here, worse for the non-overlapping ones).
      EXPECT_NEAR(s.dev, r.dev, (nonoverlapping ? 1e-11 : 1e-12) * r.dev);
      // The same identification (lag-1 ACF) where 30 averages remain and
      // the run rule does not carry, and then the same EDF.
      if (y.size() / r.m >= 30 && !r.type_carried) {
        EXPECT_EQ(s.alpha, r.alpha);
        EXPECT_NEAR(s.edf, r.edf, 1e-9 * r.edf);
      }
    } else {
      ++strided;
      EXPECT_GE(s.dev, r.interval.lo);
      EXPECT_LE(s.dev, r.interval.hi);
      EXPECT_LT(s.n, r.n);  // fewer terms than stride 1
      // Greenhall's EDF at the stride: about the overlapping one (with a
      // partial overlap the terms are nearly as informative), at least the
      // non-overlapping one.
      if (s.alpha == r.alpha) {
        EXPECT_NEAR(s.edf, r.edf, 0.01 * r.edf);
        EXPECT_GE(s.edf, edf_for(stat == Stat::oadev ? Stat::adev : Stat::hdev, s.alpha, s.m, y.size() + 1));
      }
    }
  }
  EXPECT_GT(exact, 5u);
  if (stat == Stat::oadev || stat == Stat::ohdev) {
    EXPECT_GT(strided, 5u);
  }
}

TEST(StreamingDeviation, OadevMatchesInMemory) {
  compare(Stat::oadev, "octave", 64);
  compare(Stat::oadev, "log:10", 128);
}

TEST(StreamingDeviation, OhdevMatchesInMemory) { compare(Stat::ohdev, "log:5", 96 * 2 / 3 * 2); }

TEST(StreamingDeviation, NonOverlappingExactAtEveryLevel) {
  compare(Stat::adev, "log:10", 64);
  compare(Stat::hdev, "decade", 64);
}

TEST(StreamingDeviation, LargeBoundIsAllStrideOne) {
  const auto& y = record();
  const std::vector<std::size_t> ms = averaging_factors(parse_tau_grid("octave"), std::size_t{1} << 40, kTau0);
  const auto res = streamed(Stat::oadev, ms, std::size_t{1} << 24, {});
  const StabilityRecord rec(y, DataType::freq, kTau0, Stat::oadev);
  std::vector<std::size_t> got;
  for (const auto& p : res.points) got.push_back(p.m);
  const auto ref = rec.evaluate(got, {});
  ASSERT_EQ(res.points.size(), averaging_factors(parse_tau_grid("octave"), rec.max_m(), kTau0).size());
  for (std::size_t j = 0; j < ref.size(); ++j) {
    EXPECT_EQ(res.strides[j], 1u);
    // One pass over the whole record in one buffer: the local sums are as
    // long as the in-memory phase, and as accurate.
    const double want = exact_dev(Stat::oadev, ref[j].m, 1);
    EXPECT_NEAR(res.points[j].dev, want, 1e-12 * want) << ref[j].m;
    EXPECT_NEAR(ref[j].dev, want, 1e-12 * want) << ref[j].m;
    EXPECT_EQ(res.points[j].n, ref[j].n);
  }
}

TEST(StreamingDeviation, RefusesNonFiniteWithItsIndex) {
  StreamingDeviation acc(Stat::oadev, std::vector<std::size_t>{1, 2, 4}, 64);
  std::vector<double> y(100, 1.0);
  acc.push(y);
  y[37] = std::nan("");
  try {
    acc.push(y);
    FAIL() << "accepted a NaN";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 137 "), std::string::npos) << e.what();
  }
}

TEST(StreamingDeviation, RefusesModifiedAndTotal) {
  for (Stat s : {Stat::mdev, Stat::tdev, Stat::totdev}) {
    EXPECT_FALSE(streams(s));
    EXPECT_THROW(StreamingDeviation(s, std::vector<std::size_t>{1}, 64), std::invalid_argument);
  }
}

TEST(EdfStride, StrideOneAndStrideMAreTheExistingEstimators) {
  for (int alpha = 2; alpha >= -4; --alpha)
    for (int d = 2; d <= 3; ++d)
      for (std::size_t m : {1u, 2u, 3u, 8u, 50u, 256u, 4096u})
        for (std::size_t n : {1000u, 100000u, 10000000u}) {
          SCOPED_TRACE(std::to_string(alpha) + " " + std::to_string(d) + " " + std::to_string(m) + " " +
                       std::to_string(n));
          EXPECT_EQ(edf_greenhall_stride(alpha, d, m, n, 1, false), edf_greenhall(alpha, d, m, n, true, false));
          EXPECT_EQ(edf_greenhall_stride(alpha, d, m, n, m, false), edf_greenhall(alpha, d, m, n, false, false));
          EXPECT_EQ(edf_greenhall_stride(alpha, d, m, n, 1, true), edf_greenhall(alpha, d, m, n, true, true));
        }
}

TEST(EdfStride, BetweenOverlappingAndNot) {
  // White FM, m = 4096 on 10^7 points: a stride of 64 keeps most of the
  // overlapping estimator's degrees of freedom, more than the non-overlapping one.
  const double full = edf_greenhall_stride(0, 2, 4096, 10000000, 1, false);
  const double part = edf_greenhall_stride(0, 2, 4096, 10000000, 64, false);
  const double none = edf_greenhall_stride(0, 2, 4096, 10000000, 4096, false);
  EXPECT_LT(none, part);
  EXPECT_LE(part, full);
  EXPECT_GT(part, 0.9 * full);
  EXPECT_EQ(edf_greenhall_stride(0, 2, 4096, 10000000, 3, false), 0.0);  // not a divisor
}

}  // namespace
}  // namespace cubecal
