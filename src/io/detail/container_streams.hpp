// The streams of SampleStream::open for the container formats: a robot log
// (ROS 1 bag, MCAP, rosbag2 .db3 or bag directory: message_stream.cpp) and
// an HDF5 file (hdf5_stream.cpp). Each gives the values, names, rate and
// timing checks read_series gives the whole record.
#pragma once
#include <memory>
#include <string>

#include "cubecal/io/sample_stream.hpp"

namespace cubecal::io::detail {

// The stream of a robot log at `path` (a file or a bag directory), or null
// when it is none; one topic at a time.
std::unique_ptr<SampleStream> open_message_stream(const std::string& path, const SeriesOptions& opt);
// The stream of an HDF5 file at `path` read by hyperslabs of rows, or null
// when it is none.
std::unique_ptr<SampleStream> open_hdf5_stream(const std::string& path, const SeriesOptions& opt);

// The first bytes of the regular file at `path` (up to `n`; empty for
// anything else: a pipe, a directory, the standard input).
std::string file_head(const std::string& path, std::size_t n);

}  // namespace cubecal::io::detail
