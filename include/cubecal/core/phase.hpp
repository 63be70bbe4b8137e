// Frequency-to-phase conversion.
#pragma once
#include <span>
#include <vector>

namespace cubecal {

// x[0] = 0, x[i+1] = x[i] + (y[i] - mean(y)) * tau0: N frequency points give
// N+1 phase points. The mean is removed first (it cancels in every
// statistic built on second or higher differences) so that the running sum
// stays small and keeps its precision over millions of samples.
std::vector<double> freq_to_phase(std::span<const double> y, double tau0);

// Phase data as given, minus its first value (same reason).
std::vector<double> normalize_phase(std::span<const double> x);

}  // namespace cubecal
