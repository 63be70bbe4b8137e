#include "stable32_table.hpp"

#include <zlib.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cubecal::test {

std::string shared_data(const std::string& rel) { return std::string(CUBECAL_SHARED_DATA) + "/" + rel; }

std::vector<Stable32Row> read_stable32(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<Stable32Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find('#') != std::string::npos || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream ss(line);
    Stable32Row r;
    if (ss >> r.af >> r.tau >> r.n >> r.alpha >> r.lo >> r.dev >> r.hi) rows.push_back(r);
  }
  return rows;
}

std::vector<double> read_column(const std::string& path) {
  // gzopen reads plain files as they are, and .gz files decompressed.
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open " + path);
  std::vector<double> v;
  std::vector<char> buf(4096);
  while (gzgets(f, buf.data(), static_cast<int>(buf.size()))) {
    if (std::strchr(buf.data(), '#')) continue;
    char* end = nullptr;
    const double x = std::strtod(buf.data(), &end);
    if (end != buf.data()) v.push_back(x);
  }
  gzclose(f);
  return v;
}

}  // namespace cubecal::test
