// A Matrix (math/matrix.hpp) in the pipeline's JSON: an array of rows,
// [[row 0], [row 1], ...]; no rows is []. In the one style of the
// pipeline's JSON functions (`json to_json(const T&)`, `T x_from_json(json)`);
// the core's header stays free of nlohmann. Not an installed header.
#pragma once
#include <nlohmann/json.hpp>

#include <cstddef>
#include <stdexcept>
#include <vector>

#include "cubecal/math/matrix.hpp"

namespace cubecal::pipeline::detail {

inline nlohmann::json to_json(const Matrix& m) {
  nlohmann::json j = nlohmann::json::array();
  for (std::size_t i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (double v : m.row(i)) row.push_back(v);
    j.push_back(std::move(row));
  }
  return j;
}

// From an array of rows of equal length (std::invalid_argument for a ragged one).
inline Matrix matrix_from_json(const nlohmann::json& j) {
  const auto rows = j.get<std::vector<std::vector<double>>>();
  const std::size_t cols = rows.empty() ? 0 : rows[0].size();
  Matrix m(rows.size(), cols);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != cols) throw std::invalid_argument("matrix rows of different lengths");
    for (std::size_t k = 0; k < cols; ++k) m(i, k) = rows[i][k];
  }
  return m;
}

}  // namespace cubecal::pipeline::detail
