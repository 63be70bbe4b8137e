#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "cubecal/stats/statistic.hpp"

#include "cubecal/error.hpp"

namespace cubecal {

namespace {
constexpr std::array<std::pair<Stat, std::string_view>, 15> kStatNames{{
    {Stat::adev, "adev"},
    {Stat::oadev, "oadev"},
    {Stat::mdev, "mdev"},
    {Stat::tdev, "tdev"},
    {Stat::hdev, "hdev"},
    {Stat::ohdev, "ohdev"},
    {Stat::totdev, "totdev"},
    {Stat::tierms, "tierms"},
    {Stat::mtie, "mtie"},
    {Stat::mtotdev, "mtotdev"},
    {Stat::ttotdev, "ttotdev"},
    {Stat::htotdev, "htotdev"},
    {Stat::theo1, "theo1"},
    {Stat::theobr, "theobr"},
    {Stat::theoh, "theoh"},
}};

constexpr std::array<std::string_view, kStatNames.size()> kNames = [] {
  std::array<std::string_view, kStatNames.size()> a{};
  for (std::size_t i = 0; i < kStatNames.size(); ++i) a[i] = kStatNames[i].second;
  return a;
}();

bool theo_family(Stat s) noexcept { return s == Stat::theo1 || s == Stat::theobr; }
bool theo_limits(Stat s) noexcept { return theo_family(s) || s == Stat::theoh; }
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

std::span<const std::string_view> stat_names() noexcept { return kNames; }

bool has_intervals(Stat s) noexcept { return s != Stat::tierms && s != Stat::mtie; }

double tau_per_factor(Stat s) noexcept { return theo_family(s) ? 0.75 : 1.0; }

bool factor_allowed(Stat s, std::size_t m) noexcept {
  if (m == 0) return false;
  return !theo_family(s) || m % 2 == 0;
}

int difference_order(Stat s) noexcept {
  switch (s) {
    case Stat::hdev:
    case Stat::ohdev:
    case Stat::htotdev: return 3;
    case Stat::tierms:
    case Stat::mtie: return 1;
    default: return 2;
  }
}

int lowest_alpha(Stat s) noexcept { return 2 - 2 * difference_order(s); }

void check_noise_type(Stat s, std::optional<int> alpha) {
  if (!alpha || (*alpha >= lowest_alpha(s) && *alpha <= 2)) return;
  throw UsageError(Field::alpha,
                   "{alpha} " + std::to_string(*alpha) + ": a noise type " + std::string(to_string(s)) +
                       " does not converge for (it takes " + std::to_string(lowest_alpha(s)) +
                       " to +2; -3 and -4 are for the Hadamard family: hdev, ohdev, htotdev)",
                   UsageError::Named::in_text);
}

std::size_t theoh_switch_factor(std::size_t n_phase) noexcept { return n_phase < 2 ? 0 : (n_phase - 1) / 5; }

std::size_t theoh_first_theo_factor(std::size_t n_phase) noexcept {
  const std::size_t k = theoh_switch_factor(n_phase);
  std::size_t m = (4 * k + 2) / 3;  // ceil(4k / 3): 0.75 m >= k
  m += m % 2;
  return std::max<std::size_t>(m, 2);
}

std::optional<Stat> theoh_stat_at(Stat s, std::size_t m, std::size_t n_phase) noexcept {
  if (s != Stat::theoh) return s;
  if (m >= 1 && m < theoh_switch_factor(n_phase)) return Stat::oadev;
  if (m >= theoh_first_theo_factor(n_phase) && m % 2 == 0) return Stat::theobr;
  return std::nullopt;
}

double tau_per_factor(Stat s, std::size_t m, std::size_t n_phase) noexcept {
  if (s != Stat::theoh) return tau_per_factor(s);
  return m < theoh_switch_factor(n_phase) ? 1.0 : 0.75;
}

std::size_t points_per_factor(Stat s) noexcept {
  switch (s) {
    case Stat::adev:
    case Stat::hdev: return 5;
    case Stat::oadev:
    case Stat::mdev:
    case Stat::tdev:
    case Stat::ohdev:
    case Stat::tierms: return 4;
    case Stat::mtotdev:
    case Stat::ttotdev:
    case Stat::htotdev: return 3;
    case Stat::totdev: return 2;
    case Stat::mtie:
    case Stat::theo1:
    case Stat::theobr:
    case Stat::theoh: return 1;
  }
  return 5;
}

std::size_t max_averaging_factor(Stat s, std::size_t n_phase) noexcept {
  if (n_phase < 2) return 0;
  std::size_t m = (n_phase - 1) / points_per_factor(s);  // over the N - 1 frequency points
  if (theo_limits(s)) m -= m % 2;
  return m;
}

}  // namespace cubecal
