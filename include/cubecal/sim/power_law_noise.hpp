/// @file
/// Power-law noise of a given exponent: S_y(f) ~ f^alpha for the fractional
/// frequency (alpha = +2 white PM, +1 flicker PM, 0 white FM, -1 flicker FM,
/// -2 random-walk FM, -3 flicker walk FM, -4 random-run FM), by the method of
/// Kasdin & Walter (1992), "Discrete simulation of power law noise", Proc.
/// IEEE Frequency Control Symposium, pp. 274-283: white Gaussian noise w_k
/// through the causal filter of 1 / (1 - z^-1)^(a/2),
///   x_n = sum_{k=0..n} h_k w_{n-k},  h_0 = 1,  h_k = h_{k-1} (k - 1 + a/2) / k,
/// with a = 2 - alpha for phase data (S_x ~ f^(alpha - 2)) and a = -alpha for
/// frequency data. Exact for any record length (no spectral truncation), and
/// O(n^2): meant for the short records (up to some 10^4 samples) where noise
/// identification and confidence intervals are tested; the sensor simulator
/// (simulator.hpp) makes long records. Deterministic for a seed.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// n samples of unit innovation (w ~ N(0, 1)), as phase or frequency data.
/// alpha need not be an integer (any real exponent is a valid filter).
std::vector<double> power_law_noise(double alpha, std::size_t n, std::uint64_t seed, DataType type = DataType::phase);

}  // namespace cubecal
