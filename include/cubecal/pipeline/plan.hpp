/// @file
/// `cubecal plan` as a library call: from sensor models (a preset, an
/// `analyze` result, a `cubecal model` result or datasheet terms) and
/// targets, the record length each noise term of each channel needs, or the
/// precision each term has from a record of a given length, with the
/// precision-against-length curve of each term (noise/record_plan.hpp does
/// the numbers; docs/formulas/planning.md derives them).
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/noise/record_plan.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/sim/simulator.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal::pipeline {

/// A sensor's noise as its datasheet gives it: "N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth".
struct Datasheet {
  /// The text as given.
  std::string text;
  /// The data unit the terms are converted to: deg/s for a rate sensor, the
  /// first field or acceleration unit of the text for the others (counts
  /// for counts).
  Unit unit;
  /// The terms in that unit and seconds (record_plan.hpp's PlanTerms; 0: not given).
  PlanTerms terms;
};

/// Parses TERM=VALUE UNIT items separated by commas (TERM one of Q, N, B, K,
/// R). A unit is a quantity (deg, rad, dps, dph, mGauss, uT, nT, G, g, mg,
/// ug, m, counts, ...) divided or multiplied by times (s, min, h, Hz, each
/// under sqrt(...), rt..., √ or with a power ^2, ^1.5): "deg/rth",
/// "deg/s/sqrt(Hz)", "deg/h", "deg/h/sqrt(h)", "mGauss*sqrt(h)",
/// "uT/rtHz", "m/s/sqrt(h)", "ug". Throws UsageError(Field::datasheet)
/// naming the item for an unknown term or unit, a unit that is not one of
/// that term (deg/h for N), a negative value, a term given twice, or terms of
/// two kinds of sensor (deg and uT).
Datasheet parse_datasheet(std::string_view text);

/// Where a plan's sensor models come from.
enum class PlanSource {
  none,         ///< not set yet
  preset,       ///< a preset of sim/presets.hpp
  twin,         ///< an analysis.json's twins (each channel's composite model)
  random_walk,  ///< an analysis.json's random-walk model (the paper's), when it holds no twin
  model,        ///< a `cubecal model` result's composite models
  datasheet,    ///< datasheet terms
};
/// "", "preset", "twin", "random-walk", "model", "datasheet". Throws nothing.
std::string_view to_string(PlanSource s) noexcept;

/// What `cubecal plan` is asked: the sensor and what to plan.
struct PlanRequest {
  /// Where the models come from (set by one of the set_plan_* functions).
  PlanSource source = PlanSource::none;
  /// The presets' names, the file's path or the datasheet's text.
  std::string source_name;
  /// What the source gave, in words ("the twin of each channel", "the
  /// random-walk model: the analysis holds no twin (...)"); empty: nothing to say.
  std::string source_note;
  /// The sensors: each named axis of each triad is one channel (source preset, twin, random_walk, model).
  std::vector<TriadModel> triads;
  /// The datasheet's terms (source datasheet): one channel.
  std::optional<Datasheet> datasheet;
  /// The sampling rate the models are planned at (Hz).
  double rate_hz = 0.0;
  /// The targets; empty with no duration: default_plan_targets() and default_plan_duration_s.
  std::vector<PlanTarget> targets;
  /// A record length (s) whose precision is asked; none with targets only.
  std::optional<double> duration_s;
  /// The confidence of every precision (0.683: 1 sigma).
  double ci = 0.683;
  /// The tau grid of the analysis the plan stands for.
  TauGrid grid{TauGrid::Kind::log, 10, {}};
  /// Record lengths of each term's precision curve (for the plot).
  std::size_t curve_points = 40;
  /// Throws UsageError naming the field at fault: no model source, no
  /// channel, a rate that is not positive, a confidence outside (0, 1), a
  /// duration that is not positive, a target's precision outside (0, 1), the
  /// same term targeted twice, or fewer than 2 curve points.
  void validate() const;
};

/// The presets named `names` (sim/presets.hpp) as the request's source, at
/// `rate_hz` (kPresetRateHz when none; model_at_rate keeps N and K). Throws
/// UsageError(Field::model) for an unknown preset or a source already set,
/// UsageError(Field::rate) for a rate that is not positive.
void set_plan_presets(PlanRequest& r, const std::vector<std::string>& names, std::optional<double> rate_hz);

/// An analysis as the request's source: its twins (composite models) when
/// every channel has one, else its random-walk model, said in source_note;
/// at `rate_hz` (the analysis's rate when none). `label` names it in
/// messages. Throws UsageError as models_from_composite and models_from_analysis do.
void set_plan_analysis(PlanRequest& r, const AnalysisResult& analysis, const std::string& label,
                       std::optional<double> rate_hz);

/// A `cubecal model` result as the request's source (its composite models), at `rate_hz` (the fit's rate when none).
/// Throws UsageError as models_from_composite does.
void set_plan_model_result(PlanRequest& r, const ModelResult& model, const std::string& label,
                           std::optional<double> rate_hz);

/// The file at `path` as the request's source: an analysis.json
/// (set_plan_analysis) or the JSON of `cubecal model --format json`
/// (set_plan_model_result). Throws UsageError(Field::model) for a file that
/// cannot be read, and what the readers throw for a damaged one.
void set_plan_model_file(PlanRequest& r, const std::string& path, std::optional<double> rate_hz);

/// Datasheet terms (parse_datasheet) as the request's source, at `rate_hz`,
/// which a datasheet needs: UsageError(Field::rate) without it.
void set_plan_datasheet(PlanRequest& r, std::string_view text, std::optional<double> rate_hz);

/// The targets planned when neither targets nor a duration are asked: B:10%,N:1%,K:20%,T:30%.
std::vector<PlanTarget> default_plan_targets();
/// The record length whose precision is planned when neither targets nor a duration are asked: the paper's 72 h.
inline constexpr double kDefaultPlanDurationS = 72.0 * 3600.0;

/// One row of a plan: a channel's term, with the length its target needs or
/// its precision at the asked length.
struct PlanRow {
  /// The term, its value, precision (at `duration_s`), taus and reason.
  TermPrecision at;
  /// The precision asked (a target's row); none for the precision at the asked duration.
  std::optional<double> target;
  /// The record length (s): the shortest that meets the target (NaN when
  /// unreachable), or the asked duration.
  double duration_s = 0.0;
  /// The term's value in the unit quoted for the sensor (units.hpp's display; T in s); NaN when not resolved.
  Quantity display;
};

/// A term's precision against record length, for the plot.
struct PlanCurve {
  /// The term.
  PlanTerm term = PlanTerm::N;
  /// Record lengths (s), ascending, log-spaced.
  std::vector<double> duration_s;
  /// The precision at each (relative half-width at the plan's ci); NaN where the term is not resolved.
  std::vector<double> precision;
};

/// One channel's plan.
struct PlanChannel {
  /// Its name (the axis name, or "datasheet").
  std::string name;
  /// Its data unit.
  Unit unit;
  /// One row per target, in the targets' order.
  std::vector<PlanRow> targets;
  /// One row per term at the asked duration.
  std::vector<PlanRow> at_duration;
  /// One curve per term planned.
  std::vector<PlanCurve> curves;
};

/// What `cubecal plan` answers.
struct PlanResult {
  /// The request's source, its name and note.
  PlanSource source = PlanSource::none;
  /// The presets' names, the file's path or the datasheet's text.
  std::string source_name;
  /// What the source gave, in words.
  std::string source_note;
  /// The sampling rate planned at (Hz).
  double rate_hz = 0.0;
  /// The confidence of the precisions.
  double ci = 0.683;
  /// True when neither targets nor a duration were asked (the defaults were planned).
  bool defaults = false;
  /// The targets planned.
  std::vector<PlanTarget> targets;
  /// The duration planned (s), if any.
  std::optional<double> duration_s;
  /// The channels' plans, in the models' order.
  std::vector<PlanChannel> channels;
};

/// Plans every channel of the request (validate() first). Throws what
/// validate(), plan_precision and plan_duration throw.
PlanResult run_plan(const PlanRequest& request);

/// The terms of `r`'s rows and curves: the targets' terms, else N, B, K, T. Throws nothing beyond std::bad_alloc.
std::vector<PlanTerm> planned_terms(const PlanResult& r);

/// A record length as people say it: "50 s", "12 min", "3 h 20 min", "72 h" (hours below 100 h), "4.2 d",
/// "1.3 years"; "-" for NaN. Throws nothing beyond std::bad_alloc.
std::string duration_words(double seconds);

/// A precision as a percentage: "10 %", "1.5 %", "0.25 %"; "-" for NaN. Throws nothing beyond std::bad_alloc.
std::string percent_words(double precision);

}  // namespace cubecal::pipeline
