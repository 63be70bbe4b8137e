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
#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/rate_table.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
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
  std::string report;  // --report DIR
};

constexpr const char* kAxes = "xyz";

// Rows "t_begin,t_end,wx,wy,wz" (a header line is allowed), checked.
std::vector<ScheduleRow> read_schedule(const std::string& path) {
  const io::Table t = io::read_table(path);
  if (t.data.size() != 5)
    throw InputError(path, t.first_data_line, 0,
                         "a schedule has 5 columns (t_begin,t_end,wx,wy,wz), this file has " +
                             std::to_string(t.data.size()));
  std::vector<ScheduleRow> rows(t.rows());
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i] = {t.data[0][i], t.data[1][i], {t.data[2][i], t.data[3][i], t.data[4][i]}};
  if (const auto problem = check_schedule(rows)) {
    const io::Location at = io::locate(t, problem->row, t.indices[0]);
    throw InputError(path, at.line, at.column, problem->what,
                         "one row per plateau, in seconds of the log's time base");
  }
  return rows;
}

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

nlohmann::json matrix_json(const Mat3& m) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& row : m) j.push_back(row);
  return j;
}

// Off-diagonal angles keyed "xy" (axis x leaning toward y), in `scale` units.
nlohmann::json angles_json(const Mat3& m, double scale) {
  nlohmann::json j = nlohmann::json::object();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      if (i != k) j[std::string{kAxes[i], kAxes[k]}] = m[i][k] * scale;
  return j;
}

std::array<double, 3> scaled(const std::array<double, 3>& v, double s) { return {v[0] * s, v[1] * s, v[2] * s}; }

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

struct Context {
  std::string file;
  std::string unit;
  std::string source;       // stable JSON code: reference, schedule, signal+schedule
  std::string source_text;  // for people
  const PlateauDetection* found = nullptr;
  std::array<double, 3> earth_rate{};
};

nlohmann::json result_json(const RateTableCalibration& c, const Context& ctx) {
  const std::string u = ctx.unit;
  nlohmann::json j;
  j["file"] = ctx.file;
  j["invocation"] = invocation();
  j["unit"] = u;
  j["model"] = "w = A w_g + beta (paper eq. 6); forward w_g = S w + b_g, A = S^-1, beta = -S^-1 b_g";
  j["A"] = matrix_json(c.A);
  j["A_sigma"] = matrix_json(c.A_sigma);
  j["beta"] = c.beta;
  j["beta_sigma"] = c.beta_sigma;
  j["residual_before"] = {{"max", c.residual_before.max_abs}, {"rms", c.residual_before.rms}, {"unit", u}};
  j["residual_after"] = {{"max", c.residual_after.max_abs}, {"rms", c.residual_after.rms}, {"unit", u}};
  j["error_covariance"] = matrix_json(c.error_covariance);
  j["error_covariance_unit"] = "(" + u + ")^2";
  j["forward"] = {
      {"S", matrix_json(c.S)},
      {"S_sigma", matrix_json(c.S_sigma)},
      {"bias", c.bias},
      {"bias_sigma", c.bias_sigma},
      {"scale_factor_ppm", scaled(c.scale_factor_error, 1e6)},
      {"scale_factor_ppm_sigma", scaled(c.scale_factor_error_sigma, 1e6)},
      {"scale_factor_percent", scaled(c.scale_factor_error, 100.0)},
      {"misalignment_mrad", angles_json(c.misalignment, 1e3)},
      {"misalignment_mrad_sigma", angles_json(c.misalignment_sigma, 1e3)},
      {"misalignment_deg", angles_json(c.misalignment, kRadToDeg)},
      {"misalignment_convention",
       "key ij: angle by which gyro axis i leans toward reference axis j, atan(S_ij / S_ii)"}};
  j["fit"] = {{"plateaus", c.plateaus},
              {"dof", c.dof},
              {"noise_from_residuals", c.noise_from_residuals},
              {"noise_cov", matrix_json(c.noise_cov)},
              {"earth_rate", ctx.earth_rate}};
  j["plateau_source"] = ctx.source;
  j["plateaus_dropped_short"] = ctx.found->dropped_short;
  j["plateaus_unmatched"] = ctx.found->unmatched;
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < ctx.found->plateaus.size(); ++k) {
    const Plateau& p = ctx.found->plateaus[k];
    list.push_back({{"t_begin", p.t_begin},
                    {"t_end", p.t_end},
                    {"n", p.n},
                    {"ref", p.ref},
                    {"gyro", p.mean},
                    {"gyro_std", p.stddev},
                    {"residual_after", c.residuals_after[k]}});
  }
  j["plateaus"] = list;
  return j;
}

void print_table(std::ostream& out, const RateTableCalibration& c, const Context& ctx) {
  const std::string& u = ctx.unit;
  fmt::print(out, "{}: {} plateaus from {}", ctx.file, c.plateaus, ctx.source_text);
  if (ctx.found->dropped_short > 0) fmt::print(out, ", {} too short dropped", ctx.found->dropped_short);
  if (ctx.found->unmatched > 0) fmt::print(out, ", {} outside the schedule dropped", ctx.found->unmatched);
  fmt::print(out, "; {} residual dof{}\n", c.dof, c.noise_from_residuals ? "" : " (sigmas from within-plateau noise)");

  fmt::print(out, "\ncalibration  w = A w_g + beta  (paper eq. 6), 1-sigma; beta in {}\n", u);
  for (int i = 0; i < 3; ++i) {
    fmt::print(out, "  {}  A", kAxes[i]);
    for (int k = 0; k < 3; ++k) fmt::print(out, " {:>10.6f} ± {:<8.2g}", c.A[i][k], c.A_sigma[i][k]);
    fmt::print(out, "  beta {:>10.6f} ± {:.2g}\n", c.beta[i], c.beta_sigma[i]);
  }

  fmt::print(out, "\nforward model  w_g = S w + b_g; bias in {}\n", u);
  for (int i = 0; i < 3; ++i)
    fmt::print(out, "  {}  scale-factor error {:>9.1f} ± {:<6.2g} ppm ({:>8.4f} %)   bias {:>10.6f} ± {:.2g}\n", kAxes[i],
               1e6 * c.scale_factor_error[i], 1e6 * c.scale_factor_error_sigma[i], 100.0 * c.scale_factor_error[i],
               c.bias[i], c.bias_sigma[i]);
  fmt::print(out, "  misalignment, mrad (row i leans toward column j by atan(S_ij / S_ii)):\n     {:>20}{:>20}{:>20}\n", "x",
             "y", "z");
  for (int i = 0; i < 3; ++i) {
    fmt::print(out, "  {}  ", kAxes[i]);
    for (int k = 0; k < 3; ++k)
      fmt::print(out, "{:>20}", i == k ? std::string("-")
                                       : fmt::format("{:.3f} ± {:.2g}", 1e3 * c.misalignment[i][k],
                                                     1e3 * c.misalignment_sigma[i][k]));
    out << '\n';
  }

  fmt::print(out, "\nplateau residuals, {}:  before calibration max {:.4g} rms {:.4g};  after max {:.4g} rms {:.4g}\n", u,
             c.residual_before.max_abs, c.residual_before.rms, c.residual_after.max_abs, c.residual_after.rms);
  fmt::print(out, "error covariance of the calibrated samples (eq. 12), ({})^2:\n", u);
  for (const auto& row : c.error_covariance) fmt::print(out, "  {:>12.4e} {:>12.4e} {:>12.4e}\n", row[0], row[1], row[2]);

  fmt::print(out, "\n  {:>3} {:>9} {:>9} {:>6}  {:>26}  {:>32}  {:>29}\n", "#", "t_begin s", "t_end s", "n",
             "reference " + u, "gyro mean " + u, "residual after " + u);
  for (std::size_t k = 0; k < ctx.found->plateaus.size(); ++k) {
    const Plateau& p = ctx.found->plateaus[k];
    const auto& r = c.residuals_after[k];
    fmt::print(out, "  {:>3} {:>9.1f} {:>9.1f} {:>6}  {:>8.4g} {:>8.4g} {:>8.4g}  {:>10.5f} {:>10.5f} {:>10.5f}  {:>9.2e} {:>9.2e} {:>9.2e}\n",
               k + 1, p.t_begin, p.t_end, p.n, p.ref[0], p.ref[1], p.ref[2], p.mean[0], p.mean[1], p.mean[2], r[0],
               r[1], r[2]);
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
  const double unit_per_rad_s = o.unit == "deg/s" ? kRadToDeg : 1.0;
  RateTableOptions cal_opt;
  if (!o.earth_axis.empty()) cal_opt.earth_rate = earth_rate_along(parse_axis(o.earth_axis), unit_per_rad_s);

  // Refuse to replace a result before spending any time.
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  check_report_option(o.report, o.force);

  std::vector<ScheduleRow> schedule;
  if (use_schedule) schedule = read_schedule(o.schedule);

  io::SeriesOptions so = to_series_options(o.input);
  so.table.extra_columns = ref_names;  // the reference is in physical units: not scaled by --lsb
  const io::Series series = io::read_series(o.input.file, so);
  if (series.channels.size() != 3)
    throw UsageError("a rate table needs exactly 3 gyro columns, " + std::to_string(series.channels.size()) +
                         " selected (name them with --columns gx,gy,gz)");

  TriadRecord rec;
  for (int a = 0; a < 3; ++a) rec.axes[a] = series.channels[a];
  rec.time = series.time;
  rec.dt = series.tau0;
  std::vector<std::size_t> breaks;
  for (std::size_t s = 1; s < series.segments.size(); ++s) breaks.push_back(series.segments[s].begin);
  rec.breaks = breaks;

  PlateauOptions popt;
  popt.margin_s = o.margin;
  popt.min_plateau_s = o.min_plateau;
  popt.ref_tolerance = o.ref_tolerance;
  popt.window_s = o.window;

  PlateauDetection found;
  Context ctx{o.input.file, o.unit, "", "", &found, cal_opt.earth_rate};
  try {
    if (use_ref) {
      ctx.source = "reference";
      ctx.source_text = "the reference columns";
      found = plateaus_from_reference(rec, {series.extra[0], series.extra[1], series.extra[2]}, popt);
    } else if (o.from_signal) {
      ctx.source = "signal+schedule";
      ctx.source_text = "the gyro signal, rates from the schedule";
      found = label_with_schedule(plateaus_from_signal(rec, popt), schedule);
    } else {
      ctx.source = "schedule";
      ctx.source_text = "the schedule";
      found = plateaus_from_schedule(rec, schedule, popt);
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(o.input.file, 0, 0, e.what(),
                         use_ref ? "check --ref-columns and --ref-tolerance, or lower --margin / --min-plateau"
                                 : "check the schedule's times against the log's, or lower --margin / --min-plateau");
  }

  RateTableCalibration cal;
  try {
    cal = calibrate_rate_table(found.plateaus, cal_opt);
  } catch (const std::invalid_argument& e) {
    throw InputError(o.input.file, 0, 0, e.what(), "the run must turn the gyro about each of its 3 axes");
  }

  std::ostream& out = result.stream();
  if (o.format == "json")
    out << result_json(cal, ctx).dump(2) << '\n';
  else
    print_table(out, cal, ctx);
  result.finish();
  if (!o.report.empty())
    write_report_option(
        report::rate_table_report(found, cal, {invocation(), o.input.file, o.unit, ctx.source_text, cal_opt.earth_rate}),
        o.report);
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
