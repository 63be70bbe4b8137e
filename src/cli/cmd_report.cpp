// cubecal report DIR: the results of an earlier `analyze --out DIR` (read
// through analysis_result_from_json) as one self-contained HTML page (DIR/report.html) with
// gnuplot plots in DIR/plots/.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/output_path.hpp"
#include "cubecal/report/report.hpp"

namespace cubecal::cli {

namespace {

struct ReportCmdOptions {
  std::string dir;
  bool force = false;
  bool keep_scripts = false;
  std::string gnuplot;
};

int run_report(const ReportCmdOptions& o) {
  report::ReportOptions ro;
  ro.force = o.force;
  ro.keep_scripts = o.keep_scripts;
  ro.gnuplot = o.gnuplot;
  // The page goes beside the analysis it shows: DIR must be writable before
  // the plots are drawn (a missing DIR is the reader's to report).
  std::error_code ec;
  if (std::filesystem::is_directory(o.dir, ec)) {
    // A report written before is in DIR, which is no --out: say so.
    for (const char* f : {"report.html", "plots"})
      if (!o.force && std::filesystem::exists(std::filesystem::path(o.dir) / f, ec))
        throw UsageError((std::filesystem::path(o.dir) / f).string() + " already exists: " + o.dir +
                         " has a report already (add {force} to replace it)");
    io::prepare_output_dir(o.dir, o.force, {"report.html", "plots"});
  }
  const report::ReportResult r = report::write_report(o.dir, ro);
  std::cerr << fmt::format("cubecal: wrote {} ({:.0f} kB, {} plots in {}) in {:.1f} s\n", r.html_path,
                           static_cast<double>(r.html_bytes) / 1024.0, r.plots.size(),
                           (std::filesystem::path(o.dir) / "plots/").string(), r.seconds);
  return 0;
}

}  // namespace

CLI::App* add_report_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<ReportCmdOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "One self-contained HTML page (DIR/report.html) of the results `analyze --out DIR` wrote, with "
      "gnuplot plots (data, script, SVG, PNG) in DIR/plots/");
  cmd->add_option("DIR", opt->dir, "Directory holding analysis.json (and drift.csv for the drift plots)")->required();
  cmd->add_flag("--force", opt->force, "Replace an existing report.html and plots/");
  cmd->add_flag("--keep-scripts", opt->keep_scripts,
                "Render from the existing plots/*.gp (restyled by hand) instead of writing new ones");
  cmd->add_option("--gnuplot", opt->gnuplot, "gnuplot executable (default: gnuplot on PATH)");
  cmd->callback([opt, &run] { run = [opt] { return run_report(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
