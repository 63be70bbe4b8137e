// Loader for the Stable32 result tables and plain data files in
// ../shared/data/stable32 (test support only).
#pragma once
#include <string>
#include <vector>

namespace cubecal::test {

struct Stable32Row {
  std::size_t af = 0;
  double tau = 0;
  std::size_t n = 0;
  int alpha = 0;
  double lo = 0, dev = 0, hi = 0;  // lo/hi are 0 in "all tau" tables
};

// Rows of a result table; rows commented out with '#' are skipped.
std::vector<Stable32Row> read_stable32(const std::string& path);

// First numeric column of a data file ('#' comments skipped).
std::vector<double> read_column(const std::string& path);

std::string shared_data(const std::string& rel);

}  // namespace cubecal::test
