// How the densities of a Welch spectrum vary together: the covariance of
// the means of two runs of raw bins, for a spectrum white across them, from
// the estimator's g(d) (Psd::bin_covariance). Gives the EDF of a band
// average (log bins) and the covariance matrix of the power-law fit.
// docs/formulas/spectral.md §3.
#pragma once
#include <cstddef>
#include <vector>

#include "cubecal/spectral/psd.hpp"

namespace cubecal {

class BinCovariance {
 public:
  // Throws std::invalid_argument when `raw` carries no g(d) (not from the
  // estimator).
  explicit BinCovariance(const Psd& raw);

  // cov(mean of bins [a, a+m), mean of bins [b, b+n)) / (S_a S_b): the sum
  // over the pairs (j, k) of g(|j - k|) + g((j + k) mod L), over m n.
  double between(std::size_t a, std::size_t m, std::size_t b, std::size_t n) const;
  // Equivalent degrees of freedom of the mean of bins [a, a+m): 2 / var.
  double edf(std::size_t a, std::size_t m) const;

 private:
  // sum of g(min(d, L - d)) over d in [d0, d1), 0 <= d0 <= d1 <= L.
  double range_sum(std::size_t d0, std::size_t d1) const;
  // sum of g(|e|) over the integers e in [lo, hi).
  double abs_sum(long long lo, long long hi) const;

  std::size_t length_ = 0;      // L
  std::vector<double> prefix_;  // prefix_[i] = sum of g(d), d < i
};

}  // namespace cubecal
