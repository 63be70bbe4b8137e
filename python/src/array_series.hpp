// A record held in NumPy arrays as the library's io::Series, checked as the
// readers check a file: one contiguous segment, every value finite (a NaN or
// infinity is an InputError at line = sample + 1, column = channel + 1, of
// the record's label), channels of one length.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::python {

// `temperature`, when given, becomes the record's one extra column, named
// temp_name. UsageError for a rate outside the readers' range, no channel,
// channels or a temperature of another length, or fewer than 3 samples.
io::Series array_series(const std::vector<Doubles>& channels, const std::vector<std::string>& names, double rate,
                        const std::optional<Doubles>& temperature, const std::string& temp_name,
                        const std::string& label);

}  // namespace cubecal::python
