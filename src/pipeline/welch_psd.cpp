// The Welch estimator on FFTW: docs/formulas/spectral.md §2 (the density,
// as scipy.signal.welch) and §3 (the covariance of its bins, its EDF).
#include "cubecal/pipeline/welch_psd.hpp"

#include <fftw3.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <mutex>
#include <new>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/spectral/detrend.hpp"

namespace cubecal::pipeline {

namespace {

// FFTW's planner is not thread-safe; executing a plan on its own arrays is.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

// A real-to-complex transform of length L with its own aligned arrays.
class RealTransform {
 public:
  explicit RealTransform(std::size_t length) : length_(length) {
    if (length > static_cast<std::size_t>(INT_MAX)) throw std::length_error("segment longer than FFTW's int length");
    in_ = fftw_alloc_real(length);
    out_ = fftw_alloc_complex(length / 2 + 1);
    if (in_ == nullptr || out_ == nullptr) {
      release();
      throw std::bad_alloc();
    }
    std::lock_guard<std::mutex> lock(planner_mutex());
    plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(length), in_, out_, FFTW_ESTIMATE);
    if (plan_ == nullptr) {
      release();
      throw std::runtime_error("FFTW could not plan a transform of length " + std::to_string(length));
    }
  }
  RealTransform(const RealTransform&) = delete;
  RealTransform& operator=(const RealTransform&) = delete;
  ~RealTransform() { release(); }

  std::span<double> input() noexcept { return {in_, length_}; }
  // |X_k|^2, k = 0..L/2, added to `acc` (or stored when !add).
  void power(std::span<double> acc, bool add) noexcept {
    fftw_execute(plan_);
    for (std::size_t k = 0; k < acc.size(); ++k) {
      const double p = out_[k][0] * out_[k][0] + out_[k][1] * out_[k][1];
      acc[k] = add ? acc[k] + p : p;
    }
  }

 private:
  void release() noexcept {
    if (plan_ != nullptr) {
      std::lock_guard<std::mutex> lock(planner_mutex());
      fftw_destroy_plan(plan_);
      plan_ = nullptr;
    }
    fftw_free(in_);
    fftw_free(out_);
    in_ = nullptr;
    out_ = nullptr;
  }

  std::size_t length_;
  double* in_ = nullptr;
  fftw_complex* out_ = nullptr;
  fftw_plan plan_ = nullptr;
};

// g(d), d = 0..L/2 (§3): for each lag of m whole steps that still overlap,
// |c(m s, d)|^2 is the power of the transform of h_t h_{t + m s}
// (h = w / sqrt(sum w^2)); each piece of N_p segments weighs its lags by
// N_p - |m|, over the square of all segments.
std::vector<double> bin_covariance(const std::vector<double>& w, double sum_w2, const WelchPlan& plan,
                                   const std::vector<std::size_t>& piece_segments, std::size_t segments,
                                   RealTransform& fft) {
  const std::size_t l = plan.segment_length;
  std::vector<double> g(l / 2 + 1, 0.0);
  std::vector<double> c2(l / 2 + 1);
  std::size_t most = 0;
  for (const std::size_t n : piece_segments) most = std::max(most, n);
  for (std::size_t m = 0; m < most && m * plan.step < l; ++m) {
    const std::size_t lag = m * plan.step;
    std::span<double> in = fft.input();
    for (std::size_t t = 0; t < l; ++t) in[t] = t + lag < l ? w[t] * w[t + lag] / sum_w2 : 0.0;
    fft.power(c2, false);
    double weight = 0.0;  // sum over pieces of (N_p - m), twice for m > 0 (lags +m and -m)
    for (const std::size_t n : piece_segments)
      if (n > m) weight += static_cast<double>(n - m);
    if (m > 0) weight *= 2.0;
    for (std::size_t d = 0; d < g.size(); ++d) g[d] += weight * c2[d];
  }
  const double total = static_cast<double>(segments);
  for (double& v : g) v /= total * total;
  return g;
}

}  // namespace

Psd welch_psd(std::span<const std::span<const double>> pieces, double rate_hz, const WelchOptions& options) {
  std::size_t longest = 0;
  for (const auto& p : pieces) {
    longest = std::max(longest, p.size());
    for (const double v : p)
      if (!std::isfinite(v)) throw std::invalid_argument("welch_psd: a sample is NaN or infinite");
  }
  const WelchPlan plan = plan_welch(options, longest, rate_hz);
  const std::size_t l = plan.segment_length;
  const std::vector<double> w = window_coefficients(options.window, l);
  double sum_w = 0.0;
  double sum_w2 = 0.0;
  for (const double v : w) {
    sum_w += v;
    sum_w2 += v * v;
  }

  Psd psd;
  psd.rate_hz = rate_hz;
  psd.window = options.window;
  psd.detrend = options.detrend;
  psd.segment_length = l;
  psd.overlap = plan.overlap;
  psd.enbw_hz = rate_hz * sum_w2 / (sum_w * sum_w);

  RealTransform fft(l);
  std::vector<double> acc(l / 2 + 1, 0.0);
  std::vector<std::size_t> piece_segments;
  for (const auto& p : pieces) {
    const std::size_t ns = welch_segments(p.size(), plan);
    piece_segments.push_back(ns);
    if (ns == 0) continue;
    psd.segments += ns;
    psd.samples_used += (ns - 1) * plan.step + l;
    for (std::size_t i = 0; i < ns; ++i) {
      std::span<double> in = fft.input();
      std::copy_n(p.begin() + static_cast<std::ptrdiff_t>(i * plan.step), l, in.begin());
      detrend(in, options.detrend);
      for (std::size_t t = 0; t < l; ++t) in[t] *= w[t];
      fft.power(acc, true);
    }
  }

  // One-sided density: twice the power of every bin but DC and (L even)
  // Nyquist, over rate * sum w^2 and the segments.
  const double scale = 1.0 / (rate_hz * sum_w2 * static_cast<double>(psd.segments));
  const std::size_t bins = l / 2 + 1;
  psd.frequency.resize(bins);
  psd.density.resize(bins);
  psd.first_bin.resize(bins);
  psd.bins.assign(bins, 1);
  for (std::size_t k = 0; k < bins; ++k) {
    const bool edge = k == 0 || (l % 2 == 0 && k == l / 2);
    psd.frequency[k] = static_cast<double>(k) * rate_hz / static_cast<double>(l);
    psd.density[k] = acc[k] * scale * (edge ? 1.0 : 2.0);
    psd.first_bin[k] = k;
  }
  psd.bin_covariance = bin_covariance(w, sum_w2, plan, piece_segments, psd.segments, fft);
  // EDF of bin k: 2 / (g(0) + g((2k) mod L)), the second term the
  // correlation of X_k with X_-k (DC and Nyquist: equal, half the EDF).
  psd.edf.resize(bins);
  for (std::size_t k = 0; k < bins; ++k) {
    const std::size_t twice = (2 * k) % l;
    const std::size_t d = std::min(twice, l - twice);
    psd.edf[k] = 2.0 / (psd.bin_covariance[0] + psd.bin_covariance[d]);
  }
  return psd;
}

Psd welch_psd(std::span<const double> x, double rate_hz, const WelchOptions& options) {
  const std::span<const double> one[] = {x};
  return welch_psd(std::span<const std::span<const double>>(one), rate_hz, options);
}

}  // namespace cubecal::pipeline
