// Test support: the total variances' shared term, as NIST SP 1065 writes it,
// summed directly (tests of MTOT/HTOT kernels: test_stable32_more,
// test_pvar_covariance_htot).
#pragma once
#include <cstddef>
#include <vector>

namespace cubecal::test {

// SP 1065 eq. 27 literally: per subsequence, detrend by half means, extend
// to 9m by even reflection, average the 6m squared second differences of
// m-point means.
inline double direct_total(const std::vector<double>& v, std::size_t m) {
  const std::size_t L = 3 * m;
  double total = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i + L <= v.size(); ++i, ++n) {
    std::vector<double> y(v.begin() + static_cast<std::ptrdiff_t>(i), v.begin() + static_cast<std::ptrdiff_t>(i + L));
    const std::size_t h1 = L / 2, h2 = (L + 1) / 2;
    double a = 0, b = 0;
    for (std::size_t k = 0; k < h1; ++k) a += y[k];
    for (std::size_t k = h2; k < L; ++k) b += y[k];
    a /= static_cast<double>(h1);
    b /= static_cast<double>(L - h2);
    const double dist = (L % 2 == 1) ? static_cast<double>(L + 1) / 2.0 : static_cast<double>(L) / 2.0;
    for (std::size_t k = 0; k < L; ++k) y[k] -= (b - a) / dist * static_cast<double>(k);
    std::vector<double> ext;
    for (std::size_t k = L; k-- > 0;) ext.push_back(y[k]);
    ext.insert(ext.end(), y.begin(), y.end());
    for (std::size_t k = L; k-- > 0;) ext.push_back(y[k]);
    double s = 0;
    for (std::size_t j = 0; j < 6 * m; ++j) {
      double m1 = 0, m2 = 0, m3 = 0;
      for (std::size_t k = 0; k < m; ++k) {
        m1 += ext[j + k];
        m2 += ext[j + m + k];
        m3 += ext[j + 2 * m + k];
      }
      const double d = (m1 - 2 * m2 + m3) / static_cast<double>(m);
      s += d * d;
    }
    total += s / (6.0 * static_cast<double>(m));
  }
  return total / static_cast<double>(n);
}

}  // namespace cubecal::test
