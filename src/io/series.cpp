// A uniformly sampled record: columns from a delimited file, scaled to
// units, with a sampling rate that is either given or inferred from a time
// column. Allan-type statistics assume equal spacing, so every time stamp is
// checked: a record with gaps or jitter is refused (or, on request, split
// into contiguous pieces) instead of being silently analyzed.
#include "cubecal/io/series.hpp"

#include <algorithm>
#include <limits>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string_view>
#include <utility>

#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"
#include "detail/file_buffer.hpp"
#include "detail/file_table.hpp"
#include "detail/hdf5_reader.hpp"
#include "detail/npy_reader.hpp"
#include "detail/stable32_dat.hpp"
#include "cubecal/io/mcap.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "cubecal/io/message_log.hpp"
#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/ros2_bag.hpp"
#include "cubecal/io/ulog.hpp"
#include "../detail/magnitude.hpp"
#include "cubecal/stats/sampling.hpp"
#include "detail/bag_series.hpp"
#include "detail/series_timing.hpp"
#include "detail/ulog_series.hpp"
#include "detail/shortest_text.hpp"

namespace cubecal::io {

using namespace std::string_literals;

namespace {

// Time stamps as the shortest text that reads back the same value, which is
// normally how they are written in the file.
const auto& stamp = detail::shortest_text;
using detail::lower_case;

using detail::period_text;

// Whether a column spec (name or 1-based index, as TableOptions resolves
// it) designates header column i.
bool designates(const std::string& spec, const std::vector<std::string>& header, std::size_t i) {
  if (spec == header[i]) return true;
  if (std::find(header.begin(), header.end(), spec) != header.end()) return false;
  if (spec == std::to_string(i + 1)) return true;
  return lower_case(spec) == lower_case(header[i]);
}

// The default channels of a file with a header: every column but the time
// column, the extra columns and (when asked) the temperature columns.
void default_columns(const Table& layout, const std::string& time_spec, const SeriesOptions& opt, TableOptions& topt,
                     Series& s) {
  if (!opt.table.columns.empty() || !layout.has_header) return;
  s.default_columns = true;
  for (std::size_t i = 0; i < layout.header.size(); ++i) {
    const std::string& name = layout.header[i];
    bool out = !time_spec.empty() && designates(time_spec, layout.header, i);
    for (const auto& e : opt.table.extra_columns) out = out || designates(e, layout.header, i);
    out = out || (opt.skip_temperature && looks_like_temperature_column(name));
    (out ? s.left_out : topt.columns).push_back(name);
  }
  const bool temperature = std::any_of(s.left_out.begin(), s.left_out.end(), [&](const std::string& n) {
    return opt.skip_temperature && looks_like_temperature_column(n);
  });
  if (topt.columns.empty() && temperature) {
    std::string left;
    for (const auto& n : s.left_out) left += (left.empty() ? "" : ", ") + n;
    throw InputError(s.file, 0, 0, "no data columns besides the time and temperature columns (" + left + ")",
                     "name the columns to analyze");
  }
  if (topt.columns.empty())
    throw InputError(s.file, 0, 0, "no data columns besides the time column", "name the columns to analyze");
}

void check_options(const SeriesOptions& opt) {
  for (const double lsb : opt.lsb)
    if (!(lsb > 0.0) || !std::isfinite(lsb))
      throw UsageError(Field::counts_per_unit,
                       "the LSB (counts per unit) must be a positive finite number, got " + stamp(lsb));
  if (!(opt.rate_hz >= 0.0) || !std::isfinite(opt.rate_hz)) {
    throw UsageError("the sampling rate must be a positive finite number of Hz, got " + stamp(opt.rate_hz));
  }
  if (opt.rate_hz != 0.0) check_rate(opt.rate_hz);
  if (!(opt.tolerance >= 0.0) || !std::isfinite(opt.tolerance)) {
    throw UsageError("the interval tolerance must be a non-negative fraction, got " + stamp(opt.tolerance));
  }
}

// One LSB for every column, or one per selected column (`names`, in order).
void check_lsb_count(const SeriesOptions& opt, const std::string& file, const std::vector<std::string>& names) {
  if (opt.lsb.size() <= 1 || opt.lsb.size() == names.size()) return;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ",") + n;
  throw UsageError(Field::counts_per_unit, file + ": " + std::to_string(opt.lsb.size()) + " LSB values for " +
                                               std::to_string(names.size()) +
                                               (names.size() == 1 ? " column (" : " columns (") + list +
                                               "): give one value for every column, or one per column");
}

[[noreturn]] void throw_too_short(const std::string& file, std::size_t n, std::size_t min, std::string hint) {
  throw InputError(file, 0, 0,
                   "series too short: " + std::to_string(n) + " samples, at least " + std::to_string(min) + " needed",
                   std::move(hint));
}

// Which column holds the time, and whether its stamps define the timing.
struct TimeChoice {
  std::string spec;     // column to read; empty for none
  bool timing = false;  // false: only kept out of the channels
};

TimeChoice choose_time_column(const SeriesOptions& opt, const Table& layout) {
  if (!opt.time_col.empty()) return {opt.time_col, true};
  const auto it = std::find_if(layout.header.begin(), layout.header.end(), looks_like_time_column);
  if (it == layout.header.end()) {
    if (opt.rate_hz == 0.0)
      throw UsageError(layout.file +
                       ": no sampling rate: no column is named as a time column (t, time, "
                       "t_s, timestamp...): give {rate} HZ or {time_col} NAME");
    return {};
  }
  // A given rate overrides time stamps that were found by name only (e.g.
  // PC clocks with jitter), but a time column is never a useful channel.
  return {*it, opt.rate_hz == 0.0};
}

// Values whose squares overflow make every variance inf or NaN, and a
// column whose largest value is so small that its squares underflow makes
// them 0/0: refused at their place, after the LSB scaling.
void check_magnitudes(const Series& s, const Table& t, const SeriesOptions& opt) {
  const auto fail = [&](const std::vector<double>& v, std::size_t i, std::size_t field, double scale,
                        const std::string& what) {
    const Location loc = locate(t, i, field);
    throw InputError(
        s.file, loc.line, loc.column,
        "value " + stamp(v[i]) + (scale != 1.0 ? " (" + stamp(v[i] / scale) + " after the LSB)" : "") + what,
        "rescale the column, e.g. to other units");
  };
  const auto check = [&](const std::vector<double>& v, std::size_t field, double scale) {
    // One vectorised pass for the largest magnitude (no division: this runs
    // over every value of the record); the place only on failure.
    const double raw_top = largest_magnitude(v).largest;
    const double top = raw_top / scale;
    const auto first_with = [&](double magnitude) {
      std::size_t j = 0;
      while (j + 1 < v.size() && std::fabs(v[j]) != magnitude) ++j;
      return j;
    };
    if (top > kMaxMagnitude) {
      std::size_t j = 0;
      while (j + 1 < v.size() && !(std::fabs(v[j] / scale) > kMaxMagnitude)) ++j;
      fail(v, j, field, scale, " exceeds the magnitude " + stamp(kMaxMagnitude) + " whose square a variance can hold");
    }
    if (top != 0.0 && top < kMinMagnitude)
      fail(v, first_with(raw_top), field, scale,
           " is the largest of its column, below the magnitude " + stamp(kMinMagnitude) +
               " whose square a variance can hold");
  };
  for (std::size_t c = 0; c < t.data.size(); ++c) check(t.data[c], t.indices[c], opt.lsb_of(c));
  for (std::size_t c = 0; c < t.extra.size(); ++c) check(t.extra[c], t.extra_indices[c], 1.0);
}

// A rate given beside a time column must be the rate of its stamps: a 2x
// error would otherwise halve or double every tau silently.
void check_rate_agrees(const std::string& file, const std::string& time_name, const std::vector<double>& time,
                       const SeriesOptions& opt) {
  if (!opt.check_rate_against_time || opt.rate_hz <= 0.0 || time.size() < 2) return;
  const double period = median_interval(time);
  if (!(period > 0.0) || !std::isfinite(period)) return;  // not increasing: check_timing says where
  const double from_time = 1.0 / period;
  if (std::fabs(opt.rate_hz * period - 1.0) <= opt.tolerance) return;
  throw UsageError(Field::rate, file + ": the rate " + period_text(opt.rate_hz) + " Hz contradicts the time column '" +
                                    time_name + "' (" + period_text(from_time) + " Hz, median interval " +
                                    period_text(period) +
                                    " s): leave the rate out to take it from the time stamps, "
                                    "or fix the time column");
}

// GapPolicy::skip: the rows of `fills` (row, count) get `count` missing
// samples (NaN, and the stamps of the periods between) before them, in every
// channel and extra column.
void fill_missing(Series& s, const std::vector<std::pair<std::size_t, std::size_t>>& fills) {
  std::size_t added = 0;
  for (const auto& f : fills) added += f.second;
  const auto widen = [&](std::vector<double>& v, bool stamps) {
    std::vector<double> out;
    out.reserve(v.size() + added);
    std::size_t from = 0;
    for (const auto& [row, count] : fills) {
      out.insert(out.end(), v.begin() + static_cast<std::ptrdiff_t>(from),
                 v.begin() + static_cast<std::ptrdiff_t>(row));
      for (std::size_t k = 1; k <= count; ++k)
        out.push_back(stamps ? v[row - 1] + static_cast<double>(k) * s.tau0 : std::numeric_limits<double>::quiet_NaN());
      from = row;
    }
    out.insert(out.end(), v.begin() + static_cast<std::ptrdiff_t>(from), v.end());
    v = std::move(out);
  };
  for (auto& c : s.channels) widen(c, false);
  for (auto& c : s.extra) widen(c, false);
  widen(s.time, true);
}

// Checks the time stamps against the period (given, or inferred from the
// median interval) and cuts the record into segments.
void check_timing(Series& s, const detail::PlaceError& at, const SeriesOptions& opt) {
  const std::vector<double>& time = s.time;
  const auto fail_at = [&](std::size_t row, std::string problem, std::string hint) {
    throw at(row, std::move(problem), std::move(hint));
  };

  for (std::size_t i = 1; i < time.size(); ++i) {
    if (time[i] > time[i - 1]) continue;
    fail_at(i, "time stamp " + stamp(time[i]) + " s is not after the previous one " + stamp(time[i - 1]) + " s",
            time[i] == time[i - 1] ? "duplicated time stamp: remove the repeated row or fix the logger clock"
                                   : "sort the file or fix the logger clock");
  }

  if (opt.rate_hz > 0.0) {
    s.rate_hz = opt.rate_hz;
    s.tau0 = 1.0 / opt.rate_hz;
  } else {
    if (time.size() < 2) {
      throw InputError(s.file, 0, 0, "cannot infer the sampling rate from a single time stamp", "give {rate} HZ");
    }
    // The median ignores gaps and outliers as long as most intervals are
    // regular, which the checks below then require anyway.
    // Time stamps printed with a few decimals make every interval differ from
    // the period in the last bits (5.3 - 5.2 = 0.0999999999999996): keep nine
    // significant digits of the rate, far below the 1 % interval tolerance.
    const double raw = 1.0 / median_interval(time);
    if (!(raw >= kMinRateHz && raw <= kMaxRateHz)) {
      fail_at(1,
              "time stamps " + stamp(1.0 / raw) + " s apart give a rate of " + stamp(raw) + " Hz, outside the range " +
                  stamp(kMinRateHz) + " to " + stamp(kMaxRateHz) + " Hz",
              "the time column must be in seconds");
    }
    const double scale = std::pow(10.0, 8.0 - std::floor(std::log10(raw)));
    s.rate_hz = std::round(raw * scale) / scale;
    s.tau0 = 1.0 / s.rate_hz;
    s.rate_from_time = true;
  }
  const double period = s.tau0;

  const std::string ignore_stamps = opt.time_col.empty() ? ", or give {rate} HZ to ignore the time stamps" : "";
  std::size_t begin = 0;
  std::vector<std::pair<std::size_t, std::size_t>> fills;  // skip: (row, missing samples before it)
  for (std::size_t i = 1; i < time.size(); ++i) {
    const double dt = time[i] - time[i - 1];
    if (std::fabs(dt - period) <= opt.tolerance * period) continue;
    if (opt.gaps == GapPolicy::skip) {
      // A gap of whole periods is that many missing samples; anything else
      // is jitter, which no sample can fill.
      const double periods = std::round(dt / period);
      if (periods >= 2.0 && std::fabs(dt - periods * period) <= opt.tolerance * period) {
        fills.emplace_back(i, static_cast<std::size_t>(periods) - 1);
        continue;
      }
      fail_at(i,
              "interval " + detail::duration_text(dt) + " s is not a whole number of periods of " +
                  period_text(period) + " s: no missing sample explains it",
              "use {gaps} split to cut the record at irregular intervals" + ignore_stamps);
    }
    if (opt.gaps == GapPolicy::split) {
      s.segments.push_back({begin, i});
      begin = i;
      ++s.irregular_intervals;
      continue;
    }
    // A missing sample makes an interval of at least two periods; anything
    // closer to one period is timing noise.
    if (dt >= kGapPeriods * period) {
      fail_at(i,
              "gap of " + detail::duration_text(dt) + " s (" + std::to_string(std::llround(dt / period)) +
                  " periods of " + period_text(period) + " s) after t = " + stamp(time[i - 1]) + " s",
              "use {gaps} split to analyze the contiguous pieces");
    } else {
      fail_at(i,
              "jitter: interval " + detail::duration_text(dt) + " s differs from the period " + period_text(period) +
                  " s by " +
                  detail::number_text(100.0 * std::fabs(dt - period) / period, std::chars_format::general, 3) + " %",
              "use {gaps} split to cut the record at irregular intervals" + ignore_stamps);
    }
  }
  if (!fills.empty()) fill_missing(s, fills);
  s.segments.push_back({begin, s.time.size()});
}

// A binary record as a table of all its columns (then selected like the
// columns of a text file); none for text.
// `open_path`: where an HDF5 file can be opened by the library ("" for
// standard input and inflated gzip, opened from the bytes).
std::optional<Table> binary_table(std::string_view bytes, const std::string& file, const std::string& open_path,
                                  const SeriesOptions& opt) {
  const bool missing_as_nan = opt.gaps == GapPolicy::skip;  // NaN: a missing sample, as in text
  if (!opt.binary.channels.empty()) return read_raw_binary(bytes, file, opt.binary, missing_as_nan);
  if (is_npy(bytes)) return read_npy(bytes, file, missing_as_nan);
  if (looks_like_hdf5(bytes)) return read_hdf5(bytes, file, open_path, opt.dataset, missing_as_nan);
  return std::nullopt;
}

// A Stable32 .DAT header: its lines skipped, the rate from its Tau (a
// --rate that disagrees is refused). None for other files.
std::optional<detail::Stable32Header> stable32_options(std::string_view text, const std::string& file,
                                                       SeriesOptions& opt) {
  std::optional<detail::Stable32Header> h = detail::stable32_header(text, file);
  if (!h) return h;
  opt.table.skip_rows += h->lines;
  if (h->tau) {
    const double rate = 1.0 / *h->tau;
    if (opt.rate_hz > 0.0 && std::fabs(opt.rate_hz * *h->tau - 1.0) > 1e-9)
      throw UsageError(Field::rate, file + ": the rate " + period_text(opt.rate_hz) +
                                        " Hz contradicts the Stable32 header's Tau " + stamp(*h->tau) +
                                        " s: leave out {rate}, or correct the header");
    opt.rate_hz = rate;
  }
  return h;
}

// The header's scaling (Stable32's Scale: value * Multiplier + Addend) and
// its point count, checked against the rows read.
void apply_stable32(Series& s, const detail::Stable32Header& h, std::size_t first_data_line) {
  if (h.points && *h.points != s.samples())
    throw InputError(s.file, first_data_line, 1,
                     "the Stable32 header says Points: " + std::to_string(*h.points) + ", the file has " +
                         std::to_string(s.samples()) + " data lines",
                     "correct the Points: line of the header or restore the missing lines");
  for (auto& c : s.channels)
    for (double& v : c) v = v * h.multiplier + h.addend;
  s.data_type = h.type;
}

}  // namespace

bool looks_like_temperature_column(const std::string& name) {
  static constexpr std::string_view kNames[] = {"temp", "temperature", "temp_c", "temp_degc", "t_degc"};
  return std::find(std::begin(kNames), std::end(kNames), lower_case(name)) != std::end(kNames);
}

bool looks_like_time_column(const std::string& name) {
  static constexpr std::string_view kNames[] = {"t", "time", "t_s", "time_s", "timestamp", "sec", "seconds"};
  return std::find(std::begin(kNames), std::end(kNames), lower_case(name)) != std::end(kNames);
}

Series read_series(const std::string& path_arg, const SeriesOptions& options) {
  check_options(options);
  SeriesOptions opt = options;  // a Stable32 header adds its rate and lines to skip
  // ROS 2 bags read from their files: a bag directory, or an SQLite .db3.
  if (opt.binary.channels.empty() && path_arg != kStdinPath) {
    std::error_code ec;
    // A recording directory of `cubecal record` (manifest.json), else a ROS 2 bag.
    if (looks_like_recording(path_arg)) return read_recording(path_arg, opt);
    if (std::filesystem::is_directory(path_arg, ec))
      return detail::read_bag_series(read_ros2_bag_directory(path_arg), false, opt);
    if (is_sqlite_file(path_arg)) return detail::read_bag_series(read_db3(path_arg), false, opt);
  }
  const FileBuffer buf =
      FileBuffer::open(path_arg, opt.binary.channels.empty() ? Content::series : Content::raw, opt.max_inflated_bytes);
  const std::string& path = buf.path();  // how errors name it ("<stdin>" for "-")
  if (opt.binary.channels.empty() && looks_like_ros_bag(buf.view()))
    return detail::read_bag_series(message_log(parse_ros1_bag(buf.view(), path)), buf.was_gzip(), opt);
  if (opt.binary.channels.empty() && looks_like_mcap(buf.view()))
    return detail::read_bag_series(parse_mcap(buf.view(), path), buf.was_gzip(), opt);
  if (opt.binary.channels.empty() && looks_like_sqlite(buf.view()))
    throw InputError(path, 0, 0,
                     "an SQLite database (a ROS 2 .db3 bag) is read from its file, not "s +
                         (buf.was_gzip() ? "gzip-compressed" : "from standard input"),
                     "give the .db3 file or its bag directory");
  if (opt.binary.channels.empty() && looks_like_ulog(buf.view()))
    return detail::read_ulog_series(parse_ulog(buf.view(), path), buf.view(), buf.was_gzip(), opt);
  const std::string open_path = path_arg == kStdinPath || buf.was_gzip() ? std::string() : path_arg;
  std::optional<Table> all = binary_table(buf.view(), path, open_path, opt);
  const auto stable32 = all ? std::nullopt : stable32_options(buf.view(), path, opt);
  if (!opt.dataset.empty() && !looks_like_hdf5(buf.view()))
    throw UsageError(Field::dataset, path + " is not an HDF5 file: {dataset} chooses a dataset of an HDF5 file");
  const Table layout = all ? Table{} : parse_layout(buf.view(), path, opt.table);
  const TimeChoice time = choose_time_column(opt, all ? *all : layout);

  // The time column is read as an extra column, which also keeps it out of
  // the channels when all columns are wanted.
  Series s;
  s.file = path;
  TableOptions topt = opt.table;
  topt.missing_as_nan = opt.gaps == GapPolicy::skip;  // empty fields and NaN: missing samples
  default_columns(all ? *all : layout, time.spec, opt, topt, s);
  if (!topt.columns.empty()) check_lsb_count(opt, path, topt.columns);  // before the parse of a long file
  const std::size_t time_slot = topt.extra_columns.size();
  if (!time.spec.empty()) topt.extra_columns.push_back(time.spec);
  Table t = all ? select_columns(std::move(*all), topt) : parse_table(buf, topt);

  s.gaps = opt.gaps;
  s.gzip = buf.was_gzip();
  s.bytes = t.bytes;
  if (t.data.empty()) {
    throw InputError(path, 0, 0, "no data columns besides the time column", "name the columns to analyze");
  }
  check_lsb_count(opt, path, t.names);
  check_magnitudes(s, t, opt);
  s.names = t.names;
  s.channels = std::move(t.data);
  for (std::size_t k = 0; k < time_slot; ++k) {
    s.extra_names.push_back(t.extra_names[k]);
    s.extra.push_back(std::move(t.extra[k]));
  }
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const double lsb = opt.lsb_of(c);
    if (lsb != 1.0)
      for (double& v : s.channels[c]) v /= lsb;
  }
  if (stable32) apply_stable32(s, *stable32, t.first_data_line);
  std::vector<double> stamps;
  std::string time_name;
  if (!time.spec.empty()) {
    time_name = t.extra_names[time_slot];
    stamps = std::move(t.extra[time_slot]);
  }
  const std::size_t time_field = time.spec.empty() ? 0 : t.extra_indices[time_slot];
  // A missing sample still has its time; a missing time stamp places nothing.
  for (std::size_t row = 0; row < stamps.size(); ++row)
    if (std::isnan(stamps[row])) {
      const Location loc = locate(t, row, time_field);
      throw InputError(path, loc.line, loc.column, "missing time stamp",
                       "a sample cannot be placed without its time: fill in the stamp or remove the row");
    }
  detail::finish_series(s, std::move(stamps), time_name, time.timing, opt,
                        [&](std::size_t row, std::string problem, std::string hint) {
                          const Location loc = locate(t, row, time_field);
                          return InputError(path, loc.line, loc.column, std::move(problem), std::move(hint));
                        });
  return s;
}

namespace detail {

void finish_series(Series& s, std::vector<double> time, const std::string& time_name, bool timing,
                   const SeriesOptions& opt, const PlaceError& at) {
  // The names of every format (a bag's topics and fields, ULog fields, HDF5
  // datasets) shown as printable_text shows them, as header_name does for text.
  for (auto* names : {&s.names, &s.extra_names, &s.left_out, &s.topics})
    for (std::string& n : *names) n = printable_text(n);
  // (A time column named explicitly is checked stamp by stamp against the
  // given rate in check_timing.)
  if (!timing && !time.empty()) {
    // With the rate given, stamps may repeat (coarse clocks) but not go back.
    for (std::size_t i = 1; i < time.size(); ++i)
      if (time[i] < time[i - 1])
        throw at(i, "time stamp " + stamp(time[i]) + " s is before the previous one " + stamp(time[i - 1]) + " s",
                 "sort the file or fix the logger clock");
    check_rate_agrees(s.file, time_name, time, opt);
  }
  const std::size_t n = s.samples();
  if (n < opt.min_samples) throw_too_short(s.file, n, opt.min_samples, "a longer record is needed");

  if (!timing) {
    s.rate_hz = opt.rate_hz;
    s.tau0 = 1.0 / opt.rate_hz;
    s.segments.push_back({0, n});
    return;
  }

  s.time_name = printable_text(time_name);
  s.time = std::move(time);
  check_timing(s, at, opt);
  const auto longest = std::max_element(s.segments.begin(), s.segments.end(),
                                        [](const IndexRange& a, const IndexRange& b) { return a.size() < b.size(); });
  if (longest->size() < opt.min_samples) {
    throw_too_short(
        s.file, longest->size(), opt.min_samples,
        "longest of " + std::to_string(s.segments.size()) + " contiguous pieces; the record has too many gaps");
  }
  if (!opt.keep_time && s.segments.size() == 1) std::vector<double>().swap(s.time);
}

}  // namespace detail

}  // namespace cubecal::io
