/// @file
/// The size of what `simulate` writes, known before any work: a face can
/// refuse a record no one meant to ask for (--duration 72d at 1 kHz is ~60 GB
/// of text) before the disk fills.
#pragma once
#include "cubecal/pipeline/simulate.hpp"

namespace cubecal::pipeline {

/// Bytes of text write_simulation writes for `r`: rate x duration rows of the
/// time column and every channel, 12 bytes a value (nine significant digits,
/// sign, point and separator; an exponent is rarer than the shorter values),
/// plus the header. In floating point, so an absurd duration gives a large
/// number and not an overflow; 0 for a request with no samples.
double estimated_text_bytes(const SimulateRequest& r);

/// Bytes of text per value assumed by estimated_text_bytes.
inline constexpr double kTextBytesPerValue = 12.0;

}  // namespace cubecal::pipeline
