// cubecal calibrate temperature: polynomial bias(T) per channel with the
// covariance of its coefficients (formulas.md section 4), in the form a
// flight computer applies: corrected = raw - sum_{p>=1} c_p (T - T_ref)^p.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "output.hpp"

namespace cubecal::cli {

namespace {

struct TemperatureOptions {
  InputOptions input;
  std::string temp_col;
  std::size_t order = 1;
  std::string unit = "counts";
  std::string format = "table";
  std::string out;
  bool force = false;
};

int run_calibrate_temperature(const TemperatureOptions& o) {
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  io::SeriesOptions so = to_series_options(o.input);
  so.table.extra_columns = {o.temp_col};
  const io::Series s = io::read_series(o.input.file, so);
  const auto& temp = s.extra.at(0);
  nlohmann::json j;
  j["file"] = o.input.file;
  j["temperature_column"] = s.extra_names.at(0);
  j["order"] = o.order;
  j["model"] = "bias(T) = sum_p coeff[p] (T - t_ref)^p; corrected = raw - sum_{p>=1} coeff[p] (T - t_ref)^p";
  std::string table = fmt::format("{}: bias(T) of order {} on '{}', {} samples\n", o.input.file, o.order,
                                  s.extra_names.at(0), s.samples());
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    TemperatureFit f;
    try {
      f = fit_temperature(s.channels[c], temp, o.order);
    } catch (const std::invalid_argument& e) {
      throw UsageError(s.names[c] + ": " + e.what());
    }
    std::vector<std::string> units;
    for (std::size_t p = 0; p < f.coeff.size(); ++p)
      units.push_back(p == 0 ? o.unit : o.unit + (p == 1 ? "/degC" : "/degC^" + std::to_string(p)));
    j["channels"].push_back({{"name", s.names[c]},
                             {"t_ref", f.t_ref},
                             {"coeff", f.coeff},
                             {"coeff_sigma", f.coeff_sigma},
                             {"coeff_units", units},
                             {"covariance", f.cov},
                             {"r2", f.r2},
                             {"residual_rms", f.residual_rms}});
    table += fmt::format("\n{}  (T_ref {:.3f} degC, R^2 {:.4f}, residual RMS {:.4g} {})\n", s.names[c], f.t_ref, f.r2,
                         f.residual_rms, o.unit);
    for (std::size_t p = 0; p < f.coeff.size(); ++p)
      table += fmt::format("  c{} = {:>12.6g} ± {:<10.3g} {}\n", p, f.coeff[p], f.coeff_sigma[p], units[p]);
  }
  table += "\nUncertainties: sandwich covariance with batch means (robust to a drifting bias).\n";
  const std::string text = o.format == "json" ? j.dump(1) + "\n" : table;
  result.stream() << text;
  result.finish();
  return 0;
}

}  // namespace

CLI::App* add_calibrate_temperature_command(CLI::App& calibrate, Command& run) {
  auto opt = std::make_shared<TemperatureOptions>();
  CLI::App* cmd = calibrate.add_subcommand(
      "temperature", "Polynomial bias(T) per channel with the covariance of the coefficients");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--temp-col", opt->temp_col, "Temperature column (degC)")->required();
  cmd->add_option("--order", opt->order, "Polynomial order")->check(CLI::Range(1, 5))->capture_default_str();
  cmd->add_option("--unit", opt->unit, "Unit of the channels (for the coefficient units)")->capture_default_str();
  cmd->add_option("--format", opt->format, "table or json")->check(CLI::IsMember({"table", "json"}))->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file");
  cmd->add_flag("--force", opt->force, "Replace --out if it exists");
  cmd->callback([opt, &run] { run = [opt] { return run_calibrate_temperature(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
