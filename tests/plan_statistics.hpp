// The statistics a Monte Carlo of the record plan compares with the plan
// (docs/formulas/planning.md §0, §3), shared by tests/test_plan_monte_carlo.cpp
// and bench/plan_validation.cpp: moments with the standard error of the sd,
// B's and T's central intervals, and a bootstrap standard error.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace cubecal::plan_statistics {

// Mean, sd and the standard error of the sd from the sample's own fourth
// moment (any distribution: the estimates of B and T are skewed):
// Var(s^2) ~ (m4 - (n - 3) / (n - 1) s^4) / n, SE(s) = SE(s^2) / (2 s).
struct Moments {
  double n = 0.0, mean = 0.0, sd = 0.0, sd_se = 0.0;
};
inline Moments moments(const std::vector<double>& v) {
  Moments m;
  m.n = static_cast<double>(v.size());
  for (double x : v) m.mean += x / m.n;
  double m2 = 0.0, m4 = 0.0;
  for (double x : v) {
    const double d = x - m.mean;
    m2 += d * d / m.n;
    m4 += d * d * d * d / m.n;
  }
  const double var = m2 * m.n / (m.n - 1.0);
  m.sd = std::sqrt(var);
  m.sd_se =
      m.sd > 0.0 ? std::sqrt(std::max(0.0, (m4 - (m.n - 3.0) / (m.n - 1.0) * var * var) / m.n)) / (2.0 * m.sd) : 0.0;
  return m;
}

// Linear-interpolated quantile of sorted values (as MinimumSpread::b_half_width reads its draws).
inline double quantile(const std::vector<double>& sorted, double p) {
  const double x = p * static_cast<double>(sorted.size() - 1);
  const auto i = static_cast<std::size_t>(x);
  const double f = x - static_cast<double>(i);
  return i + 1 < sorted.size() ? sorted[i] * (1 - f) + sorted[i + 1] * f : sorted.back();
}

// B's precision as the plan states it: half the central 68.3 % interval over the median.
inline double b_half_width(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return 0.5 * (quantile(v, 0.8415) - quantile(v, 0.1585)) / quantile(v, 0.5);
}

// T's: half the central 68.3 % interval of ln T, each record's T uniform over
// its tau's cell ({lo, hi} in ln tau).
inline double t_half_width(std::vector<std::array<double, 2>> cells) {
  std::sort(cells.begin(), cells.end());
  std::vector<std::array<double, 3>> law;  // lo, hi, probability
  for (const auto& c : cells) {
    if (law.empty() || law.back()[0] != c[0]) law.push_back({c[0], c[1], 0.0});
    law.back()[2] += 1.0 / static_cast<double>(cells.size());
  }
  const auto q = [&](double p) {
    double cum = 0.0;
    for (const auto& c : law) {
      if (cum + c[2] >= p) return c[0] + (p - cum) / c[2] * (c[1] - c[0]);
      cum += c[2];
    }
    return law.back()[1];
  };
  return 0.5 * (q(0.8415) - q(0.1585));
}

// The standard error of a statistic of the records: 400 bootstrap resamples (fixed seed).
template <class T, class F>
double bootstrap_se(const std::vector<T>& v, F statistic) {
  std::mt19937_64 engine(952);
  std::uniform_int_distribution<std::size_t> pick(0, v.size() - 1);
  std::vector<double> reps;
  std::vector<T> r(v.size());
  for (int b = 0; b < 400; ++b) {
    for (auto& x : r) x = v[pick(engine)];
    reps.push_back(statistic(r));
  }
  return moments(reps).sd;
}

}  // namespace cubecal::plan_statistics
