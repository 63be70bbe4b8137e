#include "report_option.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>

namespace cubecal::cli {

void add_gnuplot_option(CLI::App& cmd, std::string& gnuplot) {
  cmd.add_option("--gnuplot", gnuplot, "gnuplot executable for the report's plots (default: gnuplot on PATH)");
}

void add_report_option(CLI::App& cmd, ReportTarget& target) {
  add_gnuplot_option(cmd, target.gnuplot);
  cmd.add_option("--report", target.dir,
                 "Also write DIR/report.html, one self-contained page with the results and their plots (gnuplot "
                 "data, script, SVG and PNG in DIR/plots/); an existing report is replaced only with --force");
}

void check_report_option(const ReportTarget& target, bool force) {
  if (!target.dir.empty()) report::check_report_target(target.dir, force, target.gnuplot);
}

void write_report_option(const report::CommandReport& page, const ReportTarget& target) {
  const std::string& dir = target.dir;
  if (dir.empty()) return;
  report::ReportOptions ro;
  ro.gnuplot = target.gnuplot;
  ro.force = true;  // an existing report was refused before the work unless --force
  const report::ReportResult r = report::write_command_report(page, dir, ro);
  std::cerr << fmt::format("cubecal: wrote {} ({:.0f} kB, {} plots in {})\n", r.html_path,
                           static_cast<double>(r.html_bytes) / 1024.0, r.plots.size(),
                           (std::filesystem::path(dir) / "plots/").string());
}

}  // namespace cubecal::cli
