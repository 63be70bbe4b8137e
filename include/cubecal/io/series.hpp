/// @file
/// A uniformly sampled multi-channel record: the selected columns of a file,
/// scaled to physical units, with its sampling rate, checked for gaps, jitter
/// and non-monotonic time stamps.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/io/raw_binary_reader.hpp"
#include "cubecal/math/index_range.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal::io {

/// What a record's irregular time stamps and missing values do: error (the
/// default) refuses them at their place; split cuts the record into
/// contiguous segments at gaps and jitter; skip keeps one segment, reads an
/// empty field or NaN as a missing sample (NaN; a NaN of a .npy, raw binary
/// or HDF5 record too, never an infinity) and fills a gap of whole
/// periods in the time stamps with missing samples, for the statistics that
/// leave missing samples out (stats/gap_deviation.hpp: `dev --gaps skip`,
/// `davar --gaps skip`).
enum class GapPolicy { error, split, skip };

/// The range of sampling rates and data magnitudes every statistic can take
/// without its sums of squares overflowing or underflowing: a rate (given or
/// inferred from the time stamps) outside [kMinRateHz, kMaxRateHz] is a
/// UsageError(Field::rate) or an InputError at the time column; a value (after the
/// LSB) whose magnitude exceeds kMaxMagnitude, or is non-zero below
/// kMinMagnitude, an InputError at its place.
inline constexpr double kMinRateHz = 1e-9;
/// The largest sampling rate accepted (Hz).
inline constexpr double kMaxRateHz = 1e9;
/// The largest data magnitude accepted (data unit, after the LSB).
inline constexpr double kMaxMagnitude = 1e100;
/// The smallest non-zero data magnitude accepted (data unit, after the LSB).
inline constexpr double kMinMagnitude = 1e-100;

/// How to read a record into a Series.
struct SeriesOptions {
  TableOptions table;    ///< columns, skip_rows, threads
  std::string time_col;  ///< name or 1-based index; empty: auto-detect by name
  double rate_hz = 0.0;  ///< 0: infer from the time column
  /// Counts per unit of the selected columns (value / lsb): one value for
  /// every column, or one per column in their order (table.columns, or the
  /// default columns); empty is 1. Any other count is a
  /// UsageError(Field::counts_per_unit) naming both counts.
  std::vector<double> lsb{1.0};
  /// The LSB of channel c (lsb.size() is 0, 1 or the number of channels).
  double lsb_of(std::size_t c) const { return lsb.empty() ? 1.0 : lsb.size() == 1 ? lsb[0] : lsb.at(c); }
  /// What a gap or an irregular interval in the time stamps does (GapPolicy).
  GapPolicy gaps = GapPolicy::error;
  std::size_t min_samples = 3;  ///< fewer samples (after splitting, the longest segment) is an error
  double tolerance = 0.01;      ///< allowed |dt - period| / period
  /// With no columns named (table.columns empty): leave out, besides the time
  /// column and the extra columns, the columns whose header name looks like a
  /// temperature (looks_like_temperature_column). False for a file that is
  /// read for its temperature.
  bool skip_temperature = true;
  /// A given rate_hz must agree with the time column, when there is one,
  /// within `tolerance` of its median interval (UsageError(Field::rate) if not).
  /// False where the time stamps are not used at all.
  bool check_rate_against_time = true;
  /// ROS bags: the topics to read (sensor_msgs/Imu, MagneticField,
  /// Temperature; at most one of each type). Empty: the bag's only
  /// sensor_msgs/Imu topic. A bag's time is "stamp" (header.stamp, the
  /// default) or "record" (when the bag recorded the message), as time_col.
  std::vector<std::string> topics;
  /// false: the time stamps of a record in one contiguous segment are
  /// dropped once they are checked (Series::time is then empty; the rate and
  /// the jitter figures stay), for callers that need no more than those, so
  /// that the stamps do not add a column to the memory. A record cut at gaps
  /// keeps them (the length of each gap is in the stamps).
  bool keep_time = true;
  /// HDF5: the dataset to read ("/imu/data"), or a group of 1-D datasets.
  /// Empty: the file's only numeric 1-D or 2-D dataset.
  std::string dataset;
  /// Raw interleaved binary frames of these types (the file is then not
  /// recognised by its content). Empty: delimited text or NumPy .npy, told
  /// apart by the file's first bytes.
  RawLayout binary;
  /// A gzip file is inflated into memory up to this many bytes (0: no
  /// limit); more is an InputError naming {memory} and {stream}, raised
  /// before the memory is taken.
  std::size_t max_inflated_bytes = 0;
};

/// A record as read: its channels, sampling rate, time column and gaps.
struct Series {
  /// The path given, or "<stdin>".
  std::string file;
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  double tau0 = 0.0;               ///< 1 / rate_hz
  bool rate_from_time = false;     ///< rate inferred from the time column
  std::string time_name;           ///< empty: no time column used
  std::vector<std::string> names;  ///< channel names (header names, or "col3")
  /// No columns were named: the channels are every column but these (the time
  /// column, the extra columns, the temperature columns), named as in the header.
  bool default_columns = false;
  /// The columns left out when default_columns.
  std::vector<std::string> left_out;
  std::vector<std::vector<double>> channels;  ///< channels[c][i], in units (value / lsb_of(c))
  /// The unit of each channel when the format says it ("rad/s", "m/s^2", "T"
  /// for ROS messages); empty when it does not (text).
  std::vector<std::string> units;
  /// What says them, for messages ("the recording's manifest"); empty: the
  /// message types (ROS).
  std::string units_from;
  /// ROS bags: the topics read, as "/imu/data_raw (sensor_msgs/Imu, 13964
  /// messages)"; default_topic when none was asked for and the bag's only
  /// IMU topic was taken.
  std::vector<std::string> topics;
  /// True when no topic was asked for and the bag's only IMU topic was taken.
  bool default_topic = false;
  std::vector<double> time;  ///< seconds, empty when no time column
  /// Auxiliary columns asked for in SeriesOptions::table.extra_columns (e.g. a
  /// temperature), as read: not scaled by lsb.
  std::vector<std::string> extra_names;
  /// The extra columns, extra[c][i], as read.
  std::vector<std::vector<double>> extra;
  std::vector<IndexRange> segments;     ///< contiguous pieces (rows); one when there are no gaps
  GapPolicy gaps = GapPolicy::error;    ///< the policy the record was read with
  std::size_t irregular_intervals = 0;  ///< gaps/jitter split on (policy split)
  bool gzip = false;                    ///< the file was gzip-compressed
  /// The data type the file says (a Stable32 .DAT header's "Type:"); none
  /// when it says nothing, as text and binary formats.
  std::optional<DataType> data_type;
  std::size_t bytes = 0;  ///< bytes parsed (after decompression)
  /// Samples per channel.
  std::size_t samples() const noexcept { return channels.empty() ? 0 : channels[0].size(); }
};

/// Reads and checks a record: delimited text, NumPy .npy, HDF5, a ROS 1 bag
/// or a PX4 ULog (by their magic bytes) or raw binary (opt.binary); "-" is the standard input. Binary
/// columns are named col1..colN and go through the same checks. Throws InputError for every problem in the data
/// (location FILE:LINE:COL) and UsageError for contradictory options.
Series read_series(const std::string& path, const SeriesOptions& opt);

/// Names that are taken as a time column when none is named: t, time, t_s,
/// time_s, timestamp, sec, seconds (case-insensitive).
bool looks_like_time_column(const std::string& name);

/// Names taken as a temperature column: temp, temperature, temp_c, temp_degc,
/// t_degc (case-insensitive).
bool looks_like_temperature_column(const std::string& name);

}  // namespace cubecal::io
