/// @file
/// The Welch estimate of a one-sided power spectral density, on FFTW: the
/// record cut into segments of L samples overlapping by a fraction, each
/// detrended and windowed, its periodogram averaged; scaled as
/// scipy.signal.welch(x, fs, window, nperseg, noverlap, detrend,
/// return_onesided=True, scaling="density"). Also the covariance of its
/// bins (Psd::bin_covariance) and the EDF of each. docs/formulas/spectral.md
/// §2-§3.
///
/// FFTW is a private dependency of the pipeline library, so the estimator
/// lives here rather than in the core (which an installed project links with
/// nothing else); everything built on its result (log bins, power-law fit,
/// Allan conversions) is in the core's spectral/.
#pragma once
#include <span>
#include <vector>

#include "cubecal/spectral/psd.hpp"
#include "cubecal/spectral/welch_options.hpp"

namespace cubecal::pipeline {

/// Throws UsageError as plan_welch does (rate, segment length, overlap,
/// min frequency, a record too short), std::invalid_argument for a NaN or
/// infinite sample. Thread-safe (one FFTW plan per call, made under a lock).
Psd welch_psd(std::span<const double> x, double rate_hz, const WelchOptions& options = {});

/// Over the contiguous pieces of a record cut at gaps: the segments of every
/// piece long enough for one are averaged together (the default L follows
/// from the longest piece).
Psd welch_psd(std::span<const std::span<const double>> pieces, double rate_hz, const WelchOptions& options = {});

}  // namespace cubecal::pipeline
