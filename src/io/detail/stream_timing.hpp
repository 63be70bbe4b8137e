// The timing checks of read_series (series.cpp's check_timing and
// check_rate_agrees) on a record that arrives in pieces: the rate given, or
// inferred from the median interval of the first stamps (the first piece
// of a streamed text, the first 65536 stamps of a log or dataset), then
// every stamp checked against the period as it comes. A stream is not cut:
// a gap or jitter is an error naming its place. Used by message_stream.cpp
// and hdf5_stream.cpp.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "series_timing.hpp"

namespace cubecal::io::detail {

class StreamTiming {
 public:
  // timing: the stamps give or check the rate (read_series' `timing`);
  // otherwise opt.rate_hz is used and only checked against the stamps.
  StreamTiming(const SeriesOptions& opt, bool timing, std::string file, std::string time_name)
      : opt_(opt), timing_(timing), file_(std::move(file)), time_name_(std::move(time_name)) {}

  // The rate from the first stamps `head` (rows 0.. of the record). Throws
  // InputError placed by `at`, UsageError for a rate that contradicts them.
  void start(const std::vector<double>& head, const PlaceError& at);
  // Checks stamps `t`, the first of which is row `first` of the record.
  void check(const std::vector<double>& t, std::size_t first, const PlaceError& at);

  double rate_hz() const noexcept { return rate_hz_; }
  bool rate_from_time() const noexcept { return from_time_; }

 private:
  SeriesOptions opt_;
  bool timing_;
  std::string file_, time_name_;
  double rate_hz_ = 0.0;
  bool from_time_ = false;
  bool have_last_ = false;
  double last_ = 0.0;
};

}  // namespace cubecal::io::detail
