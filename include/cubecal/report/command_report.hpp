/// @file
/// The report page of one cubecal command (turnon, compare, calibrate
/// rate-table, calibrate mag, ...): a title, what went in, the exact command,
/// result tables and figures, in the shell and style of the analysis report
/// (html.hpp). A command's report builder (command_reports.hpp) describes the
/// page as data; write_command_report renders its plots with gnuplot into
/// DIR/plots/ and writes DIR/report.html, self-contained (plots inline as SVG).
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/report/plot.hpp"
#include "cubecal/report/report.hpp"

namespace cubecal::report {

/// One row of the input summary: label and value, plain text (escaped on the
/// page); `code` sets the value in a monospace font (file names, columns).
struct ReportField {
  /// The row's label, plain text.
  std::string label;
  /// The value, plain text.
  std::string value;
  /// True to set the value in a monospace font.
  bool code = false;
};

/// A row of the input summary whose value is HTML (escaped by the builder).
struct ReportHtmlField {
  std::string label;  ///< plain text
  /// The value, HTML.
  std::string value_html;
};

/// A table of plain-text cells (escaped on the page). The first cell of each
/// row is its label; the other columns are numbers (right-aligned) unless
/// `numeric` says otherwise (one flag per column, the label column included).
struct ReportTable {
  std::string title;  ///< `<h3>` above it; empty: none
  /// The column titles, plain text.
  std::vector<std::string> header;
  /// The rows of cells, plain text.
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> numeric;  ///< empty: all but the first column
  std::string note;           ///< small text under it; empty: none
};

/// A figure: the plot and its caption (HTML: escape strings from the data).
struct ReportFigure {
  /// The plot, rendered by gnuplot.
  Plot plot;
  /// The caption, HTML.
  std::string caption_html;
};

/// One piece of a section, written in this order: HTML (paragraphs), then the
/// table, then the figures (side by side when there are several).
struct ReportBlock {
  /// Paragraphs, HTML (escaped by the builder); empty: none.
  std::string html;
  /// A table; none: no table.
  std::optional<ReportTable> table;
  /// The figures, side by side when there are several.
  std::vector<ReportFigure> figures;
};

/// A section of a report page, with its anchor and title.
struct ReportSection {
  std::string id;     ///< anchor: letters, digits, '-'
  std::string title;  ///< plain text
  /// Its pieces, in page order.
  std::vector<ReportBlock> blocks;
};

/// One report page: title, input summary, notes and sections (write it with write_command_report).
struct CommandReport {
  std::string title;      ///< plain text: `<title>` and `<h1>`
  std::string lead_html;  ///< the paragraph under the title
  /// The input summary's rows.
  std::vector<ReportField> input;
  std::vector<ReportHtmlField> input_html;  ///< rows after `input`
  std::string command;                      ///< the command line as typed
  std::vector<std::string> notes;           ///< plain text, highlighted under the title
  /// The sections, in page order.
  std::vector<ReportSection> sections;
  /// Stems of this kind of report's plots ("runs_allan_", "mag_"): with
  /// ReportOptions::force, plot files with these prefixes that the new report
  /// did not write (an earlier run had other channels) are removed.
  std::vector<std::string> plot_prefixes;
  /// Not empty: HTML (escaped by the builder) shown instead of the default
  /// text of the Reproduce section, the Files section and the footer.
  std::string reproduce_html;
  /// HTML shown instead of the default Files section; empty: the default.
  std::string files_html;
  /// HTML shown instead of the default footer; empty: the default.
  std::string footer_html;
};

/// The plots of every figure, in page order.
std::vector<Plot> report_plots(const CommandReport& report);

/// The page. `rendered` holds the rendered plots (matched by name); a figure
/// whose plot is missing shows a placeholder, and `note` (plain text) says why.
std::string command_report_html(const CommandReport& report, const std::vector<RenderedPlot>& rendered,
                                std::string_view note = {});

/// What `cmd --report DIR` checks before any work: throws UsageError (one
/// line) when DIR/report.html or DIR/plots exists and `force` is false, or when
/// gnuplot is missing.
void check_report_target(const std::string& dir, bool force, const std::string& gnuplot = {});

/// Renders the plots into DIR/plots/ (created with DIR) and writes
/// DIR/report.html atomically. Throws UsageError for an existing report
/// without options.force, a missing gnuplot (unless !options.require_plots:
/// then the page says the plots are missing) or a failing plot.
/// options.max_points and options.seed are not used (the builders decide).
ReportResult write_command_report(const CommandReport& report, const std::string& dir,
                                  const ReportOptions& options = {});

}  // namespace cubecal::report
