/// @file
/// A periodic line of a record's spectrum: what a composite model's SIN term
/// (noise/composite_model.hpp) starts from in the twin search
/// (noise/twin_selection.hpp). The lines of a Welch spectrum are found by
/// find_spectral_lines (spectral/spectral_lines.hpp).
#pragma once

namespace cubecal {

/// A periodic line: its frequency (Hz), its power (u^2) and its shape.
struct SpectralLine {
  double frequency_hz = 0.0;  ///< power-weighted centre of the peak's bins
  double power = 0.0;         ///< u^2: the line's variance, A^2 / 2 for a sinusoid of amplitude A
  double peak_ratio = 0.0;    ///< the highest bin's density over its background
  double width_hz = 0.0;      ///< the span of the bins above the background's spread
};

}  // namespace cubecal
