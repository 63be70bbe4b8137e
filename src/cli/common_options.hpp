// Input options shared by every subcommand that reads a record.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::cli {

struct InputOptions {
  std::string file;
  std::vector<std::string> files;  // commands that take several records (turnon, compare)
  std::string columns;             // "gx,gy,gz" or "2,3,4"
  std::string time_col;
  double rate_hz = 0.0;
  std::size_t skip_rows = 0;
  std::string lsb;  // "131" or "131,131,131,16384,16384,16384"; empty: 1
  std::string gaps = "error";
  bool missing_samples = false;  // the command takes --gaps skip (dev, davar)
  unsigned threads = 0;
  std::vector<std::string> topics;  // ROS bags: --topic (repeatable)
  std::string dataset;              // HDF5: --dataset PATH
  std::string binary;               // raw binary frame: "int16le,int16le,float32le"
  std::size_t header_bytes = 0;     // skipped before the first frame (--binary only)
};

// Registers FILE (or FILE... when `several`) and the reader options.
void add_input_options(CLI::App& app, InputOptions& opt, bool several = false);

// --lsb: one positive number, or one per selected column; throws UsageError.
std::vector<double> parse_lsb_list(const std::string& list);

// Validated reader options; throws UsageError on contradictions.
io::SeriesOptions to_series_options(const InputOptions& opt);

std::vector<std::string> split_list(const std::string& s);

// CLI11 checks of numeric options with a message a user can act on
// ("--drift-window: -5 is not a positive number").
CLI::Validator positive_number();                     // finite, > 0
CLI::Validator number_between(double lo, double hi);  // finite, lo <= x <= hi
CLI::Validator whole_number(double lo, double hi);    // an integer, lo <= n <= hi (no sign wrap)

// Says on stderr which columns were taken when none were named and some were
// left out (time, temperature), so a default never silently picks a channel.
void note_default_columns(const io::Series& s);

// "deg/s,mGauss" -> units; throws UsageError naming the unknown one.
std::vector<Unit> parse_units(const std::string& list);
// Help text of --unit for the commands that infer it.
std::string unit_option_help();
// The units of the channels of `s`: parse_units(unit_option) when given,
// else the units the column names announce (unit_from_column_name), with a
// note saying which (for standard error, after any other note on the
// columns); a column whose name announces none is a UsageError
// naming it and the known units (never a silent "counts").
struct ChannelUnits {
  std::vector<Unit> units;
  std::string note;  // empty when --unit was given
};
ChannelUnits units_for(const std::string& unit_option, const io::Series& s);
// --taus value; throws UsageError.
TauGrid parse_taus(const std::string& spec);

}  // namespace cubecal::cli
