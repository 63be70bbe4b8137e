/// @file
/// Delimited-text reader: comma, tab, semicolon or whitespace (auto-detected),
/// optional header line, '#' comment lines, preamble rows to skip, gzip input.
/// Parses in parallel; returns the selected columns as contiguous arrays.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::io {

/// The field separator of a delimited-text file (detected from its first lines).
enum class Delimiter { comma, tab, semicolon, whitespace };

/// What to read from a delimited-text file.
struct TableOptions {
  std::size_t skip_rows = 0;  ///< physical lines dropped before anything else
  /// Columns wanted, by header name or 1-based index ("gx", "3"). Empty: all
  /// columns except the extra ones. Resolved against the header when there is
  /// one (exact name, else index, else name ignoring case); an unknown name
  /// is an InputError pointing at the header line.
  std::vector<std::string> columns;
  /// Extra column (e.g. time or temperature) to read besides `columns`; empty
  /// for none. Same name/index rules.
  std::vector<std::string> extra_columns;
  unsigned threads = 0;  ///< 0: hardware concurrency
  /// An empty field, or NaN spelled out, is a missing sample, read as a quiet
  /// NaN (SeriesOptions: GapPolicy::skip); else it is an error at its place.
  bool missing_as_nan = false;
};

/// The columns of a file as numbers (data in the file's own units), with where they came from.
struct Table {
  /// The path given, or the label of the input ("<stdin>").
  std::string file;
  /// The delimiter detected.
  Delimiter delimiter = Delimiter::comma;
  /// True when the first data line is a header of names.
  bool has_header = false;
  std::vector<std::string> header;        ///< all header names (empty if none)
  std::size_t total_columns = 0;          ///< fields per row in the file
  std::vector<std::string> names;         ///< names of the selected columns
  std::vector<std::size_t> indices;       ///< 0-based indices of selected columns
  std::vector<std::vector<double>> data;  ///< data[c][row], selected columns
  /// Names of the extra columns read (header names, or "col3").
  std::vector<std::string> extra_names;
  std::vector<std::size_t> extra_indices;  ///< 0-based indices of the extra columns
  std::vector<std::vector<double>> extra;  ///< extra[c][row]
  std::size_t first_data_line = 0;         ///< 1-based line number of row 0
  TableOptions options;                    ///< what was asked (for locate())
  /// Data rows read.
  std::size_t rows() const noexcept { return data.empty() ? (extra.empty() ? 0 : extra[0].size()) : data[0].size(); }
  std::size_t bytes = 0;  ///< decompressed bytes parsed
  /// Read from a binary format (no lines: locate() gives the 1-based row and
  /// column; the columns are named col1..colN and chosen by 1-based index).
  bool binary = false;
};

/// Reads a whole file. Every malformed field (non-numeric, NaN/Inf, empty),
/// wrong field count or empty file throws InputError with FILE:LINE:COL.
Table read_table(const std::string& path, const TableOptions& opt = {});

/// Same, from text already in memory (used by tests and by gzip input).
Table parse_table(std::string_view text, const std::string& file_label, const TableOptions& opt = {});

/// The layout of `text` without its data: delimiter, has_header, header,
/// total_columns, first_data_line and bytes are filled; the selection and the
/// data stay empty. Lets a caller choose columns by header name (e.g. find a
/// time column) before parsing the same text with parse_table().
Table parse_layout(std::string_view text, const std::string& file_label, const TableOptions& opt = {});

/// The columns `opt` asks for (and its extra columns) out of a table that
/// holds every column of a file in order (data[i] is field i, as a binary
/// reader returns it), resolved by the same rules as parse_table.
Table select_columns(Table all, const TableOptions& opt);

/// A place in a file, for messages.
struct Location {
  std::size_t line = 0;    ///< 1-based physical line in the (decompressed) file
  std::size_t column = 0;  ///< 1-based character column where the field starts
};

/// Where data row `row`, field `field` (0-based index into the file's fields)
/// sits in the file (for a binary table: the 1-based row and column; for
/// the standard input, which cannot be read again: nowhere, {0, 0}).
/// Re-reads the file: meant for error paths only, e.g. a non-monotonic time
/// stamp found after parsing.
Location locate(const Table& t, std::size_t row, std::size_t field);

}  // namespace cubecal::io
