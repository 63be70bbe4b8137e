// median_interval: the exact median of the intervals, whichever path it
// takes (the bracket from a sample, or all intervals when the bracket
// misses), against a plain sort of every interval.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

#include "cubecal/stats/sampling.hpp"

namespace {

double sorted_median(const std::vector<double>& t) {
  std::vector<double> dt;
  for (std::size_t i = 1; i < t.size(); ++i) dt.push_back(t[i] - t[i - 1]);
  std::sort(dt.begin(), dt.end());
  const std::size_t n = dt.size();
  return n % 2 != 0 ? dt[n / 2] : 0.5 * (dt[n / 2 - 1] + dt[n / 2]);
}

std::vector<double> stamps(std::size_t n, auto&& interval) {
  std::vector<double> t(n);
  for (std::size_t i = 1; i < n; ++i) t[i] = t[i - 1] + interval(i);
  return t;
}

TEST(MedianInterval, EqualsTheSortedMedianOnJitteredStamps) {
  for (const std::size_t n : {3UL, 4UL, 1000UL, 40'001UL, 200'000UL, 200'001UL}) {
    std::mt19937_64 rng(n);
    std::normal_distribution<double> jitter(0.0, 1e-4);
    const auto t = stamps(n, [&](std::size_t) { return 0.01 + jitter(rng); });
    EXPECT_EQ(cubecal::median_interval(t), sorted_median(t)) << n;
  }
}

TEST(MedianInterval, EqualsTheSortedMedianOnPrintedStamps) {
  // Stamps printed with two decimals: a handful of distinct intervals, most
  // of them tied at the median.
  for (const std::size_t n : {100'000UL, 100'001UL}) {
    std::vector<double> t(n);
    for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(static_cast<long long>(i) * 10) / 100.0;
    EXPECT_EQ(cubecal::median_interval(t), sorted_median(t)) << n;
  }
}

TEST(MedianInterval, EqualsTheSortedMedianWhenTheSampleMissesIt) {
  // Rates that change half-way, and a pattern whose period is the sample's
  // stride: the sample brackets the wrong intervals, and the exact answer
  // must still come out.
  const std::size_t n = 300'000;
  const auto halves =
      stamps(n, [&](std::size_t i) { return i < n / 2 ? 0.01 : 0.02 + 1e-9 * static_cast<double>(i % 7); });
  EXPECT_EQ(cubecal::median_interval(halves), sorted_median(halves));
  const std::size_t stride = (n - 1) / 4096;
  const auto aliased =
      stamps(n, [&](std::size_t i) { return (i - 1) % stride == 0 ? 0.5 : 0.01 + 1e-9 * static_cast<double>(i % 5); });
  EXPECT_EQ(cubecal::median_interval(aliased), sorted_median(aliased));
}

TEST(MedianInterval, RefusesFewerThanTwoStamps) {
  EXPECT_THROW(cubecal::median_interval(std::vector<double>{1.0}), std::invalid_argument);
}

}  // namespace
