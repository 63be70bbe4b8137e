#include "report_option.hpp"

#include <fmt/format.h>

#include <iostream>

namespace cubecal::cli {

void add_report_option(CLI::App& cmd, std::string& dir) {
  cmd.add_option("--report", dir,
                 "Also write DIR/report.html, one self-contained page with the results and their plots (gnuplot "
                 "data, script, SVG and PNG in DIR/plots/); an existing report is replaced only with --force");
}

void check_report_option(const std::string& dir, bool force) {
  if (!dir.empty()) report::check_report_target(dir, force);
}

void write_report_option(const report::CommandReport& page, const std::string& dir) {
  if (dir.empty()) return;
  report::ReportOptions ro;
  ro.force = true;  // an existing report was refused before the work unless --force
  const report::ReportResult r = report::write_command_report(page, dir, ro);
  std::cerr << fmt::format("cubecal: wrote {} ({:.0f} kB, {} plots in {}/plots/)\n", r.html_path,
                           static_cast<double>(r.html_bytes) / 1024.0, r.plots.size(), dir);
}

}  // namespace cubecal::cli
