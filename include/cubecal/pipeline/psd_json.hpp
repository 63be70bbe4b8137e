/// @file
/// The JSON form of a `cubecal psd` result (what `psd --format json`
/// prints): {command: "psd", file, rate_hz, samples, pieces, pieces_used,
/// welch {window, segment_length, overlap, overlap_samples, detrend,
/// segments, samples_used, resolution_hz, enbw_hz, bins_per_decade},
/// one_sided: true, channels [{name, unit (null when none was given),
/// density_unit, frequency_hz [], density [], edf [], bins [],
/// density_rate {unit: "(deg/h)^2/Hz", values []} (rate sensors), fit {f_lo_hz,
/// f_hi_hz, bands, chi2, dof, scale, terms [{alpha, h, sigma, valid, unit,
/// f_lo_hz, f_hi_hz}], covariance [[...]]} (when fitted; null with fit_error
/// saying why when the default band of a short record was too narrow), allan_terms
/// [{term, alpha, valid, value, sigma, unit, display {value, sigma, unit}}]}]}.
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/psd.hpp"

namespace cubecal::pipeline {

/// `cubecal psd --format json`: the result as JSON. Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const PsdResult& r);

/// A power-law fit in the keys of its "fit" object (also analysis.json's
/// spectral view): the band, each h_alpha with its sigma, unit and the range
/// where it holds, their covariance (empty rows when it was not kept).
nlohmann::json power_law_fit_json(const PowerLawFit& f, const Unit& unit);

/// The Welch plan of a spectrum in the keys of its "welch" object (window,
/// segment_length, overlap (the fraction asked for), overlap_samples,
/// detrend, segments, samples_used, resolution_hz, enbw_hz); also
/// analysis.json's spectral view.
nlohmann::json welch_json(const Psd& spectrum, double overlap);

}  // namespace cubecal::pipeline
