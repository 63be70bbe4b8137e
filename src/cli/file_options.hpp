// Per-file reader options of the commands that take several records
// (compare, turnon): FILE:key=value,key=value,... so that runs of different
// layouts (preamble, columns, rate, scale, unit) are read in one command.
#pragma once
#include <string>
#include <vector>

#include "common_options.hpp"

namespace cubecal::cli {

// One record argument with the options it is read with.
struct FileSpec {
  std::string path;
  InputOptions input;     // the command's reader options, overridden by the file's own
  std::string unit;       // the command's --unit, or the file's unit=
  bool own_unit = false;  // unit= given for this file
};

// The keys a file may carry: rate, skip-rows (or skip), columns, time-col,
// lsb, unit, gaps.
std::string file_option_keys();

// Splits `arg` into the path and its options: the text after the last ':'
// is options only when it reads as key=value pairs with a known first key
// (so "C:\data.csv", "run:3.csv" and "a:b" are paths), and never when `arg`
// names an existing file. A value may be a comma list ("columns=gx,gy,lsb=
// 131,131"): an item without '=' continues the previous key. Throws
// UsageError naming an unknown key, a key given twice, or a bad value.
FileSpec parse_file_spec(const std::string& arg, const InputOptions& defaults, const std::string& unit);

}  // namespace cubecal::cli
