/// @file
/// `calibrate rate-table` as one call: the gyro record (already read) and the
/// request in, the plateaus found and the calibration fitted to them out (the
/// paper's fourth gyro test, eq. 6-13). JSON form: calibrate_rate_table_json.hpp.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/rate_table.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::pipeline {

/// Where the true rate of each plateau comes from.
enum class PlateauSource {
  reference,        ///< reference columns of the log (Series::extra[0..2]): runs where they stay constant
  schedule,         ///< the schedule's rows cut the record
  signal_schedule,  ///< plateaus found in the gyro signal, labelled with the schedule's rates
};

std::string_view to_string(PlateauSource s) noexcept;  ///< "reference", "schedule", "signal+schedule"
/// The source named `s` ("reference", "schedule", "signal+schedule"), or nullopt. Throws nothing.
std::optional<PlateauSource> parse_plateau_source(std::string_view s) noexcept;
/// For people: "the reference columns", "the schedule", ...
std::string_view describe(PlateauSource s) noexcept;

/// What `calibrate rate-table` is asked to do (the record already read).
struct RateTableRequest {
  /// Where the plateaus' true rates come from.
  PlateauSource source = PlateauSource::reference;
  std::vector<ScheduleRow> schedule;  ///< schedule and signal_schedule: checked rows (check_schedule)
  PlateauOptions plateaus;            ///< margins, shortest plateau, tolerances, window
  std::string unit = "deg/s";         ///< of the gyro and the reference rates: "deg/s" or "rad/s"
  /// The Earth's axis in the sensor frame: the Earth rate along it is added to
  /// every reference rate. Unset: ignored (a table that compensates it).
  std::optional<std::array<double, 3>> earth_axis;
};

/// A rate-table calibration with what an output needs.
struct RateTableResult {
  std::string file;  ///< the record's file (Series::file)
  /// The gyro's unit: "deg/s" or "rad/s".
  std::string unit = "deg/s";
  /// Where the plateaus' true rates came from.
  PlateauSource source = PlateauSource::reference;
  std::array<double, 3> earth_rate{};  ///< added to every reference rate, in `unit`
  PlateauDetection found;              ///< the plateaus fitted, what was dropped
  RateTableCalibration calibration;    ///< residuals_after in the order of found.plateaus
};

/// `series` holds the 3 gyro channels, and for PlateauSource::reference the 3
/// reference columns as Series::extra (in `unit`, not scaled). Throws
/// UsageError (option "columns": not 3 gyro channels; "reference_columns",
/// "schedule", "plateaus", "unit"); the core's CalibrationError as it is
/// (no_plateaus from the detection; too_few_points, degenerate or bad_data from
/// the fit: calib/plateaus.hpp, calib/rate_table.hpp).
RateTableResult calibrate_rate_table(const io::Series& series, const RateTableRequest& request);

/// A schedule file: rows "t_begin,t_end,wx,wy,wz" (a header line is allowed),
/// checked by check_schedule. InputError at the file's place for another
/// column count or a row check_schedule refuses.
std::vector<ScheduleRow> read_schedule(const std::string& path);

}  // namespace cubecal::pipeline
