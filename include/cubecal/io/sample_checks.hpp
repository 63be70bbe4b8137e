/// @file
/// The readers' checks on a record a face holds in memory (the arrays of a
/// Python call): the same rate range and value magnitudes as a file, so that
/// what the CLI refuses in a file is refused in an array, never turned into a
/// NaN deviation.
#pragma once
#include <cstddef>
#include <span>
#include <string>

namespace cubecal::io {

/// Refuses a sampling rate that is not a finite number in [kMinRateHz,
/// kMaxRateHz] (io/series.hpp) with UsageError(Field::rate): the rule a
/// reader applies to a rate given for a file ("the sampling rate 1e+300 Hz is
/// outside the range 1e-09 to 1e+09 Hz").
void check_rate(double rate_hz);

/// Checks the samples of one channel held in memory as a reader checks a
/// column of a file: InputError(label, i + 1, column) at the first value that
/// is NaN or infinite (with `missing`, a NaN is a missing sample and only an
/// infinity is refused) or whose magnitude exceeds kMaxMagnitude, or at the
/// largest value of the channel when it is non-zero and below kMinMagnitude
/// (subnormal values, whose squares underflow). `name` is the channel's name
/// in the message.
void check_samples(std::span<const double> v, const std::string& label, std::size_t column, const std::string& name,
                   bool missing = false);

}  // namespace cubecal::io
