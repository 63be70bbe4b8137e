// record_status.hpp: the terms of a recording as its samples arrive, their
// precision against the targets and the record length still needed.
#include "cubecal/pipeline/record_status.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>

#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "detail/analysis_parts.hpp"

namespace cubecal::pipeline {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Values held per channel before they go to its pyramid.
constexpr std::size_t kPending = 4096;
// The time column's first intervals, whose median is the period.
constexpr std::size_t kPeriodIntervals = 31;

// The rate of a median interval, kept to nine significant digits as a
// record's reader keeps it (io/series.cpp).
double period_of(std::vector<double> intervals) {
  const auto mid = intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2);
  std::nth_element(intervals.begin(), mid, intervals.end());
  const double raw = 1.0 / *mid;
  if (!(raw > 0) || !std::isfinite(raw)) return 0.0;
  const double scale = std::pow(10.0, 8.0 - std::floor(std::log10(raw)));
  return 1.0 / (std::round(raw * scale) / scale);
}

// The IEEE 952 term of a plan term (T has none).
std::optional<Term> ieee_term(PlanTerm t) {
  switch (t) {
    case PlanTerm::Q: return Term::Q;
    case PlanTerm::N: return Term::N;
    case PlanTerm::B: return Term::B;
    case PlanTerm::K: return Term::K;
    case PlanTerm::R: return Term::R;
    case PlanTerm::T: return std::nullopt;
  }
  return std::nullopt;
}

// A term read from an estimate: value, 1-sigma, interval and precision at
// the confidence (z: its normal half-width).
LiveTerm resolved_term(PlanTerm which, const TermEstimate& e, std::string_view source, double z) {
  LiveTerm t;
  t.term = which;
  t.resolved = true;
  t.value = e.value;
  t.sigma = e.sigma;
  t.lo = e.value - z * e.sigma;
  t.hi = e.value + z * e.sigma;
  t.precision = e.value > 0 ? z * e.sigma / e.value : kNaN;
  t.tau_lo = e.tau_lo;
  t.tau_hi = e.tau_hi;
  t.source = std::string(source);
  return t;
}

LiveTerm unresolved_term(PlanTerm which, double value, std::string_view source, std::string why) {
  LiveTerm t;
  t.term = which;
  t.value = value;
  t.sigma = t.lo = t.hi = t.precision = kNaN;
  t.source = std::string(source);
  t.bound = source == to_string(TermSource::upper_bound);
  t.why = std::move(why);
  return t;
}

// N, K, B and T as `analyze` reports them (reported_terms.hpp).
LiveTerm reported_term(PlanTerm which, const ReportedTerms& rt, const SlopeReadOffs& ro, double z) {
  const std::string_view bound = to_string(TermSource::upper_bound);
  switch (which) {
    case PlanTerm::N:
      if (rt.N.bound())
        return unresolved_term(which, rt.N.value(), bound, "no -1/2 region in the curve: N is only bounded from above");
      return resolved_term(which, rt.N.estimate, to_string(rt.N.source), z);
    case PlanTerm::K:
      if (rt.K.bound())
        return unresolved_term(which, rt.K.value(), bound,
                               rt.K_candidate.valid
                                   ? "K not resolved yet: its estimate is within 2 sigma of zero"
                                   : "K not resolved yet: the curve does not rise at slope +1/2 within the record");
      return resolved_term(which, rt.K.estimate, to_string(rt.K.source), z);
    case PlanTerm::B:
      if (rt.no_minimum)
        return unresolved_term(which, rt.B.value(), bound,
                               "no minimum yet: B not resolved (the curve still falls at its last tau)");
      return resolved_term(which, rt.B.estimate, to_string(rt.B.source), z);
    case PlanTerm::T: {
      if (rt.no_minimum)
        return unresolved_term(which, kNaN, "",
                               "no minimum yet: T not resolved (the curve still falls at its last tau)");
      // T's uncertainty is that of ln T (the minimum's spread over
      // records): the interval is T exp(-+z s), the precision z s.
      LiveTerm t;
      t.term = which;
      t.resolved = rt.T > 0 && rt.T_rel_sigma > 0;
      t.value = rt.T > 0 ? rt.T : ro.tau_min;
      t.sigma = t.resolved ? t.value * rt.T_rel_sigma : kNaN;
      t.lo = t.resolved ? t.value * std::exp(-z * rt.T_rel_sigma) : kNaN;
      t.hi = t.resolved ? t.value * std::exp(z * rt.T_rel_sigma) : kNaN;
      t.precision = t.resolved ? z * rt.T_rel_sigma : kNaN;
      t.tau_lo = ro.tau_min_lo;
      t.tau_hi = ro.tau_min_hi;
      if (!t.resolved) t.why = "T has no uncertainty from this curve's minimum yet";
      return t;
    }
    default: return unresolved_term(which, kNaN, "", "");
  }
}

// Q and R (targets only): the read-off where the curve has their slope, as
// the plan reads them (record_plan.hpp).
LiveTerm other_term(PlanTerm which, const TermEstimate& read_off, double z) {
  if (read_off.valid && read_off.value > 0) return resolved_term(which, read_off, to_string(TermSource::read_off), z);
  return unresolved_term(which, kNaN, "",
                         which == PlanTerm::Q ? "Q not resolved: the curve has no quantization (-1) region"
                                              : "R not resolved: the curve has no rate ramp (+1) region");
}

bool is_target(const std::vector<PlanTarget>& targets, PlanTerm t) {
  return std::any_of(targets.begin(), targets.end(), [&](const PlanTarget& x) { return x.term == t; });
}

// The plan from the terms measured so far: the record length each target
// needs, and what is still needed after `record_s`.
void plan_targets(LiveChannel& ch, const std::vector<PlanTarget>& targets, double dt, double record_s, double ci) {
  const auto find = [&](PlanTerm t) -> LiveTerm* {
    for (auto& x : ch.terms)
      if (x.term == t) return &x;
    return nullptr;
  };
  // The verdicts; the plan only for the targets resolved and not yet met
  // (it is the costly part: a curve and its reading per trial length).
  std::vector<PlanTarget> open;
  for (const PlanTarget& target : targets) {
    LiveTerm* t = find(target.term);
    if (t == nullptr) continue;
    t->target = target.precision;
    t->met = t->resolved && t->precision <= target.precision;
    t->needed_s = kNaN;
    t->remaining_s = t->met ? 0.0 : kNaN;
    if (t->resolved && !t->met) open.push_back(target);  // an unresolved one: its why says what the curve lacks
  }
  if (open.empty()) return;
  PlanTerms pt;
  const LiveTerm* n = find(PlanTerm::N);
  const LiveTerm* b = find(PlanTerm::B);
  const LiveTerm* k = find(PlanTerm::K);
  pt.N = n != nullptr && std::isfinite(n->value) ? n->value : 0.0;
  pt.B = b != nullptr && b->resolved ? b->value : 0.0;
  pt.K = k != nullptr && k->resolved ? k->value : 0.0;
  std::vector<TargetPlan> plans;
  std::string failure;
  try {
    PlanOptions po;
    po.ci = ci;
    plans = plan_duration(plan_model(pt, dt), open, po);
  } catch (const Error& e) {
    failure = face_words(e.text());
  } catch (const std::exception& e) {
    failure = e.what();
  }
  for (std::size_t i = 0; i < open.size(); ++i) {
    LiveTerm* t = find(open[i].term);
    if (!failure.empty()) {
      t->why = failure;
      continue;
    }
    const TargetPlan& p = plans.at(i);
    if (std::isfinite(p.duration_s)) {
      t->needed_s = p.duration_s;
      t->remaining_s = std::max(0.0, p.duration_s - record_s);
      if (t->remaining_s == 0.0)
        t->why =
            "due now: the record is as long as the plan from the terms so far asks, the measured precision "
            "is not yet within the target";
    } else {
      t->why = (p.at.why.empty() ? std::string(to_string(p.at.reason)) : p.at.why) +
               " (the plan from the terms measured so far)";
    }
  }
}

}  // namespace

double normal_half_width(double ci) noexcept {
  if (!(ci > 0.0 && ci < 1.0)) return kNaN;
  return boost::math::quantile(boost::math::normal(), 0.5 + 0.5 * ci);
}

LiveNoiseStatus::LiveNoiseStatus(const std::vector<std::string>& columns, const std::optional<std::string>& time_column,
                                 std::optional<double> rate_hz, Unit unit, LiveStatusOptions options)
    : opt_(std::move(options)), unit_(std::move(unit)) {
  if (!(opt_.ci > 0.0 && opt_.ci < 1.0))
    throw UsageError(Field::ci, "{ci} is a confidence between 0 and 1 (0.683: 1 sigma; 0.95)",
                     UsageError::Named::in_text);
  const std::size_t wb = opt_.window_bound;
  if (wb < 16 || (wb & (wb - 1)) != 0) throw std::invalid_argument("window bound: a power of two >= 16");
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (time_column ? columns[i] == *time_column : io::looks_like_time_column(columns[i])) {
      if (time_index_ < 0) time_index_ = static_cast<int>(i);
      continue;
    }
    if (io::looks_like_temperature_column(columns[i])) continue;
    columns_.push_back(i);
    names_.push_back(columns[i]);
  }
  if (time_index_ < 0 && rate_hz && *rate_hz > 0) dt_ = 1.0 / *rate_hz;
  const DevRequest dreq = detail::oadev_request(AnalyzeRequest{});
  const std::vector<std::size_t> ms = averaging_factors(TauGrid{TauGrid::Kind::log, 10, {}}, std::size_t{1} << 50, 1.0);
  for (std::size_t c = 0; c < names_.size(); ++c) devs_.emplace_back(dreq.stat, ms, wb);
  pending_.resize(names_.size());
  broken_.resize(names_.size());
  for (auto& p : pending_) p.reserve(kPending);
}

void LiveNoiseStatus::push(std::span<const double> values) {
  if (time_index_ >= 0 && static_cast<std::size_t>(time_index_) < values.size() && dt_ == 0.0) {
    const double t = values[static_cast<std::size_t>(time_index_)];
    if (have_prev_ && t > prev_t_) intervals_.push_back(t - prev_t_);
    prev_t_ = t;
    have_prev_ = true;
    if (intervals_.size() == kPeriodIntervals) dt_ = period_of(intervals_);
  }
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (columns_[c] >= values.size()) continue;
    pending_[c].push_back(values[columns_[c]]);
    if (pending_[c].size() == kPending) flush();
  }
  ++samples_;
}

void LiveNoiseStatus::flush() {
  for (std::size_t c = 0; c < devs_.size(); ++c) {
    if (broken_[c].empty() && !pending_[c].empty()) {
      try {
        devs_[c].push(pending_[c]);
      } catch (const std::invalid_argument& e) {
        broken_[c] = std::string("the curve stopped: ") + e.what();
      }
    }
    pending_[c].clear();
  }
}

LiveChannel LiveNoiseStatus::channel_status(std::size_t c) const {
  LiveChannel ch;
  ch.name = names_[c];
  std::vector<PlanTerm> shown = {PlanTerm::N, PlanTerm::K, PlanTerm::B, PlanTerm::T};
  for (PlanTerm extra : {PlanTerm::Q, PlanTerm::R})
    if (is_target(opt_.targets, extra)) shown.push_back(extra);
  const auto none = [&](const std::string& why) {
    ch.why = why;
    for (PlanTerm t : shown) ch.terms.push_back(unresolved_term(t, kNaN, "", why));
    return ch;
  };
  if (!broken_[c].empty()) return none(broken_[c]);
  StreamingDeviation copy = devs_[c];
  const DevRequest dreq = detail::oadev_request(AnalyzeRequest{});
  StreamingDeviation::Result r = copy.finish(dt_, dreq.options);
  if (r.points.size() < 2) return none("too few samples yet for the Allan curve");
  const NoiseAnalysis na = detail::noise_of(std::move(r.points));
  const ReportedTerms rt = reported_terms(na.readoffs, na.fit, to_allan_curve(na.adev));
  if (rt.constant) return none("every deviation is zero: nothing to report");
  const double z = normal_half_width(opt_.ci);
  for (PlanTerm t : shown) {
    if (t == PlanTerm::Q)
      ch.terms.push_back(other_term(t, na.readoffs.Q, z));
    else if (t == PlanTerm::R)
      ch.terms.push_back(other_term(t, na.readoffs.R, z));
    else
      ch.terms.push_back(reported_term(t, rt, na.readoffs, z));
  }
  return ch;
}

LiveStatus LiveNoiseStatus::evaluate() {
  flush();
  LiveStatus s;
  s.samples = samples_;
  s.dt = dt_;
  s.record_s = record_seconds();
  s.ci = opt_.ci;
  s.unit = unit_;
  s.window_bound = opt_.window_bound;
  s.targets = opt_.targets;
  if (dt_ <= 0.0) {
    s.why = samples_ < kPeriodIntervals + 1 && time_index_ >= 0
                ? "too few samples yet to tell the sample period from the time column"
                : "no sample period: the recording has no time column and no {rate}";
    for (const auto& n : names_) s.channels.push_back(LiveChannel{n, {}, s.why});
    return s;
  }
  s.all_met = !opt_.targets.empty() && !names_.empty();
  for (std::size_t c = 0; c < names_.size(); ++c) {
    LiveChannel ch = channel_status(c);
    if (!opt_.targets.empty()) plan_targets(ch, opt_.targets, dt_, s.record_s, opt_.ci);
    for (const auto& t : ch.terms)
      if (t.target && !t.met) s.all_met = false;
    if (!opt_.targets.empty() && ch.terms.empty()) s.all_met = false;
    s.channels.push_back(std::move(ch));
  }
  return s;
}

namespace {

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// A term in display units (noise/units.hpp; T in s).
nlohmann::json display_json(const LiveTerm& t, const Unit& unit) {
  nlohmann::json d;
  const std::optional<Term> ieee = ieee_term(t.term);
  if (!ieee) {
    d = {{"value", number_or_null(t.value)}, {"sigma", number_or_null(t.sigma)}, {"unit", "s"}};
    d["interval"] = t.resolved ? nlohmann::json({t.lo, t.hi}) : nlohmann::json(nullptr);
    return d;
  }
  TermEstimate e;
  e.valid = std::isfinite(t.value);
  e.value = e.valid ? t.value : 0.0;
  e.sigma = std::isfinite(t.sigma) ? t.sigma : 0.0;
  const Quantity q = display(e, *ieee, unit);
  const double scale = e.value != 0.0 ? q.value / e.value : 1.0;
  d = {{"value", e.valid ? nlohmann::json(q.value) : nlohmann::json(nullptr)},
       {"sigma", t.resolved ? nlohmann::json(q.sigma) : nlohmann::json(nullptr)},
       {"unit", q.unit}};
  d["interval"] = t.resolved ? nlohmann::json({t.lo * scale, t.hi * scale}) : nlohmann::json(nullptr);
  return d;
}

nlohmann::json term_json(const LiveTerm& t, const Unit& unit) {
  nlohmann::json j;
  j["term"] = std::string(to_string(t.term));
  j["resolved"] = t.resolved;
  j["value"] = number_or_null(t.value);
  j["sigma"] = number_or_null(t.sigma);
  j["interval"] = t.resolved ? nlohmann::json({t.lo, t.hi}) : nlohmann::json(nullptr);
  j["tau_range_s"] = t.tau_hi > 0 ? nlohmann::json({t.tau_lo, t.tau_hi}) : nlohmann::json(nullptr);
  j["upper_bound"] = t.bound;
  j["source"] = t.source;
  j["display"] = display_json(t, unit);
  j["precision"] = number_or_null(t.precision);
  j["target"] = t.target ? nlohmann::json(*t.target) : nlohmann::json(nullptr);
  j["met"] = t.target ? nlohmann::json(t.met) : nlohmann::json(nullptr);
  j["needed_s"] = number_or_null(t.needed_s);
  j["remaining_s"] = t.target ? number_or_null(t.remaining_s) : nlohmann::json(nullptr);
  j["why"] = t.why;
  return j;
}

}  // namespace

nlohmann::json to_json(const LiveStatus& s) {
  nlohmann::json j;
  j["format"] = std::string(kStatusFormat);
  j["samples"] = s.samples;
  j["rate_hz"] = s.dt > 0 ? nlohmann::json(1.0 / s.dt) : nlohmann::json(nullptr);
  j["record_s"] = s.record_s;
  j["ci"] = s.ci;
  j["unit"] = s.unit.name;
  j["window_bound"] = s.window_bound;
  nlohmann::json targets = nlohmann::json::array();
  for (const auto& t : s.targets)
    targets.push_back({{"term", std::string(to_string(t.term))}, {"precision", t.precision}});
  j["targets"] = targets;
  j["all_met"] = s.all_met;
  j["why"] = face_words(s.why);
  nlohmann::json channels = nlohmann::json::array();
  for (const auto& ch : s.channels) {
    nlohmann::json c;
    c["name"] = ch.name;
    c["why"] = face_words(ch.why);
    nlohmann::json terms = nlohmann::json::array();
    for (const auto& t : ch.terms) terms.push_back(term_json(t, s.unit));
    c["terms"] = terms;
    channels.push_back(c);
  }
  j["channels"] = channels;
  return j;
}

void write_status_file(const std::string& dir, const nlohmann::json& content) {
  io::replace_file_atomically(dir + "/" + std::string(kStatusName), json_text(content, 2) + "\n");
}

}  // namespace cubecal::pipeline
