#include "cubecal/pipeline/simulate_size.hpp"

#include <cmath>

namespace cubecal::pipeline {

double estimated_text_bytes(const SimulateRequest& r) {
  const double rows = r.duration_s * r.rate_hz;
  if (!(rows >= 0.5)) return 0.0;  // also NaN
  const auto names = channel_names(r);
  double header = 2.0;  // "t" and the newline
  for (const auto& n : names) header += static_cast<double>(n.size()) + 1.0;
  return header + std::round(rows) * static_cast<double>(names.size() + 1) * kTextBytesPerValue;
}

}  // namespace cubecal::pipeline
