#include "cubecal/sim/power_law_generator.hpp"

#include <bit>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unsupported/Eigen/FFT>

namespace cubecal {

PowerLawNoise flicker_term(double bias_instability) {
  return {-1.0, bias_instability * bias_instability / std::numbers::pi};
}

std::size_t PowerLawGenerator::filter_length_for(std::size_t samples) noexcept {
  if (samples == 0) return std::size_t{1} << 16;
  return std::min(kMaxFilter, std::bit_ceil(samples));
}

PowerLawGenerator::PowerLawGenerator(PowerLawNoise term, double dt, std::size_t filter_length, std::uint64_t seed)
    : len_(filter_length), engine_(seed), pos_(filter_length) {
  if (!std::isfinite(term.alpha)) throw std::invalid_argument("power-law term: alpha must be finite");
  if (!(term.h >= 0.0) || !std::isfinite(term.h))
    throw std::invalid_argument("power-law term: h must be finite and >= 0");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::invalid_argument("power-law term: dt must be positive");
  if (len_ == 0 || !std::has_single_bit(len_))
    throw std::invalid_argument("power-law term: the filter length must be a power of two");
  sigma_w_ = std::sqrt(term.h / (2.0 * dt * std::pow(2.0 * std::numbers::pi * dt, term.alpha)));
  // Kasdin & Walter's taps, h_0 = 1, h_k = h_{k-1} (k - 1 + a/2) / k with a = -alpha.
  const double a = -term.alpha;
  std::vector<double> taps(2 * len_, 0.0);
  taps[0] = 1.0;
  for (std::size_t k = 1; k < len_; ++k)
    taps[k] = taps[k - 1] * (static_cast<double>(k) - 1.0 + a / 2.0) / static_cast<double>(k);
  Eigen::FFT<double> fft;
  fft.fwd(filter_, taps);
  current_.assign(len_, 0.0);
  tail_.assign(len_, 0.0);
}

void PowerLawGenerator::block() {
  // Innovations as power_law_noise draws them: the engine's normals in order.
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> w(2 * len_, 0.0);
  for (std::size_t k = 0; k < len_; ++k) w[k] = normal(engine_);
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, w);
  for (std::size_t k = 0; k < spectrum.size(); ++k) spectrum[k] *= filter_[k];
  std::vector<double> y;
  fft.inv(y, spectrum);
  // Overlap-add: this block's first L outputs plus what the previous block
  // left; its last L go to the next.
  for (std::size_t k = 0; k < len_; ++k) {
    current_[k] = sigma_w_ * (y[k] + tail_[k]);
    tail_[k] = y[len_ + k];
  }
  pos_ = 0;
}

void PowerLawGenerator::next(std::span<double> out) {
  for (double& v : out) {
    if (pos_ == len_) block();
    v = current_[pos_++];
  }
}

}  // namespace cubecal
