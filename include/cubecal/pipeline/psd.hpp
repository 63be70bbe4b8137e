/// @file
/// `cubecal psd` as a library call: the Welch power spectral density of every
/// channel of a record (welch_psd.hpp), optionally averaged over logarithmic
/// bands, with its power-law fit and the IEEE 952 terms the fit's
/// coefficients stand for, so that a spectrum can be set beside `analyze`.
/// JSON form: psd_json.hpp. docs/formulas/spectral.md.
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/spectral/power_law_fit.hpp"
#include "cubecal/spectral/psd.hpp"
#include "cubecal/spectral/welch_options.hpp"

namespace cubecal::pipeline {

/// What `cubecal psd` is asked to do with a record (the data already read).
struct PsdRequest {
  /// The Welch estimate's options.
  WelchOptions welch;
  /// 0: every bin of the transform in the result; K > 0: averaged over K
  /// logarithmic bands per decade (the fit always uses the raw bins).
  std::size_t bins_per_decade = 0;
  bool fit = true;  ///< the power-law fit and its IEEE 952 terms
  /// The power-law fit's options.
  PowerLawFitOptions fit_options;
  std::vector<Unit> units;  ///< one per channel, one for all, or none (an unnamed unit)
  unsigned threads = 0;     ///< 0: all cores
};

/// An IEEE 952 term from a fitted coefficient (Q from h_2 with f_h = rate/2,
/// N from h_0, B from h_-1, K from h_-2), in the data unit and seconds, and
/// in the unit people quote (noise/units.hpp display()).
struct PsdAllanTerm {
  /// Which term.
  Term term = Term::N;
  /// The exponent alpha of the coefficient it comes from.
  int alpha = 0;
  /// The term, in the data unit and seconds.
  TermEstimate estimate;
  /// The term in the unit people quote.
  Quantity display;
};

/// The spectrum of one channel and its power-law fit.
struct PsdChannel {
  /// The channel's name.
  std::string name;
  Unit unit;        ///< name empty: none given
  Psd spectrum;     ///< raw, or averaged over log bands (bins_per_decade > 0)
  PowerLawFit fit;  ///< terms empty when not asked for or not made
  /// The IEEE 952 terms of the fit.
  std::vector<PsdAllanTerm> allan_terms;
  /// Why the fit was not made: the default band holds too few log bands
  /// (a short record); empty when fitted or not asked for. A band the
  /// request sets is a UsageError instead.
  std::string fit_error;
};

/// The result of `cubecal psd`: one spectrum per channel.
struct PsdResult {
  std::string file;  ///< empty for arrays
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  /// Samples per channel.
  std::size_t samples = 0;
  std::size_t pieces = 1;       ///< contiguous pieces of the record (> 1 when cut at gaps)
  std::size_t pieces_used = 1;  ///< pieces holding at least one segment
  double overlap = 0.5;         ///< the fraction asked for (the samples are in each spectrum)
  /// Log bands per decade of the spectra (0: raw bins).
  std::size_t bins_per_decade = 0;
  /// True when the power-law fit was asked for.
  bool fitted = false;
  /// One per channel, in the record's order.
  std::vector<PsdChannel> channels;
};

/// The IEEE 952 terms a power-law fit's coefficients stand for, as run_psd
/// gives them (Q from h_2 with f_h = rate / 2, N from h_0, B from h_-1, K
/// from h_-2), displayed in `unit` (u when it has no name).
std::vector<PsdAllanTerm> psd_allan_terms(const PowerLawFit& fit, const Unit& unit, double rate_hz);

/// Throws UsageError for a plan the record cannot take (welch_options.hpp),
/// a unit count that is neither 1 nor one per channel ("units"), and a fit
/// band set in the request that is too narrow ("fit_range"; with the default
/// band the channel says why in fit_error).
PsdResult run_psd(const io::Series& series, const PsdRequest& request);

/// The same on arrays of one length, cut into `segments` as a Series is
/// (empty: one contiguous piece). std::invalid_argument for mismatched names
/// or lengths.
PsdResult run_psd(const std::vector<std::string>& names, const std::vector<std::span<const double>>& channels,
                  double rate_hz, const std::vector<IndexRange>& segments, const PsdRequest& request);

}  // namespace cubecal::pipeline
