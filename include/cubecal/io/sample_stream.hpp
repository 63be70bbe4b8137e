// A record read in bounded pieces, for analyses in constant memory: raw
// interleaved binary (SeriesOptions::binary) or delimited text, from a file
// or the standard input ("-"), with the same column selection, per-column
// LSB, magnitude and timing checks as read_series. A recording directory
// (recording.hpp) of one closed segment without breaks is its chunks read
// in turn as one text, each checked against the manifest's size and CRC-32.
// Compressed text, NumPy, ROS bags and other recordings are read whole by
// read_series and refused here.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"

namespace cubecal::io {

struct SampleChunk {
  std::vector<std::vector<double>> channels;  // channels[c][i], in units (value / lsb)
  std::vector<std::vector<double>> extra;     // the extra columns asked for, as read
  std::size_t rows() const noexcept { return channels.empty() ? 0 : channels[0].size(); }
};

class SampleStream {
 public:
  // Opens the record and reads its layout (the text header, the rate from
  // the first time stamps). Throws InputError / UsageError as read_series;
  // GapPolicy::split is a UsageError(Field::gaps) (a stream is not cut).
  // chunk_bytes: about the bytes read per piece.
  static std::unique_ptr<SampleStream> open(const std::string& path, const SeriesOptions& opt,
                                            std::size_t chunk_bytes = std::size_t{8} << 20);
  virtual ~SampleStream() = default;

  // The next piece (empty at the end: returns false). Checks every value
  // (magnitude) and time stamp (monotonic, gaps, jitter) as it goes.
  virtual bool next(SampleChunk& out) = 0;

  const std::string& file() const noexcept { return file_; }
  const std::vector<std::string>& names() const noexcept { return names_; }
  const std::vector<std::string>& extra_names() const noexcept { return extra_names_; }
  double rate_hz() const noexcept { return rate_hz_; }
  bool rate_from_time() const noexcept { return rate_from_time_; }
  const std::string& time_name() const noexcept { return time_name_; }
  bool default_columns() const noexcept { return default_columns_; }
  const std::vector<std::string>& left_out() const noexcept { return left_out_; }
  // Size of the input when it is a regular file (0 otherwise), and the bytes
  // read so far: the progress of a run.
  std::size_t total_bytes() const noexcept { return total_bytes_; }
  std::size_t bytes_read() const noexcept { return bytes_read_; }
  std::size_t rows_read() const noexcept { return rows_read_; }

 protected:
  std::string file_;
  std::vector<std::string> names_, extra_names_, left_out_;
  double rate_hz_ = 0.0;
  bool rate_from_time_ = false;
  bool default_columns_ = false;
  std::string time_name_;
  std::size_t total_bytes_ = 0, bytes_read_ = 0, rows_read_ = 0;
};

}  // namespace cubecal::io
