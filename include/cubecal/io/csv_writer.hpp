/// @file
/// Delimited-text output that the readers take back: comma-separated, one
/// header line, numbers in the shortest form that keeps 9 significant digits.
/// A name ending in .gz is written gzip-compressed. Writes go through an
/// AtomicFile (atomic_file.hpp): NAME.partial renamed into place by commit(),
/// so an interrupted run never leaves a truncated file under the real name; an
/// existing file is replaced only when asked.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace cubecal::io {

/// The value a reader gets back for `v` written by CsvWriter (nine
/// significant digits): lets a caller holding the data in memory analyze
/// exactly what the file it writes holds.
double csv_round(double v) noexcept;

/// Writes a delimited-text file (or the standard output) row by row, atomically through NAME.partial.
class CsvWriter {
 public:
  /// Throws UsageError when `path` exists and !force, or cannot be written.
  /// "-" is the standard output (written as it goes, no .partial).
  CsvWriter(std::string path, bool force);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Writes the header line: the column names. Throws UsageError when the file cannot be written.
  void header(const std::vector<std::string>& names);
  /// Writes one row of numbers (in their own units; nine significant digits). Throws UsageError when the file cannot be
  /// written.
  void row(std::span<const double> values);
  /// Flushes and renames NAME.partial to NAME. Throws UsageError when the file cannot be written or renamed. Without
  /// commit() the destructor removes the partial file.
  void commit();
  /// The path written, as given.
  const std::string& path() const noexcept { return path_; }

 private:
  void flush();
  std::string path_;
  std::string buf_;
  bool gzip_ = false;
  struct Sink;
  std::unique_ptr<Sink> sink_;
};

}  // namespace cubecal::io
