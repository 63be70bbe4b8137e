// The table of a file opened by the readers (detail/file_buffer.hpp): the
// parse of delimited_reader.hpp over a FileBuffer rather than over text.
#pragma once
#include "cubecal/io/delimited_reader.hpp"
#include "file_buffer.hpp"

namespace cubecal::io {

// As parse_table of text, from an open file (named by its path): a mapped
// file's pages are dropped behind the parse, so that the peak memory is the
// parsed columns and a few windows of text, not the whole file besides them.
Table parse_table(const FileBuffer& buf, const TableOptions& opt = {});

}  // namespace cubecal::io
