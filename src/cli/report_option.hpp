// --report DIR of the analysis commands other than `analyze` (turnon,
// compare, calibrate rate-table, calibrate mag): DIR/report.html with its
// plots in DIR/plots/, never replacing an existing report without --force.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "cubecal/report/command_report.hpp"

namespace cubecal::cli {

struct ReportTarget {
  std::string dir;      // --report DIR; empty: no report
  std::string gnuplot;  // --gnuplot PATH; empty: gnuplot on PATH
};

// Registers --report DIR and --gnuplot PATH on `cmd`.
void add_report_option(CLI::App& cmd, ReportTarget& target);
// Registers --gnuplot PATH alone (commands whose --report is a flag).
void add_gnuplot_option(CLI::App& cmd, std::string& gnuplot);

// Before any work, when a report is asked for: an existing DIR/report.html or
// DIR/plots without `force`, or no gnuplot (on PATH, or at --gnuplot), is a
// one-line error.
void check_report_option(const ReportTarget& target, bool force);

// Writes the page and its plots (with the --gnuplot program) when a report is
// asked for, and says so on standard error.
void write_report_option(const report::CommandReport& page, const ReportTarget& target);

}  // namespace cubecal::cli
