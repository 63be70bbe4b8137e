// Subcommands of the cubecal tool. Each registers its options on the parent
// app and returns the function to run once parsing succeeded.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace cubecal::cli {

using Command = std::function<int()>;

CLI::App* add_dev_command(CLI::App& app, Command& run);
CLI::App* add_analyze_command(CLI::App& app, Command& run);
CLI::App* add_simulate_command(CLI::App& app, Command& run);
CLI::App* add_demo_command(CLI::App& app, Command& run);
CLI::App* add_calibrate_command(CLI::App& app, Command& run);
CLI::App* add_report_command(CLI::App& app, Command& run);
CLI::App* add_turnon_command(CLI::App& app, Command& run);
CLI::App* add_compare_command(CLI::App& app, Command& run);
CLI::App* add_psd_command(CLI::App& app, Command& run);
CLI::App* add_davar_command(CLI::App& app, Command& run);
CLI::App* add_status_command(CLI::App& app, Command& run);
CLI::App* add_model_command(CLI::App& app, Command& run);
CLI::App* add_record_command(CLI::App& app, Command& run);
CLI::App* add_plan_command(CLI::App& app, Command& run);
// Registered on the `calibrate` subcommand:
CLI::App* add_calibrate_rate_table_command(CLI::App& calibrate, Command& run);
CLI::App* add_calibrate_mag_command(CLI::App& calibrate, Command& run);
CLI::App* add_calibrate_temperature_command(CLI::App& calibrate, Command& run);
CLI::App* add_calibrate_multiposition_command(CLI::App& calibrate, Command& run);

// The command line as typed (shell-quoted where needed), for result files
// that must say how to reproduce them.
const std::string& invocation();
void set_invocation(int argc, char** argv);

}  // namespace cubecal::cli
