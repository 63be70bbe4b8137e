/// @file
/// How long to record: the precision each noise term of a sensor model will
/// have from a static record of a given length, and the length a target
/// precision needs (`cubecal plan`; docs/formulas/planning.md).
///
/// The plan is the analysis of the record the model would give, made on the
/// model's own Allan curve: at each tau of the analysis grid the deviation is
/// the model's, its noise type the model's local slope there, its EDF
/// Greenhall's for that type, factor and record length, its interval the
/// chi-squared one at the plan's confidence. The terms are read from that
/// curve exactly as `analyze` reads them from a measured one
/// (reported_terms.hpp), so a term is planned where `analyze` would report it
/// and with the uncertainty `analyze` would state. The spread of bias
/// instability B and of the tau of the minimum T over records is the spread
/// of the minimum of a noisy curve, derived in docs/formulas/planning.md §3.
///
/// Precision: the relative half-width of a term's interval at the plan's
/// confidence (0.10: +-10 %); at 0.683 it is the relative 1-sigma.
#pragma once
#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {

/// The terms a plan speaks of: IEEE 952's five and T, the tau of the Allan curve's minimum (s).
enum class PlanTerm { Q, N, B, K, R, T };
/// "Q", "N", "B", "K", "R", "T". Throws nothing.
std::string_view to_string(PlanTerm t) noexcept;
/// The term named `name` (one letter, either case); nullopt for another. Throws nothing.
std::optional<PlanTerm> plan_term_from_name(std::string_view name) noexcept;

/// One target: a term and the precision asked of it (relative half-width at the plan's confidence, 0 < p < 1).
struct PlanTarget {
  /// The term.
  PlanTerm term = PlanTerm::N;
  /// The relative half-width asked (0.10: +-10 %).
  double precision = 0.0;
};

/// "B:10%,N:1%,K:20%,T:30%" (a percent sign, or a fraction "B:0.1"). Throws
/// UsageError(Field::target) naming the bad item and what a target looks like.
std::vector<PlanTarget> parse_plan_targets(std::string_view spec);

/// A sensor channel's noise as the plan needs it: its Allan variance at every averaging factor of its sample period.
struct PlanModel {
  /// The sample period (s).
  double dt = 0.0;
  /// The Allan variance at tau = m dt (u^2, u the data unit), for m >= 1;
  /// exact for the sampled process where the model allows.
  std::function<double(std::size_t m)> avar;
};

/// IEEE 952 terms of a datasheet or of a running record's read-offs (data unit u and s; 0: absent):
/// sigma^2(tau) = 3 Q^2 / tau^2 + N^2 / tau + (0.664 B)^2 + K^2 tau / 3 + R^2 tau^2 / 2.
struct PlanTerms {
  double Q = 0.0;  ///< angle quantization, u s
  double N = 0.0;  ///< white noise, u sqrt(s)
  double B = 0.0;  ///< bias instability (flicker floor), u
  double K = 0.0;  ///< rate random walk, u / sqrt(s)
  double R = 0.0;  ///< rate ramp, u / s
};
/// The model of those terms sampled every dt (s). Throws std::invalid_argument for dt not positive or a term negative
/// or not finite.
PlanModel plan_model(const PlanTerms& terms, double dt);

/// How a plan is made.
struct PlanOptions {
  /// Confidence of every interval and precision (0.683: 1 sigma).
  double ci = 0.683;
  /// The tau grid of the analysis the plan stands for (`analyze`'s default, log:10).
  TauGrid grid{TauGrid::Kind::log, 10, {}};
  /// The longest record a plan considers (s); a target that needs more is unreachable.
  double max_duration_s = 10.0 * 365.25 * 86400.0;
};

/// Why a term has no precision at a record length, or a target no length.
enum class PlanReason {
  none,              ///< the term is planned
  not_in_model,      ///< the model's curve never shows the term, at any length (K with no random walk)
  not_resolved,      ///< the term is in the model but this record is too short to show it
  rate_too_low,      ///< the sample rate cannot resolve the term (its region lies below the first tau)
  finer_than_model,  ///< the precision asked is finer than any length gives (T against the tau grid's step)
  too_long,          ///< the target needs more than PlanOptions::max_duration_s
};
/// A short name: "", "not in model", "not resolved", "rate too low", "finer than model", "too long". Throws nothing.
std::string_view to_string(PlanReason r) noexcept;

/// One term's plan at one record length.
struct TermPrecision {
  /// The term.
  PlanTerm term = PlanTerm::N;
  /// The term's value as `analyze` would read it from the record (its unit: Q u s, N u sqrt(s), B u, K u/sqrt(s), R
  /// u/s, T s); NaN when not resolved.
  double value = 0.0;
  /// Relative half-width of its interval at PlanOptions::ci; NaN when not resolved.
  double precision = 0.0;
  /// The taus it is read from (s).
  double tau_lo = 0.0;
  /// Upper end of those taus (s).
  double tau_hi = 0.0;
  /// none when planned; else why not.
  PlanReason reason = PlanReason::none;
  /// One sentence for the user when reason is not none ("the model has no rate random walk: its curve never rises
  /// at slope +1/2"); empty otherwise.
  std::string why;
};

/// The precision of each of `terms` from a record of `duration_s` seconds of
/// the model. Throws std::invalid_argument for a duration shorter than three
/// sample periods or a model without avar, and UsageError(Field::ci) for a
/// confidence outside (0, 1).
std::vector<TermPrecision> plan_precision(const PlanModel& model, double duration_s, std::span<const PlanTerm> terms,
                                          const PlanOptions& options = {});

/// K's relative 1-sigma over records whose Allan variance is sum_k c[k + 2] tau^k (the five-term model,
/// noise_terms.hpp) and whose curve is analysed at the taus, factors and length of `curve` (its m and terms; an OADEV
/// curve): the five-term fit of the model's own curve (the EDF of each point Greenhall's for the model's local slope),
/// its K's sigma with the flicker coefficient bound and with it free, in root mean square (docs/formulas/planning.md
/// §1.2). What `analyze` states for a K the fit measures, and what the plan plans. NaN when that curve shows no K or
/// `curve` lacks its factors. Throws nothing beyond std::bad_alloc.
double planned_random_walk_sigma(const AllanCurve& curve, const std::array<double, 5>& c);

/// One target's plan: the shortest record that meets it.
struct TargetPlan {
  /// The target.
  PlanTarget target;
  /// The record length that meets it (s); NaN when unreachable.
  double duration_s = 0.0;
  /// The term at that length (its precision at most the target's); at
  /// max_duration_s when unreachable, with reason and why saying why.
  TermPrecision at;
};

/// The shortest record length (to 2 %) whose plan_precision
/// meets each target. Throws as plan_precision.
std::vector<TargetPlan> plan_duration(const PlanModel& model, std::span<const PlanTarget> targets,
                                      const PlanOptions& options = {});

}  // namespace cubecal
