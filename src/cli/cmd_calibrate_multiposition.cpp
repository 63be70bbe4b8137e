// cubecal calibrate multiposition: accelerometer (and gyroscope) calibration
// from a sequence of static poses, without a turntable (Tedaldi, Pretto &
// Menegatti 2014; docs/formulas/multiposition.md). X' = T K (X - B) for each triad.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "commands.hpp"
#include "common_options.hpp"
#include "calibration_hints.hpp"
#include "cubecal/calib/multiposition.hpp"
#include "cubecal/pipeline/calibrate_multiposition.hpp"
#include "cubecal/pipeline/calibrate_multiposition_json.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/error.hpp"
#include "cubecal/stats/sampling.hpp"
#include "cubecal/report/command_reports.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

namespace mp = cubecal::multipos;

struct MultiposCliOptions {
  std::string acc_file;
  std::string gyro_file;
  std::string acc_columns;
  std::string gyro_columns;
  std::string time_col;
  double rate_hz = 0.0;
  std::size_t skip_rows = 0;
  double g = 9.80665;
  double init_static = 50.0;
  std::size_t window = mp::kDefaultWindow;
  std::size_t interval_samples = mp::kIntervalSamples;
  std::size_t min_intervals = mp::kMinIntervals;
  std::vector<double> acc_bias{0.0};
  double acc_scale = 0.0;
  double gyro_scale = 1.0;
  bool refine_gyro_bias = false;
  bool use_means = false;
  std::string format = "table";
  std::string out;
  bool force = false;
  unsigned threads = 0;
  ReportTarget report;  // --report DIR, --gnuplot PATH
};

// Reads one file: the given columns (3 or 6), split into triads, and the time
// column when asked. Time stamps must increase (FILE:LINE:COL otherwise).
std::vector<pipeline::TriadSamples> read_triads(const std::string& path, const std::vector<std::string>& columns,
                                                const MultiposCliOptions& o, const char* what_columns) {
  io::TableOptions to;
  to.columns = columns;
  if (!o.time_col.empty()) to.extra_columns = {o.time_col};
  to.skip_rows = o.skip_rows;
  to.threads = o.threads;
  const io::Table tab = io::read_table(path, to);
  const std::size_t want = columns.empty() ? 3 : columns.size();
  if (tab.data.size() != want || want % 3 != 0)
    throw UsageError(fmt::format("{}: {} data columns{}: choose three with {}", path, tab.data.size(),
                                 o.time_col.empty() ? "" : " besides the time column", what_columns));
  if (!o.time_col.empty()) {
    const auto& t = tab.extra[0];
    const auto at = [&](std::size_t i) { return io::locate(tab, i, tab.extra_indices[0]); };
    for (std::size_t i = 1; i < t.size(); ++i)
      if (!(t[i] > t[i - 1]) || !std::isfinite(t[i] - t[i - 1]))
        throw InputError(path, at(i).line, at(i).column,
                         fmt::format("time stamps not increasing ({} s after {} s)", t[i], t[i - 1]),
                         "check --time-col");
    // The gyroscope is integrated over the stamped intervals between poses:
    // a missing sample loses rotation, so a gap is refused; jitter is used
    // as stamped, and said.
    const SamplingCheck sc = check_sampling(t);
    if (sc.gaps > 0) {
      const std::size_t i = sc.first_gap;
      throw InputError(path, at(i).line, at(i).column,
                       fmt::format("gap of {:.6g} s ({:.0f} periods of {:.6g} s) after t = {:.10g} s{}",
                                   t[i] - t[i - 1], (t[i] - t[i - 1]) / sc.period_s, sc.period_s, t[i - 1],
                                   sc.gaps > 1 ? fmt::format(", and {} more gaps", sc.gaps - 1) : ""),
                       "the calibration integrates the gyroscope between poses and needs every sample: record "
                       "again, or cut the file to a stretch without gaps");
    }
    if (sc.jittered > 0) {
      const io::Location j = at(sc.first_jitter);
      std::cerr << fmt::format(
          "cubecal: note: {}:{}: {} of {} time intervals differ from the period {:.6g} s by more than 1 % (largest "
          "{:.3g} %); they are used as stamped\n",
          path, j.line, sc.jittered, sc.intervals, sc.period_s, 100.0 * sc.max_jitter);
    }
  }
  std::vector<pipeline::TriadSamples> out(want / 3);
  for (std::size_t k = 0; k < out.size(); ++k) {
    pipeline::TriadSamples& tr = out[k];
    tr.file = path;
    if (!o.time_col.empty()) tr.t = tab.extra[0];
    tr.x.resize(tab.rows());
    for (std::size_t i = 0; i < tab.rows(); ++i)
      tr.x[i] = {tab.data[3 * k][i], tab.data[3 * k + 1][i], tab.data[3 * k + 2][i]};
  }
  return out;
}

void print_params(std::ostream& out, const std::vector<std::string>& names, const std::vector<double>& v,
                  const std::vector<double>& s, const std::vector<std::string>& units) {
  for (std::size_t i = 0; i < names.size(); ++i)
    fmt::print(out, "  {:<7} {:>15.8g} ± {:<10.3g} {}\n", names[i], v[i], s[i], units[i]);
}

void print_matrix(std::ostream& out, const char* label, const Mat3& m) {
  for (std::size_t i = 0; i < 3; ++i)
    fmt::print(out, "  {:<4} [{:>13.6g} {:>13.6g} {:>13.6g}]\n", i == 1 ? label : "", m[i][0], m[i][1], m[i][2]);
}

void print_table(std::ostream& out, const pipeline::MultipositionResult& r) {
  const mp::AccResult& a = r.accelerometer;
  const auto& g = r.gyroscope;
  const mp::Options& opt = r.options;
  fmt::print(out, "Multi-position calibration without a turntable (Tedaldi, Pretto & Menegatti 2014)\n");
  fmt::print(out, "accelerometer {}{}\n", r.acc_file,
             r.gyro_file ? fmt::format(", gyroscope {}", *r.gyro_file == r.acc_file ? "(same file)" : *r.gyro_file)
                         : std::string());
  fmt::print(out, "{} samples at {:.6g} Hz; g = {:.6g}; initial static period {:.6g} s ({} samples, |var| {:.4g})\n",
             r.samples, r.rate_hz, opt.g, opt.init_static_s, a.init_samples, a.init_variance_norm);
  fmt::print(out, "static intervals: {} (th_mult {} of {}..{}, threshold {:.4g}; window {}, {} {} per interval)\n",
             a.intervals.size(), a.th_mult, opt.th_mult_min, opt.th_mult_max, a.threshold,
             mp::normalised_window(opt.window), opt.acc_use_means ? "mean of" : "first", opt.interval_samples);
  fmt::print(out, "  th_mult  ");
  for (const mp::Trial& t : a.trials) fmt::print(out, " {:>9}", t.th_mult);
  fmt::print(out, "\n  intervals");
  for (const mp::Trial& t : a.trials) fmt::print(out, " {:>9}", t.intervals);
  fmt::print(out, "\n  cost     ");
  for (const mp::Trial& t : a.trials)
    fmt::print(out, " {:>9}", t.fitted ? fmt::format("{:.4g}", t.cost) : std::string("-"));
  fmt::print(out, "\n\nAccelerometer  a' = T K (a - B), 1 sigma\n");
  print_params(out, a.names, a.values, a.sigma, pipeline::multiposition_acc_units());
  print_matrix(out, "T", a.model.misalignment());
  fmt::print(out, "  |g| - |a'| over {} residuals: rms {:.5g} -> {:.5g}, max {:.5g} -> {:.5g} (g units)\n",
             a.after.count, a.before.rms, a.after.rms, a.before.max, a.after.max);
  fmt::print(out, "  cost sum r^2 {:.6g} -> {:.6g}; {} iterations{}\n", a.before.cost, a.after.cost, a.iterations,
             a.converged ? "" : " (not converged)");
  if (opt.acc_scale_guess == 0.0)
    fmt::print(out, "  (before: bias guess and the isotropic scale g / mean|a - B| of the initial period)\n");
  if (!g) return;
  fmt::print(out, "\nGyroscope  w' = T K (w - B), w' in rad/s, 1 sigma (incl. accelerometer and bias errors)\n");
  print_params(out, g->names, g->values, g->sigma, pipeline::multiposition_gyro_units(g->names.size()));
  print_matrix(out, "T", g->model.misalignment());
  fmt::print(out, "  B {:>13.6g} {:>13.6g} {:>13.6g} raw ± {:.3g} {:.3g} {:.3g} ({})\n", g->model.bias[0],
             g->model.bias[1], g->model.bias[2], g->bias_sigma[0], g->bias_sigma[1], g->bias_sigma[2],
             g->names.size() == 12 ? "initial-period mean, refined" : "initial-period mean");
  fmt::print(out,
             "  gravity direction after integration between {} pose pairs: rms {:.4g} -> {:.4g} deg, max {:.4g} deg\n",
             g->pairs, g->angle_rms_before_deg, g->angle_rms_after_deg, g->angle_max_after_deg);
  fmt::print(out, "  cost sum |R^-1 u_(k-1) - u_k|^2 {:.6g} -> {:.6g}; {} iterations{}\n", g->before.cost,
             g->after.cost, g->iterations, g->converged ? "" : " (not converged)");
  fmt::print(out, "  (before: scale guess {:.6g} rad/s/raw, no misalignment)\n", opt.gyro_scale_guess);
}

int run_calibrate_multiposition(const MultiposCliOptions& o) {
  if (!o.time_col.empty() && o.rate_hz > 0.0) throw UsageError("give --time-col or --rate, not both");
  if (o.time_col.empty() && !(o.rate_hz > 0.0))
    throw UsageError("give the time column (--time-col) or the sampling rate (--rate)");
  if (o.acc_bias.size() != 1 && o.acc_bias.size() != 3) throw UsageError("--acc-bias takes one value or three (x,y,z)");
  const std::vector<std::string> acc_cols = split_list(o.acc_columns);
  const std::vector<std::string> gyro_cols = split_list(o.gyro_columns);
  if (!acc_cols.empty() && acc_cols.size() != 3) throw UsageError("--acc-columns takes three columns");
  if (!gyro_cols.empty() && gyro_cols.size() != 3) throw UsageError("--gyro-columns takes three columns");

  ResultOutput result(o.out, o.force);  // every output checked before the files are read
  check_report_option(o.report, o.force);
  pipeline::TriadSamples acc;
  std::optional<pipeline::TriadSamples> gyro;
  if (o.gyro_file.empty() && !gyro_cols.empty()) {
    // One file with both triads.
    if (acc_cols.empty()) throw UsageError("give --acc-columns with --gyro-columns for a single file");
    std::vector<std::string> cols = acc_cols;
    cols.insert(cols.end(), gyro_cols.begin(), gyro_cols.end());
    auto both = read_triads(o.acc_file, cols, o, "--acc-columns and --gyro-columns");
    acc = std::move(both[0]);
    gyro = std::move(both[1]);
  } else {
    acc = std::move(read_triads(o.acc_file, acc_cols, o, "--acc-columns")[0]);
    if (!o.gyro_file.empty())
      gyro = std::move(read_triads(o.gyro_file, gyro_cols.empty() ? acc_cols : gyro_cols, o, "--gyro-columns")[0]);
  }

  pipeline::MultipositionRequest req;
  mp::Options& opt = req.options;
  opt.g = o.g;
  opt.init_static_s = o.init_static;
  opt.window = o.window;
  opt.interval_samples = o.interval_samples;
  opt.min_intervals = o.min_intervals;
  opt.acc_use_means = o.use_means;
  opt.acc_bias_guess = o.acc_bias.size() == 3 ? Vec3{o.acc_bias[0], o.acc_bias[1], o.acc_bias[2]}
                                              : Vec3{o.acc_bias[0], o.acc_bias[0], o.acc_bias[0]};
  opt.acc_scale_guess = o.acc_scale;
  opt.gyro_scale_guess = o.gyro_scale;
  opt.refine_gyro_bias = o.refine_gyro_bias;
  req.rate_hz = o.rate_hz;

  const HintContext hints{CalibrationCommand::multiposition};
  pipeline::MultipositionResult r = with_calibration_hints(
      o.acc_file, hints, [&] { return pipeline::calibrate_multiposition_accelerometer(acc, req); });
  if (gyro) {
    HintContext gyro_hints = hints;
    gyro_hints.gyroscope = true;
    with_calibration_hints(gyro->file, gyro_hints, [&] { pipeline::add_multiposition_gyroscope(r, acc, *gyro, req); });
  }

  write_result(result, o.format == "json", r, invocation(),
               [](std::ostream& os, const auto& res) { print_table(os, res); });
  if (!o.report.dir.empty()) write_report_option(report::multiposition_report(r, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_calibrate_multiposition_command(CLI::App& calibrate, Command& run) {
  auto opt = std::make_shared<MultiposCliOptions>();
  CLI::App* cmd = calibrate.add_subcommand(
      "multiposition",
      "Accelerometer (and gyroscope) calibration from static poses without a turntable (Tedaldi et al. 2014): "
      "X' = T K (X - B); the accelerometer from |a'| = g over >= 12 static poses, the gyroscope by integrating "
      "between them");
  cmd->add_option("acc_file", opt->acc_file, "Accelerometer record: delimited text, optionally gzip")->required();
  cmd->add_option("gyro_file", opt->gyro_file,
                  "Gyroscope record (same layout and clock); omit for the accelerometer alone, or give "
                  "--gyro-columns for a file holding both");
  cmd->add_option("--acc-columns", opt->acc_columns,
                  "The 3 accelerometer columns, by header name or 1-based index (ax,ay,az or 2,3,4); default: "
                  "every column but the time column, which must then be 3");
  cmd->add_option("--gyro-columns", opt->gyro_columns,
                  "The 3 gyroscope columns (default with GYRO_FILE: those of --acc-columns); without GYRO_FILE, "
                  "read from ACC_FILE");
  cmd->add_option("--time-col", opt->time_col, "Time column (s), by name or index");
  cmd->add_option("--rate", opt->rate_hz, "Sampling rate in Hz (when there is no time column)")
      ->check(positive_number());
  cmd->add_option("--skip-rows", opt->skip_rows, "Lines to skip before the header/data (preamble), in each file");
  cmd->add_option("--g", opt->g, "Local gravity magnitude: |a'| after calibration (sets the unit of a')")
      ->capture_default_str();
  cmd->add_option("--init-static", opt->init_static,
                  "Initial static period (s): sets the static threshold and the gyroscope bias")
      ->capture_default_str();
  cmd->add_option("--window", opt->window, "Centred variance window (samples, odd, >= 11)")->capture_default_str();
  cmd->add_option("--interval-samples", opt->interval_samples,
                  "Samples taken from each static interval (and its minimum length)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->capture_default_str();
  cmd->add_option("--min-intervals", opt->min_intervals,
                  "Static intervals required (the paper's rule is 12; fewer weakens the calibration)")
      ->check(CLI::Range(std::size_t{4}, std::size_t{100000}))
      ->capture_default_str();
  cmd->add_option("--acc-bias", opt->acc_bias,
                  "Initial accelerometer bias guess (raw), one value or x,y,z (e.g. 32768 for offset-binary)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--acc-scale", opt->acc_scale,
                  "Initial accelerometer scale guess (g units per raw); 0: g / mean|a - bias| of the initial period")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--gyro-scale", opt->gyro_scale,
                  "Initial gyroscope scale guess (rad/s per raw count), e.g. 1.3323e-4 for an MPU-6050 at 250 deg/s")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--refine-gyro-bias", opt->refine_gyro_bias,
                "Fit 3 gyroscope bias corrections besides the 9 parameters");
  cmd->add_flag("--use-means", opt->use_means, "One accelerometer residual per interval (its mean)");
  cmd->add_option("--format", opt->format, "table or json")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file");
  cmd->add_flag("--force", opt->force, "Replace --out and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->add_option("--threads", opt->threads, "Reader threads (default: all cores)");
  cmd->callback([opt, &run] { run = [opt] { return run_calibrate_multiposition(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
