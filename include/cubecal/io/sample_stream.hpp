/// @file
/// A record read in bounded pieces, for analyses in constant memory: raw
/// interleaved binary (SeriesOptions::binary) or delimited text, from a file
/// or the standard input ("-"), with the same column selection, per-column
/// LSB, magnitude and timing checks as read_series. A recording directory
/// (recording.hpp) of one closed segment without breaks is its chunks read
/// in turn as one text, each checked against the manifest's size and CRC-32.
/// Gzip-compressed input is inflated piece by piece (every member in turn);
/// a NumPy .npy is its header, then rows of raw samples (a 2-D array in
/// Fortran order read column by column from its file). A ROS 1 bag, MCAP
/// file, rosbag2 .db3 or bag directory is read a chunk (or a MiB of rows) at
/// a time, one topic; an HDF5 dataset by hyperslabs of rows. A PX4 ULog, a
/// Stable32 .DAT and other recordings are read whole by read_series and
/// refused here.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"

namespace cubecal::io {

/// One piece of a streamed record.
struct SampleChunk {
  std::vector<std::vector<double>> channels;  ///< channels[c][i], in units (value / lsb)
  std::vector<std::vector<double>> extra;     ///< the extra columns asked for, as read
  /// Rows (samples per channel) in the piece.
  std::size_t rows() const noexcept { return channels.empty() ? 0 : channels[0].size(); }
};

/// A record read in bounded pieces (open, then next until it returns false).
class SampleStream {
 public:
  /// Opens the record and reads its layout (the text header, the rate from
  /// the first time stamps). Throws InputError / UsageError as read_series;
  /// GapPolicy::split is a UsageError(Field::gaps) (a stream is not cut).
  /// chunk_bytes: about the bytes read per piece.
  static std::unique_ptr<SampleStream> open(const std::string& path, const SeriesOptions& opt,
                                            std::size_t chunk_bytes = std::size_t{8} << 20);
  virtual ~SampleStream() = default;

  /// The next piece (empty at the end: returns false). Checks every value
  /// (magnitude) and time stamp (monotonic, gaps, jitter) as it goes.
  virtual bool next(SampleChunk& out) = 0;

  /// The path given, or "<stdin>".
  const std::string& file() const noexcept { return file_; }
  /// The channels' names (header names, or "col3").
  const std::vector<std::string>& names() const noexcept { return names_; }
  /// The extra columns' names.
  const std::vector<std::string>& extra_names() const noexcept { return extra_names_; }
  /// Sampling rate (Hz), given or inferred from the first time stamps.
  double rate_hz() const noexcept { return rate_hz_; }
  /// True when the rate was inferred from the time column.
  bool rate_from_time() const noexcept { return rate_from_time_; }
  /// The time column's name; empty when none is used.
  const std::string& time_name() const noexcept { return time_name_; }
  /// True when no columns were named and every other column was taken.
  bool default_columns() const noexcept { return default_columns_; }
  /// The columns left out when default_columns() (time, extra and temperature columns).
  const std::vector<std::string>& left_out() const noexcept { return left_out_; }
  /// Size of the input when it is a regular file (0 otherwise), and the bytes
  /// read so far: the progress of a run.
  std::size_t total_bytes() const noexcept { return total_bytes_; }
  /// Bytes read so far.
  std::size_t bytes_read() const noexcept { return bytes_read_; }
  /// Rows read so far.
  std::size_t rows_read() const noexcept { return rows_read_; }

 protected:
  /// See file().
  std::string file_;
  /// See names(), extra_names(), left_out().
  ///@{
  std::vector<std::string> names_, extra_names_, left_out_;
  ///@}
  /// See rate_hz().
  double rate_hz_ = 0.0;
  /// See rate_from_time().
  bool rate_from_time_ = false;
  /// See default_columns().
  bool default_columns_ = false;
  /// See time_name().
  std::string time_name_;
  /// See total_bytes(), bytes_read(), rows_read().
  ///@{
  std::size_t total_bytes_ = 0, bytes_read_ = 0, rows_read_ = 0;
  ///@}
};

/// What reading a file whole would hold, told from its first bytes without
/// reading it all (for choosing between reading it whole and streaming it).
struct InputEstimate {
  /// The bytes of the content: a plain file's size, a gzip file's inflated
  /// size (estimated from the inflation of its first MiBs when it is larger);
  /// 0 for the standard input, a pipe or a file that cannot be opened.
  std::size_t content_bytes = 0;
  /// The values (rows x columns) a NumPy .npy's header declares (0: not a .npy).
  std::size_t npy_values = 0;
  /// The rows a NumPy .npy's header declares (0: not a .npy).
  std::size_t npy_rows = 0;
  bool gzip = false;  ///< the file is gzip-compressed
  std::string head;   ///< the first MiB (at most) of the content
};

/// The estimate for `path`; throws nothing (what is wrong with a file is for
/// the reader to say).
InputEstimate estimate_input(const std::string& path);

}  // namespace cubecal::io
