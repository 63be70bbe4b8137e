// Periodic windows: docs/formulas/spectral.md §2.2.
#include "cubecal/spectral/window.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <span>

namespace cubecal {

namespace {

// sum_k a_k cos(k x), the generalized cosine windows (Hann, Hamming,
// Blackman) with x = 2 pi t / L, t = 0..L-1.
std::vector<double> cosine_sum(std::span<const double> a, std::size_t length) {
  std::vector<double> w(length);
  const double step = 2.0 * std::numbers::pi / static_cast<double>(length);
  for (std::size_t t = 0; t < length; ++t) {
    const double x = step * static_cast<double>(t);
    double s = 0.0;
    double sign = 1.0;
    // scipy's general_cosine: sum_k a_k cos(k (x - pi)) = sum_k (-1)^k a_k cos(k x).
    for (std::size_t k = 0; k < a.size(); ++k) {
      s += sign * a[k] * std::cos(static_cast<double>(k) * x);
      sign = -sign;
    }
    w[t] = s;
  }
  return w;
}

}  // namespace

std::string_view to_string(Window w) noexcept {
  switch (w) {
    case Window::rectangular: return "rectangular";
    case Window::hann: return "hann";
    case Window::hamming: return "hamming";
    case Window::blackman: return "blackman";
  }
  return "hann";
}

std::optional<Window> parse_window(std::string_view name) {
  if (name == "hann" || name == "hanning") return Window::hann;
  if (name == "hamming") return Window::hamming;
  if (name == "blackman") return Window::blackman;
  if (name == "rectangular" || name == "boxcar" || name == "rect") return Window::rectangular;
  return std::nullopt;
}

std::string known_windows() { return "hann|hamming|blackman|rectangular"; }

std::vector<double> window_coefficients(Window w, std::size_t length) {
  static constexpr std::array<double, 2> kHann{0.5, 0.5};
  static constexpr std::array<double, 2> kHamming{0.54, 0.46};
  static constexpr std::array<double, 3> kBlackman{0.42, 0.5, 0.08};
  switch (w) {
    case Window::rectangular: return std::vector<double>(length, 1.0);
    case Window::hann: return cosine_sum(kHann, length);
    case Window::hamming: return cosine_sum(kHamming, length);
    case Window::blackman: return cosine_sum(kBlackman, length);
  }
  return std::vector<double>(length, 1.0);
}

std::size_t main_lobe_half_width(Window w) noexcept {
  switch (w) {
    case Window::rectangular: return 1;
    case Window::hann:
    case Window::hamming: return 2;
    case Window::blackman: return 3;
  }
  return 2;
}

}  // namespace cubecal
