#include "cubecal/stats/phase.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "../detail/magnitude.hpp"
#include "../detail/huge_pages.hpp"

namespace cubecal {

std::vector<double> freq_to_phase(std::span<const double> y, double tau0, double scale) {
  std::vector<double> x;
  x.reserve(y.size() + 1);
  detail::advise_huge_pages(x.data(), (y.size() + 1) * sizeof(double));
  x.resize(y.size() + 1, 0.0);
  if (y.empty()) return x;
  const double inv = 1.0 / scale;
  // Two-pass mean (accurate for long records), then the running sum.
  double mean = 0.0;
  for (double v : y) mean += v * inv;
  mean /= static_cast<double>(y.size());
  double acc = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    acc += (y[i] * inv - mean) * tau0;
    x[i + 1] = acc;
  }
  return x;
}

std::vector<double> normalize_phase(std::span<const double> x, double scale) {
  std::vector<double> out(x.size());
  if (out.empty()) return out;
  const double inv = 1.0 / scale;
  const double x0 = x.front() * inv;
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = x[i] * inv - x0;
  return out;
}

double power_of_two_scale(std::span<const double> v) {
  const Magnitude m = largest_magnitude(v);
  if (!m.finite)
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k])) throw std::invalid_argument("sample " + std::to_string(k) + " is not a finite number");
  return m.largest > 0.0 ? std::ldexp(1.0, std::ilogb(m.largest)) : 1.0;
}

}  // namespace cubecal
