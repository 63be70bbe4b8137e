// cubecal calibrate rate-table: gyro scale factors, misalignment and bias
// from a rate-table run (the paper's fourth gyro test, eq. 6-13).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common_options.hpp"
#include "calibration_hints.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/calibrate_rate_table.hpp"
#include "cubecal/pipeline/calibrate_rate_table_json.hpp"
#include "cubecal/report/command_reports.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct RateTableCliOptions {
  InputOptions input;
  std::string ref_columns;
  std::string schedule;
  bool from_signal = false;
  double margin = 10.0;
  double min_plateau = 30.0;
  double ref_tolerance = 1e-6;
  double window = 10.0;
  std::string earth_axis;
  std::string unit = "deg/s";
  std::string format = "table";
  std::string out;
  bool force = false;
  ReportTarget report;  // --report DIR, --gnuplot PATH
};

constexpr const char* kAxes = "xyz";

std::array<double, 3> parse_axis(const std::string& text) {
  const auto items = split_list(text);
  std::array<double, 3> v{};
  bool ok = items.size() == 3;
  for (std::size_t i = 0; ok && i < 3; ++i) {
    try {
      std::size_t used = 0;
      v[i] = std::stod(items[i], &used);
      ok = used == items[i].size() && std::isfinite(v[i]);
    } catch (const std::exception&) {
      ok = false;
    }
  }
  if (!ok) throw UsageError("--earth-axis takes three numbers X,Y,Z (the Earth's axis in the sensor frame)");
  return v;
}

void print_table(std::ostream& out, const pipeline::RateTableResult& r) {
  const RateTableCalibration& c = r.calibration;
  const std::string& u = r.unit;
  fmt::print(out, "{}: {} plateaus from {}", r.file, c.plateaus, pipeline::describe(r.source));
  if (r.found.dropped_short > 0) fmt::print(out, ", {} too short dropped", r.found.dropped_short);
  if (r.found.unmatched > 0) fmt::print(out, ", {} outside the schedule dropped", r.found.unmatched);
  fmt::print(out, "; {} residual dof{}\n", c.dof, c.noise_from_residuals ? "" : " (sigmas from within-plateau noise)");

  fmt::print(out, "\ncalibration  w = A w_g + beta  (paper eq. 6), 1-sigma; beta in {}\n", u);
  for (int i = 0; i < 3; ++i) {
    fmt::print(out, "  {}  A", kAxes[i]);
    for (int k = 0; k < 3; ++k) fmt::print(out, " {:>10.6f} ± {:<8.2g}", c.A[i][k], c.A_sigma[i][k]);
    fmt::print(out, "  beta {:>10.6f} ± {:.2g}\n", c.beta[i], c.beta_sigma[i]);
  }

  fmt::print(out, "\nforward model  w_g = S w + b_g; bias in {}\n", u);
  for (int i = 0; i < 3; ++i)
    fmt::print(out, "  {}  scale-factor error {:>9.1f} ± {:<6.2g} ppm ({:>8.4f} %)   bias {:>10.6f} ± {:.2g}\n",
               kAxes[i], 1e6 * c.scale_factor_error[i], 1e6 * c.scale_factor_error_sigma[i],
               100.0 * c.scale_factor_error[i], c.bias[i], c.bias_sigma[i]);
  fmt::print(out, "  misalignment, mrad (row i leans toward column j by atan(S_ij / S_ii)):\n     {:>20}{:>20}{:>20}\n",
             "x", "y", "z");
  for (int i = 0; i < 3; ++i) {
    fmt::print(out, "  {}  ", kAxes[i]);
    for (int k = 0; k < 3; ++k)
      fmt::print(out, "{:>20}",
                 i == k ? std::string("-")
                        : fmt::format("{:.3f} ± {:.2g}", 1e3 * c.misalignment[i][k], 1e3 * c.misalignment_sigma[i][k]));
    out << '\n';
  }

  fmt::print(out, "\nplateau residuals, {}:  before calibration max {:.4g} rms {:.4g};  after max {:.4g} rms {:.4g}\n",
             u, c.residual_before.max_abs, c.residual_before.rms, c.residual_after.max_abs, c.residual_after.rms);
  fmt::print(out, "error covariance of the calibrated samples (eq. 12), ({})^2:\n", u);
  for (const auto& row : c.error_covariance)
    fmt::print(out, "  {:>12.4e} {:>12.4e} {:>12.4e}\n", row[0], row[1], row[2]);

  fmt::print(out, "\n  {:>3} {:>9} {:>9} {:>6}  {:>26}  {:>32}  {:>29}\n", "#", "t_begin s", "t_end s", "n",
             "reference " + u, "gyro mean " + u, "residual after " + u);
  for (std::size_t k = 0; k < r.found.plateaus.size(); ++k) {
    const Plateau& p = r.found.plateaus[k];
    const auto& e = c.residuals_after[k];
    fmt::print(out,
               "  {:>3} {:>9.1f} {:>9.1f} {:>6}  {:>8.4g} {:>8.4g} {:>8.4g}  {:>10.5f} {:>10.5f} {:>10.5f}  {:>9.2e} "
               "{:>9.2e} {:>9.2e}\n",
               k + 1, p.t_begin, p.t_end, p.n, p.ref[0], p.ref[1], p.ref[2], p.mean[0], p.mean[1], p.mean[2], e[0],
               e[1], e[2]);
  }
}

int run_rate_table_command(const RateTableCliOptions& o) {
  const bool use_ref = !o.ref_columns.empty(), use_schedule = !o.schedule.empty();
  if (use_ref == use_schedule)
    throw UsageError(use_ref ? "give either --ref-columns or --schedule, not both"
                             : "the true rates are needed: give --ref-columns rx,ry,rz (reference rate columns "
                               "of the log) or --schedule FILE (rows t_begin,t_end,wx,wy,wz)");
  if (o.from_signal && !use_schedule)
    throw UsageError("--from-signal labels the plateaus from a schedule: give --schedule FILE");
  const std::vector<std::string> ref_names = split_list(o.ref_columns);
  if (use_ref && ref_names.size() != 3)
    throw UsageError("--ref-columns takes the 3 reference rate columns (rx,ry,rz or 5,6,7)");
  if (!(o.margin >= 0.0) || !(o.min_plateau >= 0.0) || !(o.ref_tolerance >= 0.0) || !(o.window > 0.0))
    throw UsageError("--margin, --min-plateau and --ref-tolerance must be >= 0 and --window > 0 seconds");
  pipeline::RateTableRequest req;
  req.source = use_ref         ? pipeline::PlateauSource::reference
               : o.from_signal ? pipeline::PlateauSource::signal_schedule
                               : pipeline::PlateauSource::schedule;
  req.unit = o.unit;
  if (!o.earth_axis.empty()) req.earth_axis = parse_axis(o.earth_axis);
  req.plateaus.margin_s = o.margin;
  req.plateaus.min_plateau_s = o.min_plateau;
  req.plateaus.ref_tolerance = o.ref_tolerance;
  req.plateaus.window_s = o.window;

  // Refuse to replace a result before spending any time.
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  check_report_option(o.report, o.force);

  if (use_schedule) req.schedule = pipeline::read_schedule(o.schedule);

  io::SeriesOptions so = to_series_options(o.input);
  so.table.extra_columns = ref_names;  // the reference is in physical units: not scaled by --lsb
  const io::Series series = io::read_series(o.input.file, so);

  const HintContext hints{CalibrationCommand::rate_table, use_ref};
  const pipeline::RateTableResult r =
      with_calibration_hints(o.input.file, hints, [&] { return pipeline::calibrate_rate_table(series, req); });

  write_result(result, o.format == "json", r, invocation(),
               [](std::ostream& os, const auto& res) { print_table(os, res); });
  if (!o.report.dir.empty()) write_report_option(report::rate_table_report(r, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_calibrate_rate_table_command(CLI::App& calibrate, Command& run) {
  auto opt = std::make_shared<RateTableCliOptions>();
  CLI::App* cmd = calibrate.add_subcommand(
      "rate-table",
      "Gyro scale factors, misalignment and bias from constant-rate plateaus (paper eq. 6-13): fits "
      "w_g = S w + b_g by least squares and reports w = A w_g + beta with 1-sigma uncertainties. The true rates "
      "come from reference columns of the log (--ref-columns) or from a plateau schedule (--schedule)");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--ref-columns", opt->ref_columns,
                  "Reference (table) rate columns x,y,z in the sensor frame, by name or index, in --unit (not "
                  "divided by --lsb): plateaus are the runs where they stay constant");
  cmd->add_option("--schedule", opt->schedule,
                  "Plateau schedule: CSV rows t_begin,t_end,wx,wy,wz (s, then the true rate per axis) in the "
                  "log's time base (the time column, or sample/rate from 0)");
  cmd->add_flag("--from-signal", opt->from_signal,
                "With --schedule: find the plateaus in the gyro signal (moving standard deviation) and take "
                "only their rates from the schedule, for a log clock that matches the schedule only roughly");
  cmd->add_option("--margin", opt->margin, "Seconds dropped at both ends of each plateau (table settling)")
      ->capture_default_str();
  cmd->add_option("--min-plateau", opt->min_plateau, "Shortest plateau used, seconds after the margins")
      ->capture_default_str();
  cmd->add_option("--ref-tolerance", opt->ref_tolerance,
                  "Largest change of a reference column within one plateau, in --unit")
      ->capture_default_str();
  cmd->add_option("--window", opt->window, "Window of the moving standard deviation (--from-signal), seconds")
      ->capture_default_str();
  cmd->add_option("--earth-axis", opt->earth_axis,
                  "Add the Earth rate (7.2921159e-5 rad/s) along X,Y,Z (the Earth's axis in the sensor frame, "
                  "or its constant projection) to every reference rate; by default it is ignored, as when the "
                  "table compensates it. It only moves the bias");
  cmd->add_option("--unit", opt->unit, "Unit of the gyro (after --lsb) and of the reference rates")
      ->check(CLI::IsMember({"deg/s", "rad/s"}))
      ->capture_default_str();
  cmd->add_option("--format", opt->format, "Output format")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->callback([opt, &run] { run = [opt] { return run_rate_table_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
