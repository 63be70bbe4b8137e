#include "cubecal/core/phase.hpp"

namespace cubecal {

std::vector<double> freq_to_phase(std::span<const double> y, double tau0) {
  std::vector<double> x(y.size() + 1, 0.0);
  if (y.empty()) return x;
  // Two-pass mean (accurate for long records), then the running sum.
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  double acc = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    acc += (y[i] - mean) * tau0;
    x[i + 1] = acc;
  }
  return x;
}

std::vector<double> normalize_phase(std::span<const double> x) {
  std::vector<double> out(x.begin(), x.end());
  if (out.empty()) return out;
  const double x0 = out.front();
  for (double& v : out) v -= x0;
  return out;
}

}  // namespace cubecal
