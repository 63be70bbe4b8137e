#include "cubecal/pipeline/calibrate_rate_table.hpp"

#include <numbers>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"

namespace cubecal::pipeline {

std::vector<ScheduleRow> read_schedule(const std::string& path) {
  const io::Table t = io::read_table(path);
  if (t.data.size() != 5)
    throw InputError(
        path, t.first_data_line, 0,
        "a schedule has 5 columns (t_begin,t_end,wx,wy,wz), this file has " + std::to_string(t.data.size()));
  std::vector<ScheduleRow> rows(t.rows());
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i] = {t.data[0][i], t.data[1][i], {t.data[2][i], t.data[3][i], t.data[4][i]}};
  if (const auto problem = check_schedule(rows)) {
    const io::Location at = io::locate(t, problem->row, t.indices[0]);
    throw InputError(path, at.line, at.column, problem->what, "one row per plateau, in seconds of the log's time base");
  }
  return rows;
}

std::string_view to_string(PlateauSource s) noexcept {
  switch (s) {
    case PlateauSource::reference: return "reference";
    case PlateauSource::schedule: return "schedule";
    case PlateauSource::signal_schedule: return "signal+schedule";
  }
  return "";
}

std::optional<PlateauSource> parse_plateau_source(std::string_view s) noexcept {
  for (PlateauSource p : {PlateauSource::reference, PlateauSource::schedule, PlateauSource::signal_schedule})
    if (to_string(p) == s) return p;
  return std::nullopt;
}

std::string_view describe(PlateauSource s) noexcept {
  switch (s) {
    case PlateauSource::reference: return "the reference columns";
    case PlateauSource::schedule: return "the schedule";
    case PlateauSource::signal_schedule: return "the gyro signal, rates from the schedule";
  }
  return "";
}

namespace {

void check_request(const io::Series& series, const RateTableRequest& req) {
  if (series.channels.size() != 3)
    throw UsageError(Field::columns, "a rate table needs exactly 3 gyro columns, " +
                                         std::to_string(series.channels.size()) + " selected");
  if (req.source == PlateauSource::reference && series.extra.size() != 3)
    throw UsageError(Field::reference_columns,
                     "the 3 reference rate columns are needed, " + std::to_string(series.extra.size()) + " given");
  if (req.source != PlateauSource::reference && req.schedule.empty())
    throw UsageError(Field::schedule, "the plateau schedule is empty");
  const PlateauOptions& p = req.plateaus;
  if (!(p.margin_s >= 0.0) || !(p.min_plateau_s >= 0.0) || !(p.ref_tolerance >= 0.0) || !(p.window_s > 0.0))
    throw UsageError(Field::plateaus,
                     "margin, shortest plateau and reference tolerance must be >= 0 and the window > 0 s");
  if (req.unit != "deg/s" && req.unit != "rad/s")
    throw UsageError(Field::unit, "must be deg/s or rad/s, not " + req.unit);
}

PlateauDetection detect(const io::Series& series, const RateTableRequest& req) {
  TriadRecord rec;
  for (int a = 0; a < 3; ++a) rec.axes[a] = series.channels[a];
  rec.time = series.time;
  rec.dt = series.tau0;
  std::vector<std::size_t> breaks;
  for (std::size_t s = 1; s < series.segments.size(); ++s) breaks.push_back(series.segments[s].begin);
  rec.breaks = breaks;
  switch (req.source) {
    case PlateauSource::reference:
      return plateaus_from_reference(rec, {series.extra[0], series.extra[1], series.extra[2]}, req.plateaus);
    case PlateauSource::signal_schedule:
      return label_with_schedule(plateaus_from_signal(rec, req.plateaus), req.schedule);
    case PlateauSource::schedule: break;
  }
  return plateaus_from_schedule(rec, req.schedule, req.plateaus);
}

}  // namespace

RateTableResult calibrate_rate_table(const io::Series& series, const RateTableRequest& req) {
  check_request(series, req);
  RateTableResult r;
  r.file = series.file;
  r.unit = req.unit;
  r.source = req.source;
  const double unit_per_rad_s = req.unit == "deg/s" ? 180.0 / std::numbers::pi : 1.0;
  if (req.earth_axis) r.earth_rate = earth_rate_along(*req.earth_axis, unit_per_rad_s);

  // The core throws CalibrationError with its reason (no_plateaus,
  // too_few_points, degenerate, ...) for data that cannot give the calibration.
  r.found = detect(series, req);
  RateTableOptions opt;
  opt.earth_rate = r.earth_rate;
  r.calibration = cubecal::calibrate_rate_table(r.found.plateaus, opt);
  return r;
}

}  // namespace cubecal::pipeline
