/// @file
/// Plateaus of a rate-table run: the segments where the table turned at a
/// constant rate, with the gyro mean over each (the input of the rate-table
/// calibration, docs/formulas/rate-table.md §6; the paper's fourth test,
/// docs/paper.md §2.1 and §2.6).
///
/// Three ways to find them:
///  (a) from reference-rate columns logged with the gyro (table encoder or
///      commanded rate): runs where the reference vector stays constant;
///  (b) from the gyro signal alone: where a moving standard deviation is at
///      the noise level and the moving mean does not jump; the true rates then
///      come from a schedule (label_with_schedule);
///  (c) from a schedule: the intervals at which the table held each rate.
/// Every plateau loses `margin_s` at both ends (the table settling after a
/// transition) and is kept only if what remains lasts `min_plateau_s`. No
/// plateau spans a gap of the record.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cubecal {

/// A three-axis rate record as the plateau detection sees it.
struct TriadRecord {
  std::array<std::span<const double>, 3> axes;  ///< gyro samples per axis, data unit
  std::span<const double> time;                 ///< s, one per sample; empty: t_k = k * dt
  double dt = 0.0;                              ///< sampling period, s (> 0)
  /// Indices of the samples that start a new contiguous piece (after a time
  /// gap), ascending; 0 may be omitted. Nothing is averaged across them.
  std::span<const std::size_t> breaks;
};

/// One plateau of a rate-table record: a run of samples at one table rate, with its gyro statistics (data unit).
struct Plateau {
  std::size_t begin = 0;  ///< first sample
  std::size_t end = 0;    ///< one past the last sample
  double t_begin = 0.0;   ///< s, time of the first sample
  double t_end = 0.0;     ///< s, time of the last sample
  /// Samples averaged: end - begin, or fewer when signal detection merged two
  /// pieces of one plateau around a short disturbance (the disturbance is not
  /// averaged).
  std::size_t n = 0;
  std::array<double, 3> mean{};    ///< gyro mean per axis
  std::array<double, 3> stddev{};  ///< gyro sample standard deviation per axis (n - 1)
  /// Sample covariance of the gyro axes (n - 1), for the covariance of the
  /// calibrated errors over all plateau samples (the paper's eq. 12,
  /// docs/formulas/rate-table.md §4.2).
  std::array<std::array<double, 3>, 3> cov{};
  std::array<double, 3> ref{};  ///< true rate (reference or schedule), data unit
  /// True when `ref` holds a reference or schedule rate.
  bool has_ref = false;
};

/// How plateaus are cut from a record (times in seconds).
struct PlateauOptions {
  double margin_s = 10.0;       ///< dropped at both ends of every plateau
  double min_plateau_s = 30.0;  ///< shorter plateaus (after the margins) are dropped
  /// (a) A run of the reference holds every sample whose reference differs
  /// from the run's first sample by at most this much on each axis (data
  /// unit). Commanded rates are exactly constant; encoder rates need more.
  double ref_tolerance = 1e-6;
  /// (b) Moving window (s) of the standard deviation and of the jump test.
  double window_s = 10.0;
  /// (b) A sample is steady when, on every axis, the moving standard
  /// deviation is at most `steady_factor` times the quiet noise level...
  double steady_factor = 3.0;
  /// ...and the means of the windows just before and just after it differ by
  /// at most `jump_sigma` of their standard error.
  double jump_sigma = 6.0;
};

/// The plateaus of a record and what detection left out.
struct PlateauDetection {
  std::vector<Plateau> plateaus;  ///< in time order
  std::size_t dropped_short = 0;  ///< runs or rows left with less than min_plateau_s
  std::size_t unmatched = 0;      ///< (b)+schedule: plateaus no schedule row covered (dropped)
  std::size_t skipped_rows = 0;   ///< (c): schedule rows entirely outside the record
  /// (b): noise level per axis, the 25th percentile of the standard deviations
  /// of non-overlapping windows (the quietest windows are on plateaus).
  std::array<double, 3> noise{};
};

/// One row of a plateau schedule: the table held `rate` (data unit, sensor
/// frame) from t_begin to t_end (s, the record's time base).
struct ScheduleRow {
  /// Start of the row (s, the record's time base).
  double t_begin = 0.0;
  /// End of the row (s, the record's time base).
  double t_end = 0.0;
  /// The table's rate per axis (data unit, sensor frame).
  std::array<double, 3> rate{};
};

/// The first problem of a schedule: a non-finite value, t_end <= t_begin, or
/// intervals that overlap (touching is allowed). `row` is 0-based.
struct ScheduleProblem {
  /// The row at fault (0-based).
  std::size_t row = 0;
  /// What is wrong with it.
  std::string what;
};
/// The first problem of a schedule, or nullopt for a good one. Throws nothing.
std::optional<ScheduleProblem> check_schedule(std::span<const ScheduleRow> rows);

// Every function below throws CalibrationError (cubecal/error.hpp): bad_data
// for inconsistent input (spans of different lengths, dt <= 0, gap positions
// not ascending, a bad schedule); bad_option for options out of range;
// no_plateaus when no plateau is left (the message says what was looked for;
// also a record shorter than one detection window, an empty schedule).

/// (a) Plateaus where ref[0..2] (data unit, one per sample) is constant.
PlateauDetection plateaus_from_reference(const TriadRecord& rec, const std::array<std::span<const double>, 3>& ref,
                                         const PlateauOptions& opt = {});

/// (b) Plateaus from the gyro signal alone; has_ref is false.
PlateauDetection plateaus_from_signal(const TriadRecord& rec, const PlateauOptions& opt = {});

/// (c) One plateau per schedule row (one per contiguous piece if the row
/// spans a gap) over [t_begin + margin, t_end - margin].
PlateauDetection plateaus_from_schedule(const TriadRecord& rec, std::span<const ScheduleRow> rows,
                                        const PlateauOptions& opt = {});

/// Gives each plateau of `found` the rate of the schedule row that overlaps
/// it most, if that row covers at least half of it; other plateaus are
/// dropped and counted in `unmatched`. For (b) when the log clock and the
/// schedule agree only roughly.
PlateauDetection label_with_schedule(PlateauDetection found, std::span<const ScheduleRow> rows);

}  // namespace cubecal
