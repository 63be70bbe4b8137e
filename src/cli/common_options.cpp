#include "common_options.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/noise/unit_from_name.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::cli {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const auto comma = s.find(',', start);
    std::string item = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    item = b == std::string::npos ? std::string() : item.substr(b, e - b + 1);
    if (!item.empty()) out.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

namespace {

// The option's text as a finite double, or nullopt (strict: the whole text).
std::optional<double> finite_number(const std::string& text) {
  double x = 0.0;
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  const auto [p, ec] = std::from_chars(b, e, x);
  if (ec != std::errc() || p != e || !std::isfinite(x)) return std::nullopt;
  return x;
}

std::string shown(double x) { return fmt::format("{:g}", x); }

}  // namespace

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const auto x = finite_number(s);
        return x && *x > 0.0 ? std::string() : "'" + s + "' is not a positive number";
      },
      "POSITIVE");
}

CLI::Validator number_between(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        const auto x = finite_number(s);
        return x && *x >= lo && *x <= hi ? std::string()
                                         : "'" + s + "' is not a number from " + shown(lo) + " to " + shown(hi);
      },
      "NUMBER in [" + shown(lo) + ", " + shown(hi) + "]");
}

CLI::Validator whole_number(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) -> std::string {
        const auto x = finite_number(s);
        return x && *x == std::floor(*x) && *x >= lo && *x <= hi
                   ? std::string()
                   : "'" + s + "' is not a whole number from " + shown(lo) + " to " + shown(hi);
      },
      "INTEGER in [" + shown(lo) + ", " + shown(hi) + "]");
}

void note_default_columns(const io::Series& s) {
  if (s.default_topic && !s.topics.empty())
    std::cerr << "cubecal: note: " << printable_text(s.file) << ": topic " << s.topics.front()
              << " (--topic chooses others)\n";
  if (!s.default_columns || s.left_out.empty()) return;
  const auto join = [](const std::vector<std::string>& v) {
    std::string r;
    for (const auto& x : v) r += (r.empty() ? "" : ",") + x;
    return r;
  };
  std::cerr << "cubecal: note: " << printable_text(s.file) << ": columns " << join(s.names)
            << " (left out: " << join(s.left_out) << "; --columns chooses others)\n";
}

void add_input_options(CLI::App& app, InputOptions& opt, bool several) {
  if (several)
    app.add_option("files", opt.files,
                   "Input files (one record each): delimited text, optionally gzip, "
                   "NumPy .npy, HDF5, raw binary (--binary), ROS bags (ROS 1 .bag, MCAP, .db3 or a ROS 2 bag "
                   "directory), PX4 ULog "
                   "or a recording directory of cubecal record")
        ->required();
  else
    app.add_option(
           "file", opt.file,
           "Input file: delimited text (comma, tab, semicolon or "
           "whitespace), optionally gzip-compressed, NumPy .npy (1-D or 2-D), HDF5 "
           "(--dataset), raw binary (--binary), a ROS bag (ROS 1 .bag, MCAP, .db3 or a ROS 2 "
           "bag directory), a PX4 ULog (.ulg) or a recording directory of cubecal record; - reads standard input")
        ->required();
  app.add_option("--columns", opt.columns,
                 "Columns to analyse, by header name or 1-based index (gx,gy,gz or 2,3,4); "
                 "default: every column except the time and temperature columns (t, time, "
                 "timestamp..., temp, temperature and those named by --time-col / --temp-col)");
  app.add_option("--time-col", opt.time_col,
                 "Time column (seconds), by name or index; default: a column named t, time, "
                 "t_s, timestamp...; for a ROS bag: stamp (header.stamp, default) or record (the log time: when "
                 "the bag recorded each message)");
  app.add_option("--rate", opt.rate_hz,
                 "Sampling rate in Hz (inferred from the time column "
                 "when not given)")
      ->check(positive_number());
  app.add_option("--skip-rows", opt.skip_rows, "Lines to skip before the header/data (preamble)")
      ->check(whole_number(0, 1e9));
  app.add_option("--lsb", opt.lsb,
                 "Counts per unit: values are divided by this (raw counts "
                 "to physical units); one for every column or one per column in their "
                 "order, e.g. 131,131,131,16384,16384,16384");
  app.add_option("--gaps", opt.gaps,
                 "What to do with time gaps or jitter beyond 1 % of the "
                 "period: error (default) or split (analyse contiguous "
                 "segments and combine); dev and davar also take skip (empty fields, NaN "
                 "and gaps of whole periods are missing samples, left out of the OADEV "
                 "terms that need them, as AllanTools' gradev)")
      ->check(CLI::IsMember({"error", "split", "skip"}));
  app.add_option("--threads", opt.threads, "Worker threads (default: all cores)")->check(whole_number(0, 4096));
  app.add_option("--topic", opt.topics,
                 "ROS bag: topic to read (sensor_msgs/Imu: gx gy gz ax ay az; MagneticField: mx my mz; "
                 "Temperature: temp); repeat for several. Default: the bag's only Imu topic. PX4 ULog: "
                 "sensor_combined (default: gx gy gz ax ay az), vehicle_magnetometer (mx my mz, in T), "
                 "sensor_gyro, sensor_accel, sensor_mag (with temp); instance N of a topic is NAME:N")
      ->allow_extra_args(false)
      ->delimiter(',');
  app.add_option("--dataset", opt.dataset,
                 "HDF5: the dataset to read (/imu/data), or a group of equal-length 1-D datasets; default: the "
                 "file's only numeric 1-D or 2-D dataset");
  app.add_option("--binary", opt.binary,
                 "Read raw interleaved binary frames: one sample type per channel, e.g. "
                 "int16le,int16le,int16le,float32le (int8, uint8, int16, uint16, int32, uint32, int64, uint64, "
                 "float32, float64; le or be after all but the 8-bit types); columns are col1..colN; needs --rate");
  app.add_option("--header-bytes", opt.header_bytes, "Bytes to skip before the first --binary frame")
      ->check(whole_number(0, 1e15));
}

std::vector<Unit> parse_units(const std::string& list) {
  std::vector<Unit> units;
  for (const auto& name : split_list(list)) {
    auto u = parse_unit(name);
    if (!u) throw UsageError("unknown unit '" + name + "' (use " + known_units() + ")");
    units.push_back(*u);
  }
  return units;
}

std::string unit_option_help() {
  return "Unit of the values (after --lsb): " + known_units() +
         "; one for all columns or one per column. Default: from the column names' suffixes (_dps, _rads, _dph, "
         "_g, _mps2, _uT, _mG, _nT, gx[deg/s]...), said on stderr; an error when a name has none (--unit counts "
         "for raw values)";
}

ChannelUnits units_for(const std::string& unit_option, const io::Series& s) {
  if (!unit_option.empty()) return {parse_units(unit_option), {}};
  if (!s.units.empty()) {
    // The format says them (ROS messages are in SI units).
    ChannelUnits r;
    std::string said;
    for (std::size_t i = 0; i < s.units.size(); ++i) {
      const auto u = parse_unit(s.units[i]);
      if (!u)
        throw UsageError(s.file + ": channel " + s.names[i] + " is in " + s.units[i] +
                         ", which is not a unit of noise terms: give --unit (" + known_units() + ")");
      r.units.push_back(*u);
      const bool run = i > 0 && s.units[i] == s.units[i - 1];
      said += (run ? "," : said.empty() ? "" : "; ") + s.names[i];
      if (i + 1 == s.units.size() || s.units[i + 1] != s.units[i]) said += " " + s.units[i];
    }
    r.note = "cubecal: note: " + printable_text(s.file) + ": units from " +
             (s.units_from.empty() ? "the message types" : s.units_from) + ": " + said + " (--unit overrides)";
    return r;
  }
  const InferredUnits inferred = infer_units(s.names);
  if (!inferred.missing.empty()) {
    std::string cols;
    for (const auto& n : inferred.missing) cols += (cols.empty() ? "" : ", ") + n;
    const bool several = inferred.missing.size() > 1;
    throw UsageError(s.file + ": no unit in the name" + (several ? "s of columns " : " of column ") + cols +
                     ": give --unit (" + known_units() +
                     "; one for all columns or one per column; counts for raw values) or end the names with a unit (" +
                     known_unit_suffixes() + ")");
  }
  // Which unit for which columns, runs of the same unit together.
  std::string said;
  for (std::size_t i = 0; i < s.names.size();) {
    std::size_t j = i;
    std::string cols;
    while (j < s.names.size() && inferred.units[j].name == inferred.units[i].name)
      cols += (cols.empty() ? "" : ",") + s.names[j++];
    said += (said.empty() ? "" : "; ") + cols + " " + inferred.units[i].name;
    i = j;
  }
  return {inferred.units, "cubecal: note: " + printable_text(s.file) + ": units from the column names: " + said +
                              " (--unit overrides)"};
}

TauGrid parse_taus(const std::string& spec) {
  try {
    return parse_tau_grid(spec);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--taus: ") + e.what());
  }
}

std::vector<double> parse_lsb_list(const std::string& list) {
  std::vector<double> lsb;
  for (const auto& v : split_list(list)) {
    const auto x = finite_number(v);
    if (!x || !(*x > 0.0))
      throw UsageError("--lsb: '" + v +
                       "' is not a positive number of counts per unit (give one for every "
                       "column, or one per column: 131,131,131,16384,16384,16384)");
    lsb.push_back(*x);
  }
  if (lsb.empty()) lsb.push_back(1.0);
  return lsb;
}

io::SeriesOptions to_series_options(const InputOptions& opt) {
  io::SeriesOptions s;
  s.table.columns = split_list(opt.columns);
  s.table.skip_rows = opt.skip_rows;
  s.table.threads = opt.threads;
  s.time_col = opt.time_col;
  if (opt.rate_hz < 0.0 || !std::isfinite(opt.rate_hz)) throw UsageError("--rate must be a positive number of Hz");
  s.rate_hz = opt.rate_hz;
  s.lsb = parse_lsb_list(opt.lsb);
  s.gaps = opt.gaps == "split" ? io::GapPolicy::split : opt.gaps == "skip" ? io::GapPolicy::skip : io::GapPolicy::error;
  if (s.gaps == io::GapPolicy::skip && !opt.missing_samples)
    throw UsageError(
        "--gaps skip: this command needs every sample (missing samples are skipped by dev and "
        "davar, for OADEV); use --gaps split to analyze the contiguous pieces");
  s.topics = opt.topics;
  s.dataset = opt.dataset;
  if (opt.binary.empty()) {
    if (opt.header_bytes != 0) throw UsageError("--header-bytes: applies to raw binary input: give --binary TYPES");
  } else {
    if (opt.skip_rows != 0) throw UsageError("--skip-rows: counts text lines; for raw binary give --header-bytes N");
    s.binary = io::parse_raw_layout(opt.binary, opt.header_bytes);
  }
  return s;
}

}  // namespace cubecal::cli
