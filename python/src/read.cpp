// cubecal._read: every reader of the library (delimited text, gzip, .npy,
// HDF5, ROS 1/2 bags, MCAP, ULog, raw frames) into NumPy arrays, with the
// reader's errors as cubecal.InputError (file, line, column).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "common.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/raw_binary_reader.hpp"
#include "cubecal/io/series.hpp"
#include "module.hpp"

namespace py = pybind11;

namespace cubecal::python {

io::SeriesOptions series_options(const ReadArgs& a, bool missing_samples) {
  io::SeriesOptions s;
  s.table.columns = a.columns;
  s.table.extra_columns = a.extra;
  s.table.skip_rows = a.skip_rows;
  s.table.threads = a.threads;
  s.time_col = a.time;
  if (a.rate < 0.0 || !std::isfinite(a.rate)) throw UsageError(Field::rate, "rate must be a positive number of Hz");
  s.rate_hz = a.rate;
  for (const double x : a.lsb)
    if (!(x > 0.0) || !std::isfinite(x))
      throw UsageError(Field::lsb, "lsb: every value must be a positive number of counts per unit");
  s.lsb = a.lsb.empty() ? std::vector<double>{1.0} : a.lsb;
  if (a.gaps != "error" && a.gaps != "split" && a.gaps != "skip")
    throw UsageError(Field::gaps, "gaps must be \"error\", \"split\" or \"skip\"");
  if (a.gaps == "skip" && !missing_samples)
    throw UsageError(Field::gaps,
                     "gaps=\"skip\": this call needs every sample (missing samples are skipped by dev and "
                     "davar, for OADEV); use gaps=\"split\" to analyze the contiguous pieces");
  s.gaps = a.gaps == "split" ? io::GapPolicy::split : a.gaps == "skip" ? io::GapPolicy::skip : io::GapPolicy::error;
  s.topics = a.topics;
  s.dataset = a.dataset;
  if (a.binary.empty()) {
    if (a.header_bytes != 0)
      throw UsageError(Field::header_bytes, "header_bytes applies to raw binary input: give binary=TYPES");
  } else {
    if (a.skip_rows != 0)
      throw UsageError(Field::skip_rows, "skip_rows counts text lines; for raw binary give header_bytes");
    s.binary = io::parse_raw_layout(a.binary, a.header_bytes);
  }
  return s;
}

py::tuple series_to_python(io::Series&& s) {
  // Missing samples (NaN) of each channel, before the channels move: gaps="skip" only.
  py::list missing;
  for (const auto& c : s.channels)
    missing.append(s.gaps == io::GapPolicy::skip ? static_cast<std::size_t>(std::count_if(
                                                       c.begin(), c.end(), [](double v) { return std::isnan(v); }))
                                                 : std::size_t{0});
  py::dict columns;
  if (!s.time.empty()) columns[py::str(s.time_name.empty() ? "t" : s.time_name)] = to_array(std::move(s.time));
  for (std::size_t c = 0; c < s.channels.size(); ++c) columns[py::str(s.names[c])] = to_array(std::move(s.channels[c]));
  for (std::size_t c = 0; c < s.extra.size(); ++c) columns[py::str(s.extra_names[c])] = to_array(std::move(s.extra[c]));
  py::dict meta;
  meta["file"] = s.file;
  meta["rate_hz"] = s.rate_hz;
  meta["rate_from_time"] = s.rate_from_time;
  meta["time"] = s.time_name;
  meta["channels"] = s.names;
  meta["extra"] = s.extra_names;
  meta["units"] = s.units;
  meta["left_out"] = s.left_out;
  meta["topics"] = s.topics;
  py::list segments;
  for (const IndexRange& g : s.segments) segments.append(py::make_tuple(g.begin, g.end));
  meta["segments"] = segments;
  meta["gaps"] = s.gaps == io::GapPolicy::split ? "split" : s.gaps == io::GapPolicy::skip ? "skip" : "error";
  meta["missing_samples"] = missing;
  meta["bytes"] = s.bytes;
  return py::make_tuple(columns, meta);
}

namespace {

py::tuple read(const std::string& path, const ReadArgs& args) {
  const io::SeriesOptions so = series_options(args, true);  // gaps="skip": NaN in the arrays
  io::Series s;
  {
    py::gil_scoped_release free;
    s = io::read_series(path, so);
  }
  return series_to_python(std::move(s));
}

}  // namespace

void bind_read(py::module_& m) {
  py::class_<ReadArgs>(m, "_ReadArgs")
      .def(py::init<>())
      .def_readwrite("columns", &ReadArgs::columns)
      .def_readwrite("time", &ReadArgs::time)
      .def_readwrite("rate", &ReadArgs::rate)
      .def_readwrite("skip_rows", &ReadArgs::skip_rows)
      .def_readwrite("lsb", &ReadArgs::lsb)
      .def_readwrite("gaps", &ReadArgs::gaps)
      .def_readwrite("topics", &ReadArgs::topics)
      .def_readwrite("dataset", &ReadArgs::dataset)
      .def_readwrite("binary", &ReadArgs::binary)
      .def_readwrite("header_bytes", &ReadArgs::header_bytes)
      .def_readwrite("extra", &ReadArgs::extra)
      .def_readwrite("threads", &ReadArgs::threads);
  m.def("_read", &read, py::arg("path"), py::arg("args"),
        "A record read and checked as the CLI reads it: (columns dict, metadata dict).");
}

}  // namespace cubecal::python
