// Vocabulary shared by the stability statistics.
#pragma once
#include <cstddef>
#include <optional>
#include <string_view>

namespace cubecal {

// Frequency data: rate-like samples (fractional frequency, deg/s, mGauss...).
// Phase data: their time integral (time error in s, angle in deg...).
enum class DataType { phase, freq };

enum class Stat { adev, oadev, mdev, tdev, hdev, ohdev, totdev };

std::string_view to_string(Stat s) noexcept;
std::string_view to_string(DataType t) noexcept;
std::optional<Stat> parse_stat(std::string_view s) noexcept;
std::optional<DataType> parse_data_type(std::string_view s) noexcept;

// Order of the finite difference of phase behind a statistic: 2 for the Allan
// family (AVAR, MVAR, TVAR, TOTVAR), 3 for the Hadamard family.
int difference_order(Stat s) noexcept;

// Largest averaging factor Stable32 evaluates for a statistic on N phase
// points (N-1 frequency points): (N-1)/5 for ADEV and HDEV, (N-1)/4 for the
// overlapping and modified statistics, (N-1)/2 for TOTDEV.
std::size_t max_averaging_factor(Stat s, std::size_t n_phase) noexcept;

// Phase points per averaging factor in that limit: max_averaging_factor(s, N)
// >= m exactly when N >= points_per_factor(s) * m + 1 (5 for ADEV and HDEV,
// 4 for the overlapping and modified statistics, 2 for TOTDEV).
std::size_t points_per_factor(Stat s) noexcept;

}  // namespace cubecal
