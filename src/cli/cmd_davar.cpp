// cubecal davar: the dynamic Allan deviation, OADEV over a window sliding
// along the record (docs/formulas/davar.md), as a tau x time matrix per
// channel.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/davar_pipeline.hpp"
#include "cubecal/report/command_reports.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct DavarCliOptions {
  InputOptions input;
  std::string type = "freq";
  std::string window;  // empty: a tenth of the record
  std::string step;    // empty: a tenth of the window
  std::string taus = "log:10";
  double ci = 0.683;
  std::string edf = "greenhall";
  std::optional<int> alpha;
  bool no_ci = false;
  std::string method = "fast";
  std::string format = "table";
  std::string out;
  bool force = false;
  ReportTarget report;
};

std::string g(double v) { return fmt::format("{:.6e}", v); }

// Per channel and tau: the spread of the deviation over the windows.
void write_table(std::ostream& out, const pipeline::DavarResult& r) {
  const double tau0 = 1.0 / r.rate_hz;
  for (const auto& ch : r.channels) {
    const DavarMatrix& mx = ch.matrix;
    const std::size_t K = mx.windows();
    fmt::print(out, "# {}: {} — dynamic OADEV, {} windows of {} samples ({:.6g} s) every {} samples ({:.6g} s), {} Hz\n",
               r.file, ch.name, K, r.window, static_cast<double>(r.window) * tau0, r.step,
               static_cast<double>(r.step) * tau0, rate_text(r.rate_hz));
    fmt::print(out, "{:>12} {:>9} {:>13} {:>12} {:>13} {:>13} {:>12} {:>9}\n", "tau [s]", "n", "min", "at t [s]",
               "median", "max", "at t [s]", "max/min");
    std::vector<double> row(K);
    for (std::size_t j = 0; j < mx.taus(); ++j) {
      for (std::size_t k = 0; k < K; ++k) row[k] = mx.dev_at(j, k);
      const auto lo = std::min_element(row.begin(), row.end());
      const auto hi = std::max_element(row.begin(), row.end());
      const std::size_t klo = static_cast<std::size_t>(lo - row.begin());
      const std::size_t khi = static_cast<std::size_t>(hi - row.begin());
      std::vector<double> sorted = row;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(K / 2), sorted.end());
      fmt::print(out, "{:>12.6g} {:>9} {:>13.5e} {:>12.6g} {:>13.5e} {:>13.5e} {:>12.6g} {:>9.4g}\n", mx.tau[j],
                 mx.n[j], *lo, mx.centre[klo], sorted[K / 2], *hi, mx.centre[khi], *lo > 0 ? *hi / *lo : 0.0);
    }
    out << '\n';
  }
  out << "# t: the window's centre, seconds from the record's start; --format csv or json gives every cell\n";
}

// Long format: one row per cell.
void write_csv(std::ostream& out, const pipeline::DavarResult& r) {
  const bool intervals = !r.channels.empty() && r.channels.front().matrix.intervals;
  out << (intervals ? "channel,t,tau,dev,n,lo,hi,edf,alpha\n" : "channel,t,tau,dev,n\n");
  for (const auto& ch : r.channels) {
    const DavarMatrix& mx = ch.matrix;
    for (std::size_t k = 0; k < mx.windows(); ++k)
      for (std::size_t j = 0; j < mx.taus(); ++j) {
        const std::size_t c = mx.cell(j, k);
        fmt::print(out, "{},{},{},{},{}", ch.name, mx.centre[k], mx.tau[j], g(mx.dev[c]), mx.n[j]);
        if (intervals) fmt::print(out, ",{},{},{},{}", g(mx.lo[c]), g(mx.hi[c]), g(mx.edf[c]), mx.alpha[c]);
        out << '\n';
      }
  }
}

int run_davar_command(const DavarCliOptions& o) {
  check_report_option(o.report, o.force);
  ResultOutput result(o.out, o.force);  // refuses an unusable --out before the work
  pipeline::DavarRequest req;
  req.type = *parse_data_type(o.type);
  if (!o.window.empty()) req.window = pipeline::parse_davar_span(o.window, "window");
  if (!o.step.empty()) req.step = pipeline::parse_davar_span(o.step, "step");
  req.grid = parse_taus(o.taus);
  req.intervals.enabled = !o.no_ci;
  if (!(o.ci > 0.0 && o.ci < 1.0)) throw UsageError("--ci must be between 0 and 1 (e.g. 0.683 or 0.95)");
  req.intervals.ci = o.ci;
  req.intervals.edf = o.edf == "simple" ? EdfMethod::simple : EdfMethod::greenhall;
  req.intervals.alpha = o.alpha;
  req.method = o.method == "direct" ? DavarMethod::direct : DavarMethod::fast;
  req.threads = o.input.threads;

  io::SeriesOptions so = to_series_options(o.input);
  so.keep_time = false;  // the rate and the contiguity are all davar needs of the stamps
  const io::Series series = io::read_series(o.input.file, so);
  const pipeline::DavarResult res = pipeline::run_davar(series, req);
  note_default_columns(series);  // after the work: a failed run says one line
  for (const std::string& line : {excluded_taus_warning(res.tau_list), merged_taus_note(res.tau_list)})
    if (!line.empty()) std::cerr << line << '\n';

  std::ostream& out = result.stream();
  if (o.format == "json") {
    nlohmann::json j = pipeline::to_json(res);
    j["invocation"] = invocation();
    out << j.dump() << '\n';
  } else if (o.format == "csv") {
    write_csv(out, res);
  } else {
    write_table(out, res);
  }
  result.finish();
  if (!o.report.dir.empty()) write_report_option(report::davar_report(res, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_davar_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<DavarCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "davar", "Dynamic Allan deviation: OADEV over a window sliding along the record, a tau x time matrix per "
               "channel that shows how the noise changes during a run");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--type", opt->type,
                  "freq: rate-like samples (deg/s, fractional frequency); phase: their integral (angle, time "
                  "error in s)")
      ->check(CLI::IsMember({"freq", "phase"}))
      ->capture_default_str();
  cmd->add_option("--window", opt->window,
                  "Window length: a duration (1h, 30min, 90s, 2d) or a whole number of samples (36000); default: a "
                  "tenth of the record");
  cmd->add_option("--step", opt->step,
                  "How far the window moves each time: a duration (60s) or a whole number of samples; default: a "
                  "tenth of the window");
  cmd->add_option("--taus", opt->taus,
                  "Tau grid: octave, decade, all, log:K (K per decade) or a list of seconds (1,10,100), up to the "
                  "OADEV limit of one window (a quarter of it)")
      ->capture_default_str();
  cmd->add_option("--ci", opt->ci, "Confidence factor of the intervals")
      ->check(number_between(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--edf", opt->edf, "EDF: greenhall (as Stable32) or simple (SP 1065 Table 5)")
      ->check(CLI::IsMember({"greenhall", "simple"}))
      ->capture_default_str();
  cmd->add_option("--alpha", opt->alpha,
                  "Use this noise type (+2 WPM, +1 FPM, 0 WFM, -1 FFM, -2 RWFM) in every cell instead of "
                  "identifying it in each window (faster)")
      ->check(CLI::Range(-2, 2));
  cmd->add_flag("--no-ci", opt->no_ci, "Deviations only: no noise identification and no intervals");
  cmd->add_option("--method", opt->method,
                  "fast (block sums slid along the record) or direct (OADEV of every window anew: the definition, "
                  "much slower; for checking)")
      ->check(CLI::IsMember({"fast", "direct"}))
      ->capture_default_str();
  cmd->add_option("--format", opt->format,
                  "table (per tau: the spread over the windows), csv (one row per cell: channel,t,tau,dev,n, then "
                  "lo,hi,edf,alpha with intervals) or json (per channel, one array per tau)")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->callback([opt, &run] { run = [opt] { return run_davar_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
