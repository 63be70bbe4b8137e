// cubecal calibrate temperature: polynomial bias(T) per channel with the
// covariance of its coefficients (docs/formulas/drift-covariance-temperature.md §3), in the form a
// flight computer applies: corrected = raw - sum_{p>=1} c_p (T - T_ref)^p.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "common_options.hpp"
#include "calibration_hints.hpp"
#include "cubecal/pipeline/calibrate_temperature.hpp"
#include "cubecal/pipeline/calibrate_temperature_json.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct TemperatureOptions {
  InputOptions input;
  std::string temp_col;
  std::size_t order = 1;
  std::string unit;  // empty: from the column names (units_for), as analyze
  std::string format = "table";
  std::string out;
  bool force = false;
  ReportTarget report;  // --report DIR, --gnuplot PATH
};

std::string table_text(const pipeline::TemperatureResult& r) {
  std::string table =
      fmt::format("{}: bias(T) of order {} on '{}', {} samples\n", r.file, r.order, r.temperature_column, r.samples);
  for (const auto& c : r.channels) {
    const TemperatureFit& f = c.fit;
    table += fmt::format("\n{}  (T_ref {:.3f} degC, R^2 {:.4f}, residual RMS {:.4g} {})\n", c.name, f.t_ref, f.r2,
                         f.residual_rms, r.unit);
    for (std::size_t p = 0; p < f.coeff.size(); ++p)
      table += fmt::format("  c{} = {:>12.6g} ± {:<10.3g} {}\n", p, f.coeff[p], f.coeff_sigma[p], c.coeff_units[p]);
  }
  table += "\nUncertainties: sandwich covariance with batch means (robust to a drifting bias).\n";
  return table;
}

// The channels' one unit: --unit as given, else the unit the column names
// (or the format) announce, the same for every channel; a name without one
// stops the run as in analyze, rather than labelling the coefficients counts.
std::string channel_unit(const TemperatureOptions& o, const io::Series& s) {
  if (!o.unit.empty()) return o.unit;
  const ChannelUnits u = units_for({}, s);
  for (std::size_t c = 1; c < u.units.size(); ++c)
    if (u.units[c].name != u.units[0].name)
      throw UsageError(s.file + ": channel " + s.names[0] + " is in " + u.units[0].name + " and " + s.names[c] +
                       " in " + u.units[c].name +
                       ": the coefficients of one run share one unit: calibrate the channels of each unit in their "
                       "own run (--columns)");
  if (!u.note.empty()) std::cerr << u.note << '\n';
  return u.units.empty() ? std::string("counts") : u.units[0].name;
}

int run_calibrate_temperature(const TemperatureOptions& o) {
  pipeline::TemperatureRequest req;
  req.order = o.order;
  if (!o.unit.empty()) req.unit = o.unit;
  req.validate();
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  check_report_option(o.report, o.force);
  io::SeriesOptions so = to_series_options(o.input);
  so.table.extra_columns = {o.temp_col};
  const io::Series s = io::read_series(o.input.file, so);
  req.unit = channel_unit(o, s);
  const pipeline::TemperatureResult r = with_calibration_hints(o.input.file, {CalibrationCommand::temperature},
                                                               [&] { return pipeline::calibrate_temperature(s, req); });
  result.stream() << (o.format == "json" ? pipeline::json_text(pipeline::to_json(r), 1) + "\n" : table_text(r));
  result.finish();
  if (!o.report.dir.empty()) write_report_option(report::temperature_report(r, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_calibrate_temperature_command(CLI::App& calibrate, Command& run) {
  auto opt = std::make_shared<TemperatureOptions>();
  CLI::App* cmd =
      calibrate.add_subcommand("temperature", "Polynomial bias(T) per channel with the covariance of the coefficients");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--temp-col", opt->temp_col, "Temperature column (degC)")->required();
  cmd->add_option("--order", opt->order, "Polynomial order")->check(CLI::Range(1, 5))->capture_default_str();
  cmd->add_option("--unit", opt->unit,
                  "Unit of the values (after --lsb), one for every channel: the coefficients are in it, per degC^p. "
                  "Default: from the column names' suffixes (_dps, _rads, _dph, _g, _mps2, _uT, _mG, _nT, "
                  "gx[deg/s]...), said on stderr; an error when a name has none (--unit counts for raw values)");
  cmd->add_option("--format", opt->format, "table or json")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file");
  cmd->add_flag("--force", opt->force, "Replace --out and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->callback([opt, &run] { run = [opt] { return run_calibrate_temperature(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
