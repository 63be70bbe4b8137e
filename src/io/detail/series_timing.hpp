// The timing checks of read_series, shared by every format it reads: the
// rate (given, or inferred from the time stamps), gaps and jitter, the
// segments and the minimum length. Defined in series.cpp.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::io::detail {

// The error for a problem at sample `row` of the time stamps, located as the
// format can (FILE:LINE:COL for text, a byte offset for a bag).
using PlaceError = std::function<InputError(std::size_t row, std::string problem, std::string hint)>;

// Completes `s`, whose channels are filled and scaled: with `timing`, the
// time stamps `time` (named `time_name`) give or check the rate and are
// checked for gaps and jitter (split on with GapPolicy::split); without, the
// given rate is used (and checked against `time`, when there are stamps).
// Throws InputError when the record (or its longest segment) is shorter
// than opt.min_samples.
void finish_series(Series& s, std::vector<double> time, const std::string& time_name, bool timing,
                   const SeriesOptions& opt, const PlaceError& at);

}  // namespace cubecal::io::detail
