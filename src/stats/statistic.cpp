#include <array>
#include <utility>

#include "cubecal/stats/statistic.hpp"

namespace cubecal {

namespace {
constexpr std::array<std::pair<Stat, std::string_view>, 7> kStatNames{{
    {Stat::adev, "adev"},
    {Stat::oadev, "oadev"},
    {Stat::mdev, "mdev"},
    {Stat::tdev, "tdev"},
    {Stat::hdev, "hdev"},
    {Stat::ohdev, "ohdev"},
    {Stat::totdev, "totdev"},
}};
}  // namespace

std::string_view to_string(Stat s) noexcept {
  for (const auto& [k, v] : kStatNames)
    if (k == s) return v;
  return "?";
}

std::string_view to_string(DataType t) noexcept { return t == DataType::phase ? "phase" : "freq"; }

std::optional<Stat> parse_stat(std::string_view s) noexcept {
  for (const auto& [k, v] : kStatNames)
    if (v == s) return k;
  return std::nullopt;
}

std::optional<DataType> parse_data_type(std::string_view s) noexcept {
  if (s == "phase") return DataType::phase;
  if (s == "freq" || s == "frequency") return DataType::freq;
  return std::nullopt;
}

int difference_order(Stat s) noexcept {
  return (s == Stat::hdev || s == Stat::ohdev) ? 3 : 2;
}

std::size_t points_per_factor(Stat s) noexcept {
  switch (s) {
    case Stat::adev:
    case Stat::hdev:
      return 5;
    case Stat::oadev:
    case Stat::mdev:
    case Stat::tdev:
    case Stat::ohdev:
      return 4;
    case Stat::totdev:
      return 2;
  }
  return 5;
}

std::size_t max_averaging_factor(Stat s, std::size_t n_phase) noexcept {
  if (n_phase < 2) return 0;
  return (n_phase - 1) / points_per_factor(s);  // over the N - 1 frequency points
}

}  // namespace cubecal
