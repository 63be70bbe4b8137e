/// @file
/// Data windows (tapers) of the Welch spectral estimator, as
/// scipy.signal.get_window(name, L) gives them for spectral analysis
/// (fftbins=True: the "periodic" form, L points of an (L+1)-point symmetric
/// window without its last point). docs/formulas/spectral.md §2.2.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal {

/// The data windows of a Welch spectrum.
enum class Window { rectangular, hann, hamming, blackman };

/// "rectangular", "hann", "hamming", "blackman". Throws nothing.
std::string_view to_string(Window w) noexcept;
/// "hann" (also "hanning"), "hamming", "blackman", "rectangular" (also
/// "boxcar", "rect"); nullopt for anything else.
std::optional<Window> parse_window(std::string_view name);
std::string known_windows();  ///< "hann|hamming|blackman|rectangular"

/// The L coefficients w_0 .. w_{L-1} (periodic form).
std::vector<double> window_coefficients(Window w, std::size_t length);

/// Half the width of the window's main lobe, in frequency bins of an L-point
/// transform (rectangular 1, hann and hamming 2, blackman 3): the bins a
/// constant removed from the segment (detrending) or a frequency below the
/// resolution leaks into.
std::size_t main_lobe_half_width(Window w) noexcept;

}  // namespace cubecal
