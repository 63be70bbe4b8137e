/// @file
/// The report of an analysis: a typed pipeline::AnalysisResult as one
/// self-contained HTML page, DIR/report.html, with its plots rendered by
/// gnuplot into DIR/plots/ (the page is built by analysis_report() of
/// analysis_report.hpp and written by write_command_report):
///   allan_<sensor>        OADEV with intervals, the fitted random-walk model
///                         (dashed), the Gauss-Markov model (dotted) and the
///                         fitted noise-term lines (the paper's Figs. 1, 2, 4)
///   drift_<sensor>        bias drift of the data and of the fitted model,
///                         simulated (Figs. 3, 5)
///   temperature_<sensor>  the fitted bias-temperature polynomial
///   compensated_<sensor>  OADEV before and after temperature compensation
///   psd_<channel>         analyze --psd: the channel's one-sided PSD with its
///                         fitted power-law terms (as the psd page draws it)
/// `<sensor>` is rate, field or other: channels grouped by the kind of their unit
/// (with _<unit> appended when one kind comes in several units).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cubecal/pipeline/analyze.hpp"

namespace cubecal::report {

/// How the analyze report is written.
struct ReportOptions {
  bool force = false;             ///< replace an existing report.html and plots/ files
  bool keep_scripts = false;      ///< re-render from existing (user-edited) plots/*.gp
  bool require_plots = true;      ///< false: without gnuplot, write the page without plots (and say so)
  std::string gnuplot;            ///< gnuplot executable; empty: on PATH
  std::size_t max_points = 2000;  ///< per drift series in a plot
  std::uint64_t seed = 1;         ///< of the simulated model drift
  unsigned jobs = 0;              ///< gnuplot processes at once (0: hardware threads)
};

/// What writing the analyze report did.
struct ReportResult {
  /// Path of report.html.
  std::string html_path;
  /// Its size (bytes).
  std::size_t html_bytes = 0;
  std::vector<std::string> plots;  ///< names of the plots in plots/
  std::string note;                ///< why plots are missing (require_plots = false), else empty
  double seconds = 0.0;            ///< wall time of write_report
};

/// What the page says besides the result.
struct AnalysisReportContext {
  std::string command;     ///< the `cubecal analyze` command line that reproduces the result
  std::string drift_note;  ///< not empty: why the drift series are missing (the page shows no drift plots)
};

/// The page of `r` into DIR (created): `analyze --report` and `demo` pass the
/// result they hold. Throws UsageError with one line for gnuplot missing (unless
/// !options.require_plots) or an existing report without `force`.
ReportResult write_report(const pipeline::AnalysisResult& r, const AnalysisReportContext& context,
                          const std::string& dir, const ReportOptions& options = {});

/// `cubecal report DIR`: the result of an earlier `analyze --out DIR` read from
/// DIR/analysis.json (from_json) and its drift series from DIR/drift.csv (no
/// drift plots when absent or not matching), then the page as above. The model
/// curves are computed from the fitted parameters. Throws UsageError with one
/// line for: no analysis.json, a file that is not an analysis result, gnuplot
/// missing, an existing report without `force`.
ReportResult write_report(const std::string& dir, const ReportOptions& options = {});

/// The files write_report would replace that exist now (report.html, plots/).
std::vector<std::string> existing_report_outputs(const std::string& dir);

}  // namespace cubecal::report
