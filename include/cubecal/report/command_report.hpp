// The report page of one cubecal command (turnon, compare, calibrate
// rate-table, calibrate mag, ...): a title, what went in, the exact command,
// result tables and figures, in the shell and style of the analysis report
// (html.hpp). A command's report builder (command_reports.hpp) describes the
// page as data; write_command_report renders its plots with gnuplot into
// DIR/plots/ and writes DIR/report.html, self-contained (plots inline as SVG).
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/report/plot.hpp"
#include "cubecal/report/report.hpp"

namespace cubecal::report {

// One row of the input summary: label and value, plain text (escaped on the
// page); `code` sets the value in a monospace font (file names, columns).
struct ReportField {
  std::string label;
  std::string value;
  bool code = false;
};

// A row of the input summary whose value is HTML (escaped by the builder).
struct ReportHtmlField {
  std::string label;  // plain text
  std::string value_html;
};

// A table of plain-text cells (escaped on the page). The first cell of each
// row is its label; the other columns are numbers (right-aligned) unless
// `numeric` says otherwise (one flag per column, the label column included).
struct ReportTable {
  std::string title;  // <h3> above it; empty: none
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> numeric;  // empty: all but the first column
  std::string note;           // small text under it; empty: none
};

// A figure: the plot and its caption (HTML: escape strings from the data).
struct ReportFigure {
  Plot plot;
  std::string caption_html;
};

// One piece of a section, written in this order: HTML (paragraphs), then the
// table, then the figures (side by side when there are several).
struct ReportBlock {
  std::string html;
  std::optional<ReportTable> table;
  std::vector<ReportFigure> figures;
};

struct ReportSection {
  std::string id;     // anchor: letters, digits, '-'
  std::string title;  // plain text
  std::vector<ReportBlock> blocks;
};

struct CommandReport {
  std::string title;      // plain text: <title> and <h1>
  std::string lead_html;  // the paragraph under the title
  std::vector<ReportField> input;
  std::vector<ReportHtmlField> input_html;  // rows after `input`
  std::string command;                      // the command line as typed
  std::vector<std::string> notes;           // plain text, highlighted under the title
  std::vector<ReportSection> sections;
  // Stems of this kind of report's plots ("runs_allan_", "mag_"): with
  // ReportOptions::force, plot files with these prefixes that the new report
  // did not write (an earlier run had other channels) are removed.
  std::vector<std::string> plot_prefixes;
  // Not empty: HTML (escaped by the builder) shown instead of the default
  // text of the Reproduce section, the Files section and the footer.
  std::string reproduce_html;
  std::string files_html;
  std::string footer_html;
};

// The plots of every figure, in page order.
std::vector<Plot> report_plots(const CommandReport& report);

// The page. `rendered` holds the rendered plots (matched by name); a figure
// whose plot is missing shows a placeholder, and `note` (plain text) says why.
std::string command_report_html(const CommandReport& report, const std::vector<RenderedPlot>& rendered,
                                std::string_view note = {});

// What `cmd --report DIR` checks before any work: throws UsageError (one
// line) when DIR/report.html or DIR/plots exists and `force` is false, or when
// gnuplot is missing.
void check_report_target(const std::string& dir, bool force, const std::string& gnuplot = {});

// Renders the plots into DIR/plots/ (created with DIR) and writes
// DIR/report.html atomically. Throws UsageError for an existing report
// without options.force, a missing gnuplot (unless !options.require_plots:
// then the page says the plots are missing) or a failing plot.
// options.max_points and options.seed are not used (the builders decide).
ReportResult write_command_report(const CommandReport& report, const std::string& dir,
                                  const ReportOptions& options = {});

}  // namespace cubecal::report
