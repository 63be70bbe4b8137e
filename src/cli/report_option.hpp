// --report DIR of the analysis commands other than `analyze` (turnon,
// compare, calibrate rate-table, calibrate mag): DIR/report.html with its
// plots in DIR/plots/, never replacing an existing report without --force.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "cubecal/report/command_report.hpp"

namespace cubecal::cli {

// Registers --report DIR on `cmd`.
void add_report_option(CLI::App& cmd, std::string& dir);

// Before any work, when `dir` is not empty: an existing DIR/report.html or
// DIR/plots without `force`, or a missing gnuplot, is a one-line error.
void check_report_option(const std::string& dir, bool force);

// Writes the page and its plots into `dir` (when not empty) and says so on
// standard error.
void write_report_option(const report::CommandReport& page, const std::string& dir);

}  // namespace cubecal::cli
