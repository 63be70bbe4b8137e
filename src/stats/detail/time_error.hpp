// Time-interval error statistics on phase data (docs/formulas/stability.md):
// TIE rms and MTIE, as Stable32 computes them. Neither has a noise type, an
// EDF or a confidence interval.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "cubecal/stats/kernels.hpp"

namespace cubecal {

// Phase from frequency for the time-interval errors: x[0] = 0,
// x[i+1] = x[i] + y[i] tau0 / scale. Unlike freq_to_phase (stats/phase.hpp)
// the mean frequency is kept: a frequency offset is a time error that grows,
// and TIE and MTIE measure it.
std::vector<double> integrate_frequency(std::span<const double> y, double tau0, double scale = 1.0);

// TIE rms at averaging factor m: sqrt of the mean of (x[i+m] - x[i])^2 over
// the N - m terms. Returned as {mean square, N - m}.
VarianceTerm tie_mean_square(std::span<const double> x, std::size_t m);

// MTIE at averaging factor m: the largest peak-to-peak phase excursion in a
// window of m + 1 points, over the N - m windows. Returned as {MTIE^2, N - m}
// (the square, so that the deviation code takes its root like the others).
// O(N) per factor (van Herk / Gil-Werman running maximum and minimum).
VarianceTerm mtie_square(std::span<const double> x, std::size_t m);

}  // namespace cubecal
