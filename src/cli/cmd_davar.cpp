// cubecal davar: the dynamic Allan deviation, OADEV over a window sliding
// along the record (docs/formulas/davar.md), as a tau x time matrix per
// channel.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/davar_pipeline.hpp"
#include "cubecal/pipeline/json_text.hpp"
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

// Per channel and tau: the spread of the deviation over the windows (the
// windows with a value: with missing samples a cell may have no whole term).
void write_table(std::ostream& out, const pipeline::DavarResult& r) {
  const double tau0 = 1.0 / r.rate_hz;
  bool missing = false;
  for (const auto& ch : r.channels) {
    const DavarMatrix& mx = ch.matrix;
    const std::size_t K = mx.windows();
    missing = missing || mx.missing > 0;
    fmt::print(
        out, "# {}: {} — dynamic OADEV, {} windows of {} samples ({:.6g} s) every {} samples ({:.6g} s), {} Hz{}\n",
        r.file, ch.name, K, r.window, static_cast<double>(r.window) * tau0, r.step, static_cast<double>(r.step) * tau0,
        rate_text(r.rate_hz), mx.missing > 0 ? fmt::format(", {} missing sample(s)", mx.missing) : std::string());
    fmt::print(out, "{:>12} {:>9} {:>13} {:>12} {:>13} {:>13} {:>12} {:>9}\n", "tau [s]", "n", "min", "at t [s]",
               "median", "max", "at t [s]", "max/min");
    std::vector<std::size_t> with_value;  // windows whose cell has a value
    for (std::size_t j = 0; j < mx.taus(); ++j) {
      with_value.clear();
      std::size_t fewest = mx.n[j];
      for (std::size_t k = 0; k < K; ++k) {
        fewest = std::min(fewest, mx.terms_at(j, k));
        if (!std::isnan(mx.dev_at(j, k))) with_value.push_back(k);
      }
      if (with_value.empty()) {
        fmt::print(out, "{:>12.6g} {:>9} {:>13}\n", mx.tau[j], fewest, "no window has a whole term");
        continue;
      }
      const auto by_dev = [&](std::size_t a, std::size_t b) { return mx.dev_at(j, a) < mx.dev_at(j, b); };
      const std::size_t klo = *std::min_element(with_value.begin(), with_value.end(), by_dev);
      const std::size_t khi = *std::max_element(with_value.begin(), with_value.end(), by_dev);
      std::vector<double> sorted;
      for (const std::size_t k : with_value) sorted.push_back(mx.dev_at(j, k));
      const std::size_t half = sorted.size() / 2;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(half), sorted.end());
      const double lo = mx.dev_at(j, klo), hi = mx.dev_at(j, khi);
      fmt::print(out, "{:>12.6g} {:>9} {:>13.5e} {:>12.6g} {:>13.5e} {:>13.5e} {:>12.6g} {:>9.4g}\n", mx.tau[j], fewest,
                 lo, mx.centre[klo], sorted[half], hi, mx.centre[khi], lo > 0 ? hi / lo : 0.0);
    }
    out << '\n';
  }
  out << "# t: the window's centre, seconds from the record's start; --format csv or json gives every cell\n";
  if (missing)
    out << "# n: the fewest whole terms of a window (--gaps skip leaves out the terms that need a missing sample); "
           "min, median and max over the windows with a value\n";
}

// Long format: one row per cell; a cell without a whole term (missing
// samples) has empty dev, lo, hi, edf and alpha fields.
void write_csv(std::ostream& out, const pipeline::DavarResult& r) {
  const bool intervals = !r.channels.empty() && r.channels.front().matrix.intervals;
  out << (intervals ? "channel,t,tau,dev,n,lo,hi,edf,alpha\n" : "channel,t,tau,dev,n\n");
  for (const auto& ch : r.channels) {
    const DavarMatrix& mx = ch.matrix;
    for (std::size_t k = 0; k < mx.windows(); ++k)
      for (std::size_t j = 0; j < mx.taus(); ++j) {
        const std::size_t c = mx.cell(j, k);
        const bool value = !std::isnan(mx.dev[c]);
        fmt::print(out, "{},{},{},{},{}", ch.name, mx.centre[k], mx.tau[j], value ? g(mx.dev[c]) : "",
                   mx.terms_at(j, k));
        if (intervals && value) fmt::print(out, ",{},{},{},{}", g(mx.lo[c]), g(mx.hi[c]), g(mx.edf[c]), mx.alpha[c]);
        if (intervals && !value) out << ",,,,";
        out << '\n';
      }
  }
}

int run_davar_command(const DavarCliOptions& o) {
  check_report_option(o.report, o.force);
  ResultOutput result(o.out, o.force);  // refuses an unusable --out before the work
  pipeline::DavarRequest req;
  req.type = *parse_data_type(o.type);
  if (!o.window.empty()) req.window = pipeline::parse_davar_span(o.window, Field::window);
  if (!o.step.empty()) req.step = pipeline::parse_davar_span(o.step, Field::step);
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
  if (series.gaps == io::GapPolicy::skip) {
    std::size_t missing = 0, empty = 0;
    for (const auto& ch : res.channels) {
      missing += ch.matrix.missing;
      for (const double d : ch.matrix.dev) empty += std::isnan(d) ? 1 : 0;
    }
    std::cerr << fmt::format(
        "cubecal: note: {}: {} missing sample(s) in {} channel(s) of {} samples: each window's "
        "OADEV leaves out the terms that need one (--gaps skip){}\n",
        series.file, missing, series.channels.size(), series.samples(),
        empty > 0 ? fmt::format("; {} cell(s) have no whole term and no value", empty) : std::string());
  }
  for (const std::string& line : {excluded_taus_warning(res.tau_list), merged_taus_note(res.tau_list)})
    if (!line.empty()) std::cerr << line << '\n';

  std::ostream& out = result.stream();
  if (o.format == "json") {
    nlohmann::json j = pipeline::to_json(res);
    j["invocation"] = invocation();
    out << pipeline::json_text(j) << '\n';
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
      "davar",
      "Dynamic Allan deviation: OADEV over a window sliding along the record, a tau x time matrix per "
      "channel that shows how the noise changes during a run");
  add_input_options(*cmd, opt->input);
  opt->input.missing_samples = true;  // --gaps skip
  cmd->get_option("--gaps")->description(
      "What to do with time gaps or jitter beyond 1 % of the period: error (default) or skip (empty fields, NaN "
      "and gaps of whole periods are missing samples: each window's OADEV leaves out the terms that need one, "
      "as dev --gaps skip; a cell without a whole term has no value: an empty field in CSV, null in JSON); with "
      "split, a record cut at a gap is refused (one window slides along one contiguous record)");
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
