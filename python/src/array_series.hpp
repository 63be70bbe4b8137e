// A record held in NumPy arrays as the library's io::Series, checked as the
// readers check a file: one contiguous segment, every value finite (a NaN or
// infinity is an InputError at line = sample + 1, column = channel + 1, of
// the record's label), channels of one length.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "common.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::python {

// `temperature`, when given, becomes the record's one extra column, named
// temp_name. UsageError for a rate outside the readers' range, no channel,
// channels or a temperature of another length, or fewer than 3 samples.
io::Series array_series(const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
                        const std::optional<Doubles>& temperature, const std::string& temp_name,
                        const std::string& label);

// The record of a call that takes a file or arrays (psd, davar, model): the
// file at `path` when given (read as `read` says, without its time stamps),
// else the arrays. `missing_samples`: the call takes gaps="skip".
io::Series call_record(const std::optional<std::string>& path, const ReadArgs& read,
                       const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
                       bool missing_samples = false);

}  // namespace cubecal::python
