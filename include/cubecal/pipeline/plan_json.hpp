/// @file
/// The JSON forms of a `cubecal plan` result. `plan --format json` prints
/// to_json: a list of rows, one per channel and term, {channel, term, kind
/// ("target": the length a target needs; "duration": the precision at the
/// asked length), precision (the target, or the precision at the length;
/// null when the term is not resolved), duration_s (the length that meets
/// the target, null when none does; or the asked length), achieved (the
/// precision at duration_s), value and unit (the term in the unit quoted for
/// the sensor; T in s), tau_lo, tau_hi (s), reason (null when planned, else
/// "not in model", "not resolved", "rate too low", "finer than model",
/// "too long") and why (a sentence, null when planned)}. plan_document is
/// the whole result (Python's cubecal.plan): {command: "plan", source,
/// source_name, source_note, rate_hz, ci, defaults, targets [{term,
/// precision}], duration_s, channels [{name, unit}], rows [as above],
/// curves [{channel, term, duration_s [], precision []}]}.
#pragma once
#include <nlohmann/json.hpp>

#include "cubecal/pipeline/plan.hpp"

namespace cubecal::pipeline {

/// `cubecal plan --format json`: the rows. Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const PlanResult& r);

/// The whole result: source, options, rows and curves. Throws nothing beyond std::bad_alloc.
nlohmann::json plan_document(const PlanResult& r);

}  // namespace cubecal::pipeline
