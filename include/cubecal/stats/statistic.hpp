/// @file
/// Vocabulary shared by the stability statistics.
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace cubecal {

/// Frequency data: rate-like samples (fractional frequency, deg/s, mGauss...).
/// Phase data: their time integral (time error in s, angle in deg...).
enum class DataType { phase, freq };

/// The Allan family (adev .. totdev), the time-interval errors (tierms, mtie),
/// the total variances of SP 1065 (mtotdev, ttotdev, htotdev) and the Theo
/// family (theo1, the bias-removed theobr, and theoh: OADEV at short taus,
/// TheoBR at long ones). docs/formulas/stability.md defines each.
enum class Stat {
  adev,
  oadev,
  mdev,
  tdev,
  hdev,
  ohdev,
  totdev,
  tierms,
  mtie,
  mtotdev,
  ttotdev,
  htotdev,
  theo1,
  theobr,
  theoh
};

/// The statistic's name: "adev", "oadev", ... Throws nothing.
std::string_view to_string(Stat s) noexcept;
/// "freq" or "phase". Throws nothing.
std::string_view to_string(DataType t) noexcept;
/// The statistic named `s` (as to_string gives it), or nullopt. Throws nothing.
std::optional<Stat> parse_stat(std::string_view s) noexcept;
/// "freq" or "phase" as a DataType, or nullopt. Throws nothing.
std::optional<DataType> parse_data_type(std::string_view s) noexcept;

/// Every statistic's name, in the order of the enum (for option lists and help).
std::span<const std::string_view> stat_names() noexcept;

/// False for the time-interval errors (TIE rms, MTIE): they have no noise
/// identification, no EDF and no confidence interval.
bool has_intervals(Stat s) noexcept;

/// The tau of averaging factor m is m * tau_per_factor(s) * tau0: 0.75 for the
/// Theo family (Theo1 at m spans 0.75 m tau0), 1 for the others.
double tau_per_factor(Stat s) noexcept;

/// Whether the statistic is defined at averaging factor m (the Theo family
/// takes even m only; TheoH, whose factors depend on the record, any m here:
/// see theoh_stat_at).
bool factor_allowed(Stat s, std::size_t m) noexcept;

/// TheoH (Howe & Tasset 2006; SP 1065 sec. 5.2.16) on N phase points: AVAR
/// (overlapping) at 1 <= m < k/tau0 with tau = m tau0, TheoBR at even
/// m >= k/(0.75 tau0) with tau = 0.75 m tau0 (Stable32's convention), k the
/// largest tau <= 20 % of the record T = (N - 1) tau0. theoh_switch_factor
/// is k/tau0 = floor((N - 1) / 5); theoh_first_theo_factor the smallest even
/// m with 0.75 m >= k/tau0. Factors in between are not defined.
std::size_t theoh_switch_factor(std::size_t n_phase) noexcept;
/// The smallest even m with 0.75 m >= theoh_switch_factor(n_phase). Throws nothing.
std::size_t theoh_first_theo_factor(std::size_t n_phase) noexcept;

/// The statistic TheoH evaluates at factor m on n_phase points: oadev below
/// the switch, theobr from the first Theo factor on (even m), nullopt in
/// between or at an odd m beyond. Any other statistic: itself.
std::optional<Stat> theoh_stat_at(Stat s, std::size_t m, std::size_t n_phase) noexcept;

/// tau_per_factor at factor m of a record of n_phase points: TheoH's 1 or
/// 0.75 by the part m falls in, tau_per_factor(s) otherwise.
double tau_per_factor(Stat s, std::size_t m, std::size_t n_phase) noexcept;

/// Order of the finite difference of phase behind a statistic: 2 for the Allan
/// family (AVAR, MVAR, TVAR, TOTVAR, MTOT, TTOT, the Theo family), 3 for the
/// Hadamard family (HVAR, OHVAR, HTOT), 1 for TIE rms and MTIE.
int difference_order(Stat s) noexcept;

/// The lowest power-law noise type (alpha of S_y(f) ~ f^alpha) a statistic
/// converges for, and so has an EDF and an interval for: -2 (random-walk FM)
/// for the Allan family and the total and Theo statistics, -4 (random-run FM)
/// for the Hadamard family; 2 - 2 * difference_order(s).
int lowest_alpha(Stat s) noexcept;

/// Refuses a given noise type (`--alpha`) that the statistic cannot take:
/// below lowest_alpha(s) or above +2 (white PM). Throws UsageError naming
/// Field::alpha; nothing when `alpha` is empty.
void check_noise_type(Stat s, std::optional<int> alpha);

/// Largest averaging factor Stable32 evaluates for a statistic on N phase
/// points (N-1 frequency points): (N-1)/5 for ADEV and HDEV, (N-1)/4 for the
/// overlapping and modified statistics and TIE rms, (N-1)/3 for MTOT, TTOT and
/// HTOT, (N-1)/2 for TOTDEV, N-1 for MTIE and the Theo family (TheoH
/// included; whose largest factor is then the largest even one).
std::size_t max_averaging_factor(Stat s, std::size_t n_phase) noexcept;

/// Phase points per averaging factor in that limit: max_averaging_factor(s, N)
/// >= m exactly when N >= points_per_factor(s) * m + 1 (5 for ADEV and HDEV,
/// 4 for the overlapping and modified statistics and TIE rms, 3 for the
/// modified and Hadamard totals, 2 for TOTDEV, 1 for MTIE and the Theo family).
std::size_t points_per_factor(Stat s) noexcept;

}  // namespace cubecal
