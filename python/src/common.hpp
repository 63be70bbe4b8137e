// Arguments the Python calls share, parsed as the CLI parses its options and
// refused with cubecal.UsageError naming the argument.
#pragma once
#include <pybind11/pybind11.h>

#include <string>

#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal::python {

Stat stat_arg(const std::string& name);
DataType data_type_arg(const std::string& name);
// "octave", "decade", "all", "log:K", or a sequence of taus in seconds.
TauGrid taus_arg(const pybind11::object& taus);

}  // namespace cubecal::python

#include <optional>
#include <vector>

#include "cubecal/io/series.hpp"

namespace cubecal::python {

// How a file is read: the keywords of cubecal.read (and of analyze and the
// calibrations on a path), in the words of the CLI's input options.
struct ReadArgs {
  std::vector<std::string> columns;
  std::string time;   // time column; empty: detected by name
  double rate = 0.0;  // 0: from the time column
  std::size_t skip_rows = 0;
  std::vector<double> lsb;          // counts per unit: one for all or one per column
  std::string gaps = "error";       // "error", "split" or "skip" (missing samples: see series_options)
  std::vector<std::string> topics;  // ROS bags
  std::string dataset;              // HDF5
  std::string binary;               // raw frames: "float64le,int16le,..."
  std::size_t header_bytes = 0;
  std::vector<std::string> extra;  // further columns read as they are (a temperature)
  unsigned threads = 0;
};

// gaps="skip" (an empty field or NaN is a missing sample, a gap of whole
// periods is filled with them) is taken where the call leaves missing samples
// out, as the CLI's --gaps skip (`missing_samples`: cubecal.read, davar, dev),
// and refused with UsageError(Field::gaps) elsewhere.
io::SeriesOptions series_options(const ReadArgs& a, bool missing_samples = false);
// The record as a dict of 1-D arrays in file order (time first when there is
// one, the channels, then the extra columns) and its metadata.
pybind11::tuple series_to_python(io::Series&& s);

}  // namespace cubecal::python
