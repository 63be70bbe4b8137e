// Uses the installed cubecal core: OADEV of a linear frequency ramp, whose
// Allan variance is R^2 tau^2 / 2 exactly. Exit 0 when it agrees.
#include <cmath>
#include <cstdio>
#include <vector>

#include "cubecal/stats/stability.hpp"

int main() {
  const double R = 1e-3;
  std::vector<double> y(1000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = R * static_cast<double>(i);
  const std::size_t ms[] = {1, 10, 100};
  const auto pts = cubecal::stability(y, cubecal::DataType::freq, 1.0, cubecal::Stat::oadev, ms);
  for (const auto& p : pts) {
    const double want = R * p.tau / std::sqrt(2.0);
    if (std::abs(p.dev / want - 1.0) > 1e-9) {
      std::printf("tau %g: %g != %g\n", p.tau, p.dev, want);
      return 1;
    }
  }
  std::puts("cubecal core usable via find_package");
  return 0;
}
