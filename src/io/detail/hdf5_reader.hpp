// HDF5 datasets (through libhdf5): a numeric 1-D dataset is one channel
// (named after the dataset), a 2-D dataset has a row per sample and a
// column per channel (col1..colN), a 1-D compound dataset gives its numeric
// members as named columns, and a group of numeric 1-D datasets of equal
// length gives one named column per dataset. Chunked and compressed
// datasets are read by the library. No time axis unless a named column is
// one (t, time...): the rate is given otherwise.
#pragma once
#include <memory>
#include <string>
#include <string_view>

#include "cubecal/io/delimited_reader.hpp"

namespace cubecal::io {

// Whether `head` holds the HDF5 signature "\x89HDF\r\n\x1a\n" at offset 0,
// 512, 1024, 2048... (after a user block), as far as `head` goes.
bool looks_like_hdf5(std::string_view head) noexcept;

// Every column of `dataset` (a path such as "/imu/data"; a group for the
// group form). Empty: the file's only numeric 1-D or 2-D dataset; with
// several or none, an InputError lists the datasets (path, shape, type).
// The file is opened at `open_path` when it is a plain file there (empty:
// from `bytes`, e.g. standard input or inflated gzip). Every HDF5 error is
// an InputError of one line naming `file` (the library prints nothing). An
// infinite value is an InputError naming its row and column; so is a NaN,
// unless `missing_as_nan` (`--gaps skip`: a NaN is a missing sample, kept as
// NaN).
Table read_hdf5(std::string_view bytes, const std::string& file, const std::string& open_path,
                const std::string& dataset, bool missing_as_nan = false);

// The dataset (or group) read_hdf5 reads, taken a hyperslab of rows at a
// time (hdf5_stream.cpp): the same choice, columns, names and checks.
class Hdf5Rows {
 public:
  // Opens the file at `path`; throws InputError as read_hdf5.
  Hdf5Rows(const std::string& path, const std::string& dataset);
  ~Hdf5Rows();
  Hdf5Rows(const Hdf5Rows&) = delete;
  Hdf5Rows& operator=(const Hdf5Rows&) = delete;
  // Rows of the dataset.
  std::size_t rows() const noexcept;
  // Rows [first, first + count) as read_hdf5's table holds them (every
  // column, named); an infinite or NaN value is an InputError naming its row
  // of the dataset.
  Table slab(std::size_t first, std::size_t count) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cubecal::io
