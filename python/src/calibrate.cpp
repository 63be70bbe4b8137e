// cubecal._calibrate_* and cubecal._turnon / _compare: the calibration
// commands (`calibrate rate-table`, `mag`, `temperature`, `multiposition`)
// and the runs commands (`turnon`, `compare`) on a file read as the CLI
// reads it, or on arrays. Each checks its arguments as the CLI checks its
// options (UsageError naming the Python keyword), runs the pipeline without
// the GIL and returns the pipeline's to_json as Python objects
// (json_value.hpp), the same document the CLI writes (the calibrations that the CLI writes with its
// invocation get the Python call's text as "invocation").
//
// Data that cannot determine a calibration raise the core's
// CalibrationError with its reason, as they are (the CLI turns them into an
// InputError with a hint in its flags); a plain std::invalid_argument from a
// calibration becomes an InputError on the record, as in the CLI.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "array_series.hpp"
#include "arrays.hpp"
#include "common.hpp"
#include "errors.hpp"
#include "json_value.hpp"
#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/calib/multiposition.hpp"
#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/static_detection.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/noise/unit_from_name.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/calibrate_mag.hpp"
#include "cubecal/pipeline/calibrate_mag_json.hpp"
#include "cubecal/pipeline/calibrate_multiposition.hpp"
#include "cubecal/pipeline/calibrate_multiposition_json.hpp"
#include "cubecal/pipeline/calibrate_rate_table.hpp"
#include "cubecal/pipeline/calibrate_rate_table_json.hpp"
#include "cubecal/pipeline/calibrate_temperature.hpp"
#include "cubecal/pipeline/calibrate_temperature_json.hpp"
#include "cubecal/pipeline/turnon.hpp"
#include "cubecal/pipeline/turnon_json.hpp"
#include "cubecal/stats/sampling.hpp"
#include "module.hpp"
#include "units.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

namespace mp = cubecal::multipos;

// ---------------------------------------------------------------------------
// Shared pieces.

bool finite_positive(double x) { return x > 0.0 && std::isfinite(x); }

// Runs a calibration on the record `label`: the core's CalibrationError (and
// UsageError, InputError) as they are; a plain std::invalid_argument, a call
// the data made impossible, as an InputError on the record (the CLI's rule).
template <class F>
decltype(auto) on_record(const std::string& label, F&& f) {
  try {
    return f();
  } catch (const CalibrationError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw InputError(label, 0, 0, e.what());
  }
}

// The values of a 1-D array, checked as a reader checks a column (finite,
// magnitudes a variance can hold: io/sample_checks.hpp): an InputError at
// line = sample + 1, column = `column` of the record `label`.
std::vector<double> finite_values(const Doubles& a, const std::string& what, const std::string& label,
                                  std::size_t column) {
  const std::span<const double> v = view(a, what);
  io::check_samples(v, label, column, what);
  return {v.begin(), v.end()};
}

// Time stamps given as an array: finite, strictly increasing, one per
// sample, without gaps; with !allow_jitter (as a reader checks a time column
// read with gaps = error) without intervals off the period by more than 1 %
// either. `line` of an InputError is the 1-based sample.
std::vector<double> checked_times(const Doubles& a, std::size_t samples, const std::string& what,
                                  const std::string& label, bool allow_jitter) {
  std::vector<double> t = finite_values(a, what, label, 0);
  if (t.size() != samples)
    throw ArgumentError(what, "the time stamps must be one per sample (" + std::to_string(t.size()) + " for " +
                                  std::to_string(samples) + " samples)");
  for (std::size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1]))
      throw InputError(label, i + 1, 0,
                       fmt::format("time stamp {:.10g} s is not after the previous one {:.10g} s", t[i], t[i - 1]),
                       "the time stamps must increase");
  if (t.size() < 2) return t;
  const SamplingCheck sc = check_sampling(t);
  if (sc.gaps > 0) {
    const std::size_t i = sc.first_gap;
    throw InputError(label, i + 1, 0,
                     fmt::format("gap of {:.6g} s ({:.0f} periods of {:.6g} s) after t = {:.10g} s", t[i] - t[i - 1],
                                 (t[i] - t[i - 1]) / sc.period_s, sc.period_s, t[i - 1]),
                     "calibrate a stretch without gaps");
  }
  if (sc.jittered > 0 && !allow_jitter) {
    const std::size_t i = sc.first_jitter;
    throw InputError(
        label, i + 1, 0,
        fmt::format("jitter: interval {:.6g} s differs from the period {:.6g} s by {:.3g} %", t[i] - t[i - 1],
                    sc.period_s, 100.0 * std::fabs(t[i] - t[i - 1] - sc.period_s) / sc.period_s),
        "the time stamps must be uniform within 1 % of their period");
  }
  return t;
}

nlohmann::json with_invocation(nlohmann::json j, const std::string& command) {
  j["invocation"] = command;
  return j;
}

// ---------------------------------------------------------------------------
// calibrate rate-table

struct RateTableArgs {
  std::vector<std::string> reference;  // a file's 3 reference rate columns
  std::string schedule_file;           // rows t_begin,t_end,wx,wy,wz
  std::optional<Doubles> schedule;     // the same rows as an (rows, 5) array
  bool from_signal = false;
  double margin = 10.0;
  double min_plateau = 30.0;
  double ref_tolerance = 1e-6;
  double window = 10.0;
  std::vector<double> earth_axis;  // empty, or the Earth's axis X,Y,Z in the sensor frame
  std::string unit = "deg/s";
};

std::vector<ScheduleRow> schedule_rows(const Doubles& a) {
  if (a.ndim() != 2 || a.shape(1) != 5)
    throw UsageError(Field::schedule, "the schedule is an array of rows t_begin, t_end, wx, wy, wz (shape (rows, 5))");
  const auto n = static_cast<std::size_t>(a.shape(0));
  const double* p = a.data();
  std::vector<ScheduleRow> rows(n);
  for (std::size_t i = 0; i < n; ++i) rows[i] = {p[5 * i], p[5 * i + 1], {p[5 * i + 2], p[5 * i + 3], p[5 * i + 4]}};
  if (rows.empty()) throw UsageError(Field::schedule, "the schedule has no rows");
  if (const auto problem = check_schedule(rows)) throw UsageError(Field::schedule, problem->what);
  return rows;
}

// The request, checked as `calibrate rate-table` checks its options;
// `use_ref`: the reference rates are given (columns of a file, or arrays).
pipeline::RateTableRequest rate_table_request(const RateTableArgs& a, bool use_ref) {
  const bool use_schedule = !a.schedule_file.empty() || a.schedule.has_value();
  if (use_ref == use_schedule)
    throw ArgumentError(use_ref ? "schedule" : "reference",
                        use_ref ? "give either reference or schedule, not both"
                                : "the true rates are needed: give reference (the 3 reference rate columns of the "
                                  "record) or schedule (rows t_begin, t_end, wx, wy, wz)");
  if (a.from_signal && !use_schedule)
    throw UsageError(Field::from_signal, "from_signal labels the plateaus from a schedule: give schedule");
  const auto seconds = [](double x, bool positive, const char* option) {
    if (!(positive ? x > 0.0 : x >= 0.0) || !std::isfinite(x))
      throw ArgumentError(option, std::string(option) +
                                      ": margin, min_plateau and ref_tolerance must be >= 0 and "
                                      "window > 0 seconds");
  };
  seconds(a.margin, false, "margin");
  seconds(a.min_plateau, false, "min_plateau");
  seconds(a.ref_tolerance, false, "ref_tolerance");
  seconds(a.window, true, "window");
  if (a.unit != "deg/s" && a.unit != "rad/s") throw UsageError(Field::unit, "unit must be \"deg/s\" or \"rad/s\"");
  pipeline::RateTableRequest req;
  req.source = use_ref         ? pipeline::PlateauSource::reference
               : a.from_signal ? pipeline::PlateauSource::signal_schedule
                               : pipeline::PlateauSource::schedule;
  req.unit = a.unit;
  if (!a.earth_axis.empty()) {
    if (a.earth_axis.size() != 3 || !std::isfinite(a.earth_axis[0]) || !std::isfinite(a.earth_axis[1]) ||
        !std::isfinite(a.earth_axis[2]))
      throw UsageError(Field::earth_axis,
                       "earth_axis takes three numbers X, Y, Z (the Earth's axis in the sensor frame)");
    req.earth_axis = std::array<double, 3>{a.earth_axis[0], a.earth_axis[1], a.earth_axis[2]};
  }
  req.plateaus.margin_s = a.margin;
  req.plateaus.min_plateau_s = a.min_plateau;
  req.plateaus.ref_tolerance = a.ref_tolerance;
  req.plateaus.window_s = a.window;
  if (a.schedule) req.schedule = schedule_rows(*a.schedule);
  return req;
}

nlohmann::json rate_table_file(const std::string& path, const ReadArgs& read, const RateTableArgs& a,
                               const std::string& command) {
  if (!a.reference.empty() && a.reference.size() != 3)
    throw ArgumentError("reference", "reference takes the 3 reference rate columns (rx,ry,rz or 5,6,7)");
  if (!read.extra.empty()) throw ArgumentError("extra", "the extra columns of a rate table are its reference columns");
  pipeline::RateTableRequest req = rate_table_request(a, !a.reference.empty());
  io::SeriesOptions so = series_options(read);
  so.table.extra_columns = a.reference;  // the reference is in physical units: not scaled by lsb
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    if (!a.schedule_file.empty()) req.schedule = pipeline::read_schedule(a.schedule_file);
    const io::Series s = io::read_series(path, so);
    j = pipeline::to_json(on_record(path, [&] { return pipeline::calibrate_rate_table(s, req); }));
  }
  return with_invocation(std::move(j), command);
}

nlohmann::json rate_table_arrays(const std::vector<Doubles>& channels, const std::vector<std::string>& names,
                                 double rate, const std::optional<Doubles>& time, const std::vector<Doubles>& reference,
                                 const std::vector<std::string>& reference_names, const RateTableArgs& a,
                                 const std::string& label, const std::string& command) {
  if (!reference.empty() && reference.size() != 3)
    throw ArgumentError("reference", "reference: the 3 reference rates x, y, z, one value per sample each");
  if (reference_names.size() != reference.size()) throw std::invalid_argument("reference_names: one per reference");
  if (channels.size() != 3)
    throw ArgumentError(
        "data", "a rate table needs exactly the 3 gyro channels, " + std::to_string(channels.size()) + " given");
  pipeline::RateTableRequest req = rate_table_request(a, !reference.empty());
  std::vector<double> t;
  if (time) {
    t = checked_times(*time, view(channels[0], "data").size(), "time", label, false);
    if (rate == 0.0 && t.size() >= 2) rate = 1.0 / median_interval(t);
  }
  io::Series s = array_series(channels, names, rate, std::nullopt, "", label);
  if (time) {
    if (std::fabs(s.rate_hz * median_interval(t) - 1.0) > 0.01)
      throw UsageError(Field::rate,
                       fmt::format("the rate {:.6g} Hz contradicts the time stamps (median interval {:.6g} s): "
                                   "leave the rate out to take it from the time stamps",
                                   s.rate_hz, median_interval(t)));
    s.time = std::move(t);
    s.time_name = "time";
  }
  for (std::size_t k = 0; k < reference.size(); ++k) {
    s.extra_names.push_back(reference_names[k]);
    s.extra.push_back(finite_values(reference[k], reference_names[k], label, channels.size() + k + 1));
    if (s.extra.back().size() != s.samples())
      throw ArgumentError("reference", "the reference rates must have one value per sample (" +
                                           std::to_string(s.extra.back().size()) + " for " +
                                           std::to_string(s.samples()) + " samples)");
  }
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    if (!a.schedule_file.empty()) req.schedule = pipeline::read_schedule(a.schedule_file);
    j = pipeline::to_json(on_record(label, [&] { return pipeline::calibrate_rate_table(s, req); }));
  }
  return with_invocation(std::move(j), command);
}

// ---------------------------------------------------------------------------
// calibrate mag

struct MagArgs {
  std::string method = "ellipsoid";
  double lsb = 1.0;
  std::optional<double> field_norm;
  std::optional<double> noise;
  double reject = 0.0;
  bool allow_partial = false;
  std::string unit;
};

// The request, validated as the CLI's; `field_column`: a field norm per
// point is given.
pipeline::MagRequest mag_request(const MagArgs& a, bool field_column) {
  const auto method = mag::parse_method(a.method);
  if (!method) throw UsageError(Field::method, "method must be \"twostep\", \"twostep-full\" or \"ellipsoid\"");
  pipeline::MagRequest req;
  req.method = *method;
  req.counts_per_unit = a.lsb;
  req.field_norm = a.field_norm;
  req.field_column = field_column;
  req.noise = a.noise;
  req.reject_sigma = a.reject;
  req.allow_partial = a.allow_partial;
  req.unit = a.unit;
  req.validate();
  return req;
}

nlohmann::json mag_file(const std::string& path, const std::vector<std::string>& columns, std::size_t skip_rows,
                        unsigned threads, const std::string& field_column, const MagArgs& a,
                        const std::string& command) {
  pipeline::check_mag_columns(columns);
  const pipeline::MagRequest req = mag_request(a, !field_column.empty());
  io::TableOptions to;
  to.columns = columns;
  to.skip_rows = skip_rows;
  to.threads = threads;
  if (!field_column.empty()) to.extra_columns.push_back(field_column);
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    const io::Table t = io::read_table(path, to);
    if (t.data.size() != 3)
      throw UsageError(Field::columns, path + " has " + std::to_string(t.data.size()) +
                                           " data columns: name the 3 magnetometer columns with columns=\"mx,my,mz\"");
    j = pipeline::to_json(on_record(path, [&] { return pipeline::calibrate_mag(t, req); }));
  }
  return with_invocation(std::move(j), command);
}

// Points as 3 arrays; their rows count from 1 (rejected_lines are the
// 1-based numbers of the points rejected).
nlohmann::json mag_arrays(const std::vector<Doubles>& xyz, const std::vector<std::string>& names,
                          const std::optional<Doubles>& field_norms, const MagArgs& a, const std::string& label,
                          const std::string& command) {
  if (xyz.size() != 3 || names.size() != 3)
    throw ArgumentError("points", "the points are 3 arrays x, y, z (or an array of shape (n, 3))");
  const pipeline::MagRequest req = mag_request(a, field_norms.has_value());
  io::Table t;
  t.file = label;
  t.names = names;
  t.first_data_line = 1;
  for (std::size_t c = 0; c < 3; ++c) {
    t.data.push_back(finite_values(xyz[c], names[c], label, c + 1));
    t.indices.push_back(c);
    if (t.data.back().size() != t.data.front().size())
      throw ArgumentError("points", "x, y and z must have the same length (" + std::to_string(t.data.back().size()) +
                                        " and " + std::to_string(t.data.front().size()) + ")");
  }
  t.total_columns = 3;
  if (field_norms) {
    t.extra_names.push_back("field_norm");
    t.extra.push_back(finite_values(*field_norms, "field_column", label, 4));
    t.extra_indices.push_back(3);
    t.total_columns = 4;
    if (t.extra[0].size() != t.rows())
      throw UsageError(Field::field_column, "the field norms must be one per point (" +
                                                std::to_string(t.extra[0].size()) + " for " + std::to_string(t.rows()) +
                                                " points)");
  }
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    j = pipeline::to_json(on_record(label, [&] { return pipeline::calibrate_mag(t, req); }));
  }
  return with_invocation(std::move(j), command);
}

// ---------------------------------------------------------------------------
// calibrate temperature

struct TemperatureArgs {
  std::size_t order = 1;
  std::string unit = "counts";
};

pipeline::TemperatureRequest temperature_request(const TemperatureArgs& a) {
  pipeline::TemperatureRequest req;
  req.order = a.order;
  req.unit = a.unit;
  req.temp_index = 0;
  req.validate();
  return req;
}

nlohmann::json temperature_file(const std::string& path, const ReadArgs& read, const std::string& temperature,
                                const TemperatureArgs& a) {
  if (temperature.empty()) throw ArgumentError("temperature", "name the temperature column (degC) of the file");
  if (!read.extra.empty())
    throw ArgumentError("extra", "the extra column of a temperature calibration is its temperature");
  const pipeline::TemperatureRequest req = temperature_request(a);
  io::SeriesOptions so = series_options(read);
  so.table.extra_columns = {temperature};
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    const io::Series s = io::read_series(path, so);
    j = pipeline::to_json(on_record(path, [&] { return pipeline::calibrate_temperature(s, req); }));
  }
  return j;
}

nlohmann::json temperature_arrays(const std::vector<Doubles>& channels, const std::vector<std::string>& names,
                                  double rate, const Doubles& temperature, const std::string& temp_name,
                                  const TemperatureArgs& a, const std::string& label) {
  const pipeline::TemperatureRequest req = temperature_request(a);
  const io::Series s = array_series(channels, names, rate, temperature, temp_name, label);
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    j = pipeline::to_json(on_record(label, [&] { return pipeline::calibrate_temperature(s, req); }));
  }
  return j;
}

// ---------------------------------------------------------------------------
// calibrate multiposition

struct MultipositionArgs {
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
};

pipeline::MultipositionRequest multiposition_request(const MultipositionArgs& a, double rate) {
  if (!finite_positive(a.g)) throw UsageError(Field::g, "g: the local gravity magnitude must be positive");
  if (!finite_positive(a.init_static))
    throw UsageError(Field::init_static, "init_static: the initial static period must be a positive number of seconds");
  if (a.window < mp::kMinWindow)
    throw UsageError(Field::window,
                     "window: the variance window must be at least " + std::to_string(mp::kMinWindow) + " samples");
  if (a.interval_samples < 1 || a.interval_samples > 1000000)
    throw UsageError(Field::interval_samples, "interval_samples must be 1 to 1000000");
  if (a.min_intervals < 4 || a.min_intervals > 100000)
    throw UsageError(Field::min_intervals, "min_intervals must be 4 to 100000");
  if (a.acc_bias.size() != 1 && a.acc_bias.size() != 3)
    throw UsageError(Field::acc_bias, "acc_bias takes one value or three (x, y, z)");
  for (const double b : a.acc_bias)
    if (!std::isfinite(b)) throw UsageError(Field::acc_bias, "acc_bias must be finite");
  if (!(a.acc_scale >= 0.0) || !std::isfinite(a.acc_scale))
    throw UsageError(Field::acc_scale, "acc_scale must be 0 (automatic) or a positive scale guess");
  if (!finite_positive(a.gyro_scale))
    throw UsageError(Field::gyro_scale, "gyro_scale must be positive (rad/s per count)");
  pipeline::MultipositionRequest req;
  mp::Options& opt = req.options;
  opt.g = a.g;
  opt.init_static_s = a.init_static;
  opt.window = a.window;
  opt.interval_samples = a.interval_samples;
  opt.min_intervals = a.min_intervals;
  opt.acc_use_means = a.use_means;
  opt.acc_bias_guess = a.acc_bias.size() == 3 ? Vec3{a.acc_bias[0], a.acc_bias[1], a.acc_bias[2]}
                                              : Vec3{a.acc_bias[0], a.acc_bias[0], a.acc_bias[0]};
  opt.acc_scale_guess = a.acc_scale;
  opt.gyro_scale_guess = a.gyro_scale;
  opt.refine_gyro_bias = a.refine_gyro_bias;
  req.rate_hz = rate;
  return req;
}

void check_sampling_choice(bool stamped, double rate) {
  if (rate < 0.0 || !std::isfinite(rate)) throw UsageError(Field::rate, "rate must be a positive number of Hz");
  if (rate > 0.0) io::check_rate(rate);
  if (stamped && rate > 0.0) throw UsageError(Field::rate, "give the time stamps or the rate, not both");
  if (!stamped && !(rate > 0.0))
    throw UsageError(Field::rate, "give the time stamps (time=) or the sampling rate (rate=)");
}

// The given columns (3 or 6) of one file as triads, with the time column
// when asked, its stamps increasing and without gaps (as the CLI reads them).
std::vector<pipeline::TriadSamples> read_triads(const std::string& path, const std::vector<std::string>& columns,
                                                const std::string& time_col, std::size_t skip_rows, unsigned threads,
                                                const char* what_columns) {
  io::TableOptions to;
  to.columns = columns;
  if (!time_col.empty()) to.extra_columns = {time_col};
  to.skip_rows = skip_rows;
  to.threads = threads;
  const io::Table tab = io::read_table(path, to);
  const std::size_t want = columns.empty() ? 3 : columns.size();
  if (tab.data.size() != want || want % 3 != 0)
    throw ArgumentError(what_columns, fmt::format("{}: {} data columns{}: choose three with {}", path, tab.data.size(),
                                                  time_col.empty() ? "" : " besides the time column", what_columns));
  if (!time_col.empty()) {
    const auto& t = tab.extra[0];
    const auto at = [&](std::size_t i) { return io::locate(tab, i, tab.extra_indices[0]); };
    for (std::size_t i = 1; i < t.size(); ++i)
      if (!(t[i] > t[i - 1]) || !std::isfinite(t[i] - t[i - 1]))
        throw InputError(path, at(i).line, at(i).column,
                         fmt::format("time stamps not increasing ({} s after {} s)", t[i], t[i - 1]), "check time=");
    // The gyroscope is integrated over the stamped intervals between poses: a
    // missing sample loses rotation, so a gap is refused; jitter is used as
    // stamped.
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
  }
  std::vector<pipeline::TriadSamples> out(want / 3);
  for (std::size_t k = 0; k < out.size(); ++k) {
    pipeline::TriadSamples& tr = out[k];
    tr.file = path;
    if (!time_col.empty()) tr.t = tab.extra[0];
    tr.x.resize(tab.rows());
    for (std::size_t i = 0; i < tab.rows(); ++i)
      tr.x[i] = {tab.data[3 * k][i], tab.data[3 * k + 1][i], tab.data[3 * k + 2][i]};
  }
  return out;
}

nlohmann::json run_multiposition(const pipeline::TriadSamples& acc, const std::optional<pipeline::TriadSamples>& gyro,
                                 const pipeline::MultipositionRequest& req, const std::string& command) {
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    pipeline::MultipositionResult r =
        on_record(acc.file, [&] { return pipeline::calibrate_multiposition_accelerometer(acc, req); });
    if (gyro) on_record(gyro->file, [&] { pipeline::add_multiposition_gyroscope(r, acc, *gyro, req); });
    j = pipeline::to_json(r);
  }
  return with_invocation(std::move(j), command);
}

nlohmann::json multiposition_file(const std::string& acc_path, const std::string& gyro_path,
                                  const std::vector<std::string>& acc_columns,
                                  const std::vector<std::string>& gyro_columns, const std::string& time_col,
                                  double rate, std::size_t skip_rows, unsigned threads, const MultipositionArgs& a,
                                  const std::string& command) {
  check_sampling_choice(!time_col.empty(), rate);
  if (!acc_columns.empty() && acc_columns.size() != 3)
    throw UsageError(Field::acc_columns, "acc_columns takes three columns");
  if (!gyro_columns.empty() && gyro_columns.size() != 3)
    throw UsageError(Field::gyro_columns, "gyro_columns takes three columns");
  const pipeline::MultipositionRequest req = multiposition_request(a, rate);
  pipeline::TriadSamples acc;
  std::optional<pipeline::TriadSamples> gyro;
  {
    py::gil_scoped_release free;
    if (gyro_path.empty() && !gyro_columns.empty()) {
      // One file with both triads.
      if (acc_columns.empty())
        throw UsageError(Field::acc_columns, "give acc_columns with gyro_columns for a single file");
      std::vector<std::string> cols = acc_columns;
      cols.insert(cols.end(), gyro_columns.begin(), gyro_columns.end());
      auto both = read_triads(acc_path, cols, time_col, skip_rows, threads, "acc_columns and gyro_columns");
      acc = std::move(both[0]);
      gyro = std::move(both[1]);
    } else {
      acc = std::move(read_triads(acc_path, acc_columns, time_col, skip_rows, threads, "acc_columns")[0]);
      if (!gyro_path.empty())
        gyro = std::move(read_triads(gyro_path, gyro_columns.empty() ? acc_columns : gyro_columns, time_col, skip_rows,
                                     threads, "gyro_columns")[0]);
    }
  }
  return run_multiposition(acc, gyro, req, command);
}

pipeline::TriadSamples triad_of(const std::vector<Doubles>& xyz, const std::optional<Doubles>& time,
                                const std::string& what, const std::string& label) {
  if (xyz.size() != 3)
    throw ArgumentError(what, what + ": the 3 axes x, y, z (an array of shape (n, 3), 3 arrays or 3 named columns)");
  std::array<std::vector<double>, 3> axes;
  for (std::size_t c = 0; c < 3; ++c) {
    axes[c] = finite_values(xyz[c], what + " axis " + std::string(1, "xyz"[c]), label, c + 1);
    if (axes[c].size() != axes[0].size()) throw ArgumentError(what, what + ": the 3 axes must have the same length");
  }
  pipeline::TriadSamples tr;
  tr.file = label;
  tr.x.resize(axes[0].size());
  for (std::size_t i = 0; i < tr.x.size(); ++i) tr.x[i] = {axes[0][i], axes[1][i], axes[2][i]};
  // The stamps are used as they are (the CLI's rule): jitter is allowed, a
  // gap (a lost piece of rotation) is not.
  if (time) tr.t = checked_times(*time, tr.x.size(), what == "acc" ? "time" : "gyro_time", label, true);
  return tr;
}

nlohmann::json multiposition_arrays(const std::vector<Doubles>& acc, const std::optional<std::vector<Doubles>>& gyro,
                                    const std::optional<Doubles>& time, const std::optional<Doubles>& gyro_time,
                                    double rate, const MultipositionArgs& a, const std::string& acc_label,
                                    const std::string& gyro_label, const std::string& command) {
  check_sampling_choice(time.has_value(), rate);
  if (gyro_time && !time) throw ArgumentError("gyro_time", "gyro_time needs the accelerometer's time stamps (time=)");
  const pipeline::MultipositionRequest req = multiposition_request(a, rate);
  const pipeline::TriadSamples acc_samples = triad_of(acc, time, "acc", acc_label);
  std::optional<pipeline::TriadSamples> gyro_samples;
  if (gyro) gyro_samples = triad_of(*gyro, gyro_time ? gyro_time : time, "gyro", gyro_label);
  return run_multiposition(acc_samples, gyro_samples, req, command);
}

// ---------------------------------------------------------------------------
// turnon, compare

// One run: a file with its reader options, or arrays at a rate; its own
// units (compare) or none (the call's).
struct RunInput {
  std::string path;
  ReadArgs read;
  std::vector<Doubles> channels;
  std::vector<std::string> names;
  double rate = 0.0;
  std::string label;
  std::vector<std::string> units;
};

struct RunsArgs {
  std::vector<std::string> units;  // one for all channels or one per channel; empty: from the names
  py::object taus = py::str("log:10");
  double ci = 0.683;
  unsigned threads = 0;
};

std::vector<Unit> units_of(const std::vector<std::string>& names, const std::string& option) {
  std::vector<Unit> units;
  for (const auto& name : names) {
    const auto u = parse_unit(name);
    if (!u) throw ArgumentError(option, "unknown unit '" + name + "' (use " + known_units() + ")");
    units.push_back(*u);
  }
  return units;
}

// The request of each run with its units: its own, else the call's, else
// those the names of the first such run announce, which every other such
// run's names must announce too (the CLI's rule).
std::vector<pipeline::AnalyzeRequest> run_requests(const pipeline::AnalyzeRequest& base, const RunsArgs& a,
                                                   const std::vector<RunInput>& inputs,
                                                   const std::vector<io::Series>& runs) {
  std::vector<pipeline::AnalyzeRequest> reqs(runs.size(), base);
  const io::Series* reference = nullptr;
  std::vector<Unit> inferred;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (!inputs[k].units.empty()) {
      reqs[k].units = units_of(inputs[k].units, "unit");
      continue;
    }
    if (!a.units.empty()) {
      reqs[k].units = units_of(a.units, "unit");
      continue;
    }
    if (!reference) {
      inferred = announced_units(runs[k]);
      reference = &runs[k];
    } else {
      std::vector<Unit> other;
      try {
        other = announced_units(runs[k]);
      } catch (const UsageError&) {
      }
      bool same = other.size() == inferred.size();
      for (std::size_t c = 0; same && c < inferred.size(); ++c) same = other[c].name == inferred[c].name;
      if (!same)
        throw UsageError(Field::unit, runs[k].file + ": its channel names do not announce the units of " +
                                          reference->file + "'s: give unit=");
    }
    reqs[k].units = inferred;
  }
  return reqs;
}

pipeline::AnalyzeRequest runs_request(const RunsArgs& a) {
  pipeline::AnalyzeRequest req;
  req.grid = taus_arg(a.taus);
  if (!(a.ci > 0.0 && a.ci < 1.0)) throw UsageError(Field::ci, "ci must be between 0 and 1");
  req.ci = a.ci;
  req.threads = a.threads;
  units_of(a.units, "unit");  // a typo fails before any file is read
  return req;
}

// The records of the runs, arrays first (with the GIL), then the files
// (without it); `read_files` is called where the GIL is released.
std::vector<std::optional<io::Series>> array_runs(const std::vector<RunInput>& inputs) {
  std::vector<std::optional<io::Series>> out(inputs.size());
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const RunInput& in = inputs[k];
    units_of(in.units, "unit");
    if (in.path.empty()) out[k] = array_series(in.channels, in.names, in.rate, std::nullopt, "", in.label);
  }
  return out;
}

std::vector<io::Series> all_runs(const std::vector<RunInput>& inputs, std::vector<std::optional<io::Series>>&& arrays) {
  std::vector<io::SeriesOptions> options(inputs.size());
  for (std::size_t k = 0; k < inputs.size(); ++k)
    if (!inputs[k].path.empty()) options[k] = series_options(inputs[k].read);
  std::vector<io::Series> runs;
  for (std::size_t k = 0; k < inputs.size(); ++k)
    runs.push_back(arrays[k] ? std::move(*arrays[k]) : io::read_series(inputs[k].path, options[k]));
  return runs;
}

nlohmann::json turnon(const std::vector<RunInput>& inputs, const RunsArgs& a) {
  const pipeline::AnalyzeRequest base = runs_request(a);
  for (const auto& in : inputs)
    if (!in.units.empty())
      throw UsageError(Field::unit,
                       (in.path.empty() ? in.label : in.path) +
                           ": turnon averages the runs' biases, so every run is in the same unit: give unit= "
                           "to turnon (or scale a run with lsb=), not a unit per run");
  auto arrays = array_runs(inputs);
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    const std::vector<io::Series> runs = all_runs(inputs, std::move(arrays));
    const auto reqs = run_requests(base, a, inputs, runs);
    j = pipeline::to_json(pipeline::run_turnon(runs, reqs.empty() ? base : reqs.front()));
  }
  return j;
}

nlohmann::json compare(const std::vector<RunInput>& inputs, const RunsArgs& a) {
  const pipeline::AnalyzeRequest base = runs_request(a);
  if (inputs.empty()) throw ArgumentError("runs", "no run to compare");
  auto arrays = array_runs(inputs);
  nlohmann::json j;
  {
    py::gil_scoped_release free;
    const std::vector<io::Series> runs = all_runs(inputs, std::move(arrays));
    j = pipeline::to_json(pipeline::run_compare(runs, run_requests(base, a, inputs, runs)));
  }
  return j;
}

}  // namespace

void bind_calibrate(py::module_& m) {
  py::class_<RateTableArgs>(m, "_RateTableArgs")
      .def(py::init<>())
      .def_readwrite("reference", &RateTableArgs::reference)
      .def_readwrite("schedule_file", &RateTableArgs::schedule_file)
      .def_readwrite("schedule", &RateTableArgs::schedule)
      .def_readwrite("from_signal", &RateTableArgs::from_signal)
      .def_readwrite("margin", &RateTableArgs::margin)
      .def_readwrite("min_plateau", &RateTableArgs::min_plateau)
      .def_readwrite("ref_tolerance", &RateTableArgs::ref_tolerance)
      .def_readwrite("window", &RateTableArgs::window)
      .def_readwrite("earth_axis", &RateTableArgs::earth_axis)
      .def_readwrite("unit", &RateTableArgs::unit);
  m.def("_rate_table_file", returning_python(&rate_table_file), py::arg("path"), py::arg("read"), py::arg("args"),
        py::arg("command"));
  m.def("_rate_table_arrays", returning_python(&rate_table_arrays), py::arg("channels"), py::arg("names"),
        py::arg("rate"), py::arg("time"), py::arg("reference"), py::arg("reference_names"), py::arg("args"),
        py::arg("label"), py::arg("command"));

  py::class_<MagArgs>(m, "_MagArgs")
      .def(py::init<>())
      .def_readwrite("method", &MagArgs::method)
      .def_readwrite("lsb", &MagArgs::lsb)
      .def_readwrite("field_norm", &MagArgs::field_norm)
      .def_readwrite("noise", &MagArgs::noise)
      .def_readwrite("reject", &MagArgs::reject)
      .def_readwrite("allow_partial", &MagArgs::allow_partial)
      .def_readwrite("unit", &MagArgs::unit);
  m.def("_mag_file", returning_python(&mag_file), py::arg("path"), py::arg("columns"), py::arg("skip_rows"),
        py::arg("threads"), py::arg("field_column"), py::arg("args"), py::arg("command"));
  m.def("_mag_arrays", returning_python(&mag_arrays), py::arg("xyz"), py::arg("names"), py::arg("field_norms"),
        py::arg("args"), py::arg("label"), py::arg("command"));

  py::class_<TemperatureArgs>(m, "_TemperatureArgs")
      .def(py::init<>())
      .def_readwrite("order", &TemperatureArgs::order)
      .def_readwrite("unit", &TemperatureArgs::unit);
  m.def("_temperature_file", returning_python(&temperature_file), py::arg("path"), py::arg("read"),
        py::arg("temperature"), py::arg("args"));
  m.def("_temperature_arrays", returning_python(&temperature_arrays), py::arg("channels"), py::arg("names"),
        py::arg("rate"), py::arg("temperature"), py::arg("temp_name"), py::arg("args"), py::arg("label"));

  py::class_<MultipositionArgs>(m, "_MultipositionArgs")
      .def(py::init<>())
      .def_readwrite("g", &MultipositionArgs::g)
      .def_readwrite("init_static", &MultipositionArgs::init_static)
      .def_readwrite("window", &MultipositionArgs::window)
      .def_readwrite("interval_samples", &MultipositionArgs::interval_samples)
      .def_readwrite("min_intervals", &MultipositionArgs::min_intervals)
      .def_readwrite("acc_bias", &MultipositionArgs::acc_bias)
      .def_readwrite("acc_scale", &MultipositionArgs::acc_scale)
      .def_readwrite("gyro_scale", &MultipositionArgs::gyro_scale)
      .def_readwrite("refine_gyro_bias", &MultipositionArgs::refine_gyro_bias)
      .def_readwrite("use_means", &MultipositionArgs::use_means);
  m.def("_multiposition_file", returning_python(&multiposition_file), py::arg("acc_path"), py::arg("gyro_path"),
        py::arg("acc_columns"), py::arg("gyro_columns"), py::arg("time"), py::arg("rate"), py::arg("skip_rows"),
        py::arg("threads"), py::arg("args"), py::arg("command"));
  m.def("_multiposition_arrays", returning_python(&multiposition_arrays), py::arg("acc"), py::arg("gyro"),
        py::arg("time"), py::arg("gyro_time"), py::arg("rate"), py::arg("args"), py::arg("acc_label"),
        py::arg("gyro_label"), py::arg("command"));

  py::class_<RunInput>(m, "_RunInput")
      .def(py::init<>())
      .def_readwrite("path", &RunInput::path)
      .def_readwrite("read", &RunInput::read)
      .def_readwrite("channels", &RunInput::channels)
      .def_readwrite("names", &RunInput::names)
      .def_readwrite("rate", &RunInput::rate)
      .def_readwrite("label", &RunInput::label)
      .def_readwrite("units", &RunInput::units);
  py::class_<RunsArgs>(m, "_RunsArgs")
      .def(py::init<>())
      .def_readwrite("units", &RunsArgs::units)
      .def_readwrite("taus", &RunsArgs::taus)
      .def_readwrite("ci", &RunsArgs::ci)
      .def_readwrite("threads", &RunsArgs::threads);
  m.def("_turnon", returning_python(&turnon), py::arg("runs"), py::arg("args"));
  m.def("_compare", returning_python(&compare), py::arg("runs"), py::arg("args"));
}

}  // namespace cubecal::python
