/// @file
/// The JSON form of the analysis results, beside their types: `analyze`'s
/// AnalysisResult (analysis.json: stable keys, every number with its unit,
/// the confidence level of the intervals) and `dev`'s DevResult
/// (`dev --format json`). The readers read back what to_json wrote, so a later
/// run (`cubecal report DIR`, `simulate --model`) gets the typed result of an
/// earlier one; a document without a key the result needs is a UsageError
/// naming the key.
#pragma once
#include <nlohmann/json.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"

namespace cubecal::pipeline {

/// analysis.json's "format_version". 2: noise.arw is N read on the -1/2 line
/// at tau = 1 s (before: the line tangent to the whole -1/2 region, often at
/// its shortest taus), and noise.reported holds the terms every output
/// reports (noise/reported_terms.hpp): N, K only when significant, B or
/// "no minimum within the record". A file without the key is version 1:
/// analysis_result_from_json reads its N again from the stored curve.
inline constexpr int kAnalysisFormatVersion = 2;

/// analysis.json without its "command" (see AnalysisDocument). Noise terms
/// are stored in their display units (display() of noise/units.hpp) with the
/// tau range they were read from; densities are derived values, written for
/// the user and not read back. The drift series are not stored (drift.csv
/// holds them): analysis_result_from_json leaves the times and the drift values of each DriftSeries empty. A channel
/// with a spectral view (analyze --psd) has "spectral": "welch" (the plan),
/// "spectrum" (the log bands), "fit" (as `psd --format json` writes it; null
/// with "fit_error" when not made) and "terms" (each IEEE 952 term of the fit
/// in display units beside the Allan curve's five-term fit, "allan_fit", and
/// "difference_sigmas"; derived, made again from "fit" on reading). A document
/// without it has no spectral view. With analyze --composite, each channel's
/// "model" has "composite" (the channel as `model --format json` writes it,
/// model_fit_json.hpp) and the document a "composite" with how they were
/// fitted (model, selection_replicates, bootstrap, seed, robust).
nlohmann::json to_json(const AnalysisResult& r);
/// Throws UsageError ("analysis.json: channels[0].noise: no key 'fit' ...")
/// for a document that lacks a key the result needs. Keys added after the
/// first release (ci, gaps, ...) take their defaults when absent.
AnalysisResult analysis_result_from_json(const nlohmann::json& j, const std::string& where);

/// An analysis.json document: the result and the command line recorded with it.
struct AnalysisDocument {
  /// The analysis.
  AnalysisResult result;
  /// The command line recorded with it.
  std::string command;
  std::vector<std::size_t> drift_points;  ///< drift.points of each channel: its rows in drift.csv
};

/// The analysis.json document: to_json(AnalysisResult), "command" and the drift points. Throws nothing beyond
/// std::bad_alloc.
nlohmann::json to_json(const AnalysisDocument& d);
/// Parses the text of an analysis.json; `label` (the file name) starts every
/// message. Throws UsageError for text that is not JSON or not an analysis.
AnalysisDocument parse_analysis_json(const std::string& text, const std::string& label);

/// `dev --format json`: {"stat","type","rate_hz","file","samples","segments",
/// "ci","edf_method","columns":[{"name","af","tau","dev","n"[,"lo","hi",
/// "edf","alpha"]}],"excluded_taus":[{"tau_s","af","needs_samples","samples",
/// "reason"}],"merged_taus":[{"tau_s","merged_with_tau_s","af"}]}; "ci" is
/// null and the interval arrays are left out when the intervals were not
/// computed. analysis.json carries "excluded_taus" and "merged_taus" of its
/// Allan curve the same way, and "model_excluded_taus" (listed taus on the
/// curve but beyond the --max-samples head the model is fitted on).
nlohmann::json to_json(const DevResult& r);
/// The DevResult that to_json(const DevResult&) wrote; `where` (the file)
/// starts every message. Throws UsageError for a document that lacks a key
/// the result needs or holds a value it cannot use (an unknown statistic or
/// data type, a rate that is not positive).
DevResult dev_result_from_json(const nlohmann::json& j, const std::string& where);

}  // namespace cubecal::pipeline
