/// @file
/// Power-law noise of any length, a block at a time: Kasdin & Walter's (1992)
/// filter of white noise, 1 / (1 - z^-1)^(a/2) with a = -alpha (frequency
/// data: the output's one-sided PSD is S_y(f) = h f^alpha for f << 1/dt),
/// truncated to its first `filter_length` taps and applied by FFT
/// (overlap-add, O(log L) per sample, memory O(L)). With a filter at least as
/// long as the record it is Kasdin & Walter's exact generator
/// (power_law_noise.hpp computes the same samples by direct convolution);
/// longer records keep the f^alpha law down to f ~ 1 / (filter_length dt),
/// below which the output is white in frequency. docs/formulas/simulator.md §5a.
///
/// The scale: the innovations are N(0, sigma_w^2) with
///   sigma_w^2 = h / (2 dt (2 pi dt)^alpha),
/// so that the discrete PSD 2 dt sigma_w^2 |2 sin(pi f dt)|^alpha tends to
/// h f^alpha. IEEE 952's bias instability B is flicker FM with h_{-1} =
/// B^2 / pi: the Allan deviation's floor 2 ln 2 h_{-1} = (2 ln 2 / pi) B^2.
#pragma once
#include <complex>
#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

namespace cubecal {

/// One power-law term of a sensor's rate (or field) noise: S_y(f) = h f^alpha,
/// one-sided, in unit^2/Hz times Hz^-alpha.
struct PowerLawNoise {
  double alpha = -1.0;  ///< 0 white, -1 flicker (bias instability), -2 random walk ...
  /// The level h, in unit^2/Hz times Hz^-alpha.
  double h = 0.0;
};

/// The flicker term of bias instability B (unit): alpha -1, h = B^2 / pi.
PowerLawNoise flicker_term(double bias_instability);

/// Power-law noise of any alpha by Kasdin & Walter's filter of white noise, block by block (FFT convolution).
class PowerLawGenerator {
 public:
  /// The longest filter used (2^18 taps: at 10 Hz, 7.3 h of memory).
  static constexpr std::size_t kMaxFilter = std::size_t{1} << 18;
  /// A filter for a record of `samples` (0: unknown): the power of two at
  /// least as long as the record, at most kMaxFilter.
  static std::size_t filter_length_for(std::size_t samples) noexcept;

  /// Throws std::invalid_argument for a non-finite alpha, a negative or
  /// non-finite h, a non-positive dt or a filter length that is not a power
  /// of two.
  PowerLawGenerator(PowerLawNoise term, double dt, std::size_t filter_length, std::uint64_t seed);

  /// The next out.size() samples of the process.
  void next(std::span<double> out);

 private:
  void block();

  std::size_t len_;  ///< L: taps and block length
  double sigma_w_;
  std::mt19937_64 engine_;
  std::vector<std::complex<double>> filter_;  ///< FFT of the taps, zero-padded to 2L
  std::vector<double> current_, tail_;        ///< this block's outputs; the next block's share
  std::size_t pos_;                           ///< next unread sample of current_
};

}  // namespace cubecal
