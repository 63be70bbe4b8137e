// cubecal calibrate: rate-table, magnetometer, temperature and multi-position calibration.
#include "commands.hpp"

namespace cubecal::cli {

CLI::App* add_calibrate_command(CLI::App& app, Command& run) {
  CLI::App* cmd = app.add_subcommand("calibrate",
                                     "Calibration from lab logs: rate-table (gyro scale factor, "
                                     "misalignment, bias), mag (TWOSTEP, ellipsoid), temperature (bias(T)), "
                                     "multiposition (accelerometer and gyro without a turntable)");
  cmd->require_subcommand(1);
  add_calibrate_rate_table_command(*cmd, run);
  add_calibrate_mag_command(*cmd, run);
  add_calibrate_temperature_command(*cmd, run);
  add_calibrate_multiposition_command(*cmd, run);
  return cmd;
}

}  // namespace cubecal::cli
