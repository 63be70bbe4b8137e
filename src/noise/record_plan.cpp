// How long to record (record_plan.hpp; docs/formulas/planning.md): the
// analysis of the record a model would give, made on the model's own curve.
#include "cubecal/noise/record_plan.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cctype>
#include <cmath>
#include <fast_float/fast_float.h>
#include <limits>
#include <stdexcept>
#include <cstdio>

#include "cubecal/error.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string percent(double p) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g %%", 100.0 * p);
  return buf;
}

}  // namespace

std::string_view to_string(PlanTerm t) noexcept {
  switch (t) {
    case PlanTerm::Q: return "Q";
    case PlanTerm::N: return "N";
    case PlanTerm::B: return "B";
    case PlanTerm::K: return "K";
    case PlanTerm::R: return "R";
    case PlanTerm::T: return "T";
  }
  return "?";
}

std::optional<PlanTerm> plan_term_from_name(std::string_view name) noexcept {
  if (name.size() != 1) return std::nullopt;
  switch (std::toupper(static_cast<unsigned char>(name[0]))) {
    case 'Q': return PlanTerm::Q;
    case 'N': return PlanTerm::N;
    case 'B': return PlanTerm::B;
    case 'K': return PlanTerm::K;
    case 'R': return PlanTerm::R;
    case 'T': return PlanTerm::T;
    default: return std::nullopt;
  }
}

std::string_view to_string(PlanReason r) noexcept {
  switch (r) {
    case PlanReason::none: return "";
    case PlanReason::not_in_model: return "not in model";
    case PlanReason::not_resolved: return "not resolved";
    case PlanReason::rate_too_low: return "rate too low";
    case PlanReason::finer_than_model: return "finer than model";
    case PlanReason::too_long: return "too long";
  }
  return "";
}

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

PlanTarget parse_one_target(std::string_view item) {
  const std::string what =
      "a target is TERM:PRECISION with TERM one of Q, N, B, K, R, T and PRECISION a percentage (B:10%) "
      "or a fraction (B:0.1) between 0 and 1";
  const auto colon = item.find(':');
  if (colon == std::string_view::npos)
    throw UsageError(Field::target, "'" + std::string(item) + "' has no ':'; " + what);
  const auto term = plan_term_from_name(trim(item.substr(0, colon)));
  if (!term) throw UsageError(Field::target, "'" + std::string(item) + "' names no term; " + what);
  std::string_view num = trim(item.substr(colon + 1));
  const bool pct = !num.empty() && num.back() == '%';
  if (pct) num = trim(num.substr(0, num.size() - 1));
  double v = kNaN;
  const auto res = fast_float::from_chars(num.data(), num.data() + num.size(), v);
  if (num.empty() || res.ec != std::errc{} || res.ptr != num.data() + num.size() || !std::isfinite(v))
    throw UsageError(Field::target, "'" + std::string(item) + "': the precision is not a number; " + what);
  if (pct) v /= 100.0;
  if (!(v > 0.0 && v < 1.0))
    throw UsageError(Field::target, "'" + std::string(item) + "': the precision must lie between 0 and 100 %; " + what);
  return {*term, v};
}

}  // namespace

std::vector<PlanTarget> parse_plan_targets(std::string_view spec) {
  std::vector<PlanTarget> out;
  std::size_t start = 0;
  while (start <= spec.size()) {
    const auto comma = spec.find(',', start);
    const std::string_view item = trim(spec.substr(start, comma == std::string_view::npos ? spec.npos : comma - start));
    if (item.empty())
      throw UsageError(Field::target, "an empty target in '" + std::string(spec) +
                                          "'; give TERM:PRECISION items separated by commas, e.g. B:10%,N:1%");
    const PlanTarget t = parse_one_target(item);
    for (const PlanTarget& o : out)
      if (o.term == t.term)
        throw UsageError(Field::target, "the term " + std::string(to_string(t.term)) + " is targeted twice in '" +
                                            std::string(spec) + "'");
    out.push_back(t);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

PlanModel plan_model(const PlanTerms& t, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::invalid_argument("plan_model: dt must be positive");
  for (const double v : {t.Q, t.N, t.B, t.K, t.R})
    if (!(v >= 0.0) || !std::isfinite(v)) throw std::invalid_argument("plan_model: terms must be finite and >= 0");
  return {dt, [t, dt](std::size_t m) {
            const double tau = static_cast<double>(m) * dt;
            const double b = kFlickerFloor * t.B;
            return 3.0 * t.Q * t.Q / (tau * tau) + t.N * t.N / tau + b * b + t.K * t.K * tau / 3.0 +
                   t.R * t.R * tau * tau / 2.0;
          }};
}

namespace {

// ---------------------------------------------------------------------------
// The model's curve as `analyze` would measure it (planning.md §1).

// The noise type at m from the model's local slope mu of AVAR ~ tau^mu:
// alpha = -mu - 1 (white FM mu = -1: 0; flicker FM 0: -1; random-walk FM
// +1: -2), mu <= -1.5 the PM types (mu = -2), taken as white PM (the
// quantization noise of a rate sensor is white PM of its angle); beyond
// random walk (rate ramp) the EDF of random walk, the steepest Greenhall's
// algorithm answers for the Allan variance.
int alpha_of_slope(double mu) {
  if (!std::isfinite(mu)) return 0;
  if (mu <= -1.5) return 2;
  return static_cast<int>(std::clamp(std::lround(-mu - 1.0), -2L, 1L));
}

int model_alpha(const PlanModel& model, std::size_t m) {
  const std::size_t lo = std::max<std::size_t>(1, m * 4 / 5), hi = std::max(m * 5 / 4, m + 1);
  const double mu =
      std::log(model.avar(hi) / model.avar(lo)) / std::log(static_cast<double>(hi) / static_cast<double>(lo));
  return alpha_of_slope(mu);
}

struct ModelCurve {
  AllanCurve curve;  // intervals at 1 sigma (ci 0.683)
};

constexpr double kOneSigma = 0.682689492137086;

ModelCurve model_curve(const PlanModel& model, std::size_t n, const PlanOptions& opt) {
  ModelCurve mc;
  const std::size_t n_phase = n + 1;
  const auto ms = averaging_factors(opt.grid, max_averaging_factor(Stat::oadev, n_phase), model.dt);
  for (const std::size_t m : ms) {
    const double a = model.avar(m);
    if (!(a > 0.0) || !std::isfinite(a)) continue;
    const double dev = std::sqrt(a);
    const double edf = edf_for(Stat::oadev, model_alpha(model, m), m, n_phase);
    if (!(edf > 0.0)) continue;
    mc.curve.tau.push_back(static_cast<double>(m) * model.dt);
    mc.curve.dev.push_back(dev);
    mc.curve.interval.push_back(chi2_interval(dev, edf, kOneSigma));
    mc.curve.edf.push_back(edf);
    mc.curve.m.push_back(m);
    mc.curve.terms.push_back(n_phase - 2 * m);
  }
  return mc;
}

// ---------------------------------------------------------------------------

double ci_factor(double ci) {
  if (!(ci > 0.0 && ci < 1.0))
    throw UsageError(Field::ci, "the confidence must lie between 0 and 1 (0.683: 1 sigma), not " + std::to_string(ci));
  return boost::math::quantile(boost::math::normal(), 0.5 + ci / 2.0);
}

TermPrecision unresolved(PlanTerm term, std::string why) {
  TermPrecision p;
  p.term = term;
  p.value = p.precision = kNaN;
  p.reason = PlanReason::not_resolved;
  p.why = std::move(why);
  return p;
}

TermPrecision from_estimate(PlanTerm term, const TermEstimate& e, double z) {
  TermPrecision p;
  p.term = term;
  p.value = e.value;
  p.precision = z * e.sigma / e.value;
  p.tau_lo = e.tau_lo;
  p.tau_hi = e.tau_hi;
  return p;
}

// The relative 1-sigma of the fit's K on the model curve of `c` at the
// points of `curve`, plus `floor` (u^2) at every point.
double fitted_k_sigma(const AllanCurve& curve, const std::array<double, 5>& c, double floor) {
  AllanCurve mc;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const double tau = curve.tau[i];
    double v = floor, slope = 0.0;
    for (std::size_t k = 0; k < 5; ++k) {
      const double part = std::max(0.0, c[k]) * std::pow(tau, static_cast<double>(k) - 2.0);
      v += part;
      slope += (static_cast<double>(k) - 2.0) * part;
    }
    if (!(v > 0.0) || !std::isfinite(v)) continue;
    const double mu = slope / v;  // d ln sigma^2 / d ln tau
    const int alpha = alpha_of_slope(mu);
    const std::size_t m = curve.m[i];
    const double edf = edf_for(Stat::oadev, alpha, m, curve.terms[i] + 2 * m);
    if (!(edf > 0.0)) continue;
    mc.tau.push_back(tau);
    mc.dev.push_back(std::sqrt(v));
    mc.interval.push_back(chi2_interval(std::sqrt(v), edf, kOneSigma));
    mc.edf.push_back(edf);
    mc.m.push_back(m);
    mc.terms.push_back(curve.terms[i]);
  }
  const NoiseFit f = fit_noise_terms(mc);
  return f.K.valid && f.K.value > 0.0 ? f.K.sigma / f.K.value : kNaN;
}

}  // namespace

double planned_random_walk_sigma(const AllanCurve& curve, const std::array<double, 5>& c) {
  if (curve.m.size() != curve.size() || curve.terms.size() != curve.size() || curve.size() < 3 || !(c[3] > 0.0))
    return kNaN;
  const double bound = fitted_k_sigma(curve, c, 0.0);
  if (c[2] > 0.0 || !std::isfinite(bound)) return bound;
  // No flicker floor: the fit of a measured curve frees its flicker coefficient whenever the estimate comes out
  // positive, in half the records; a floor of a millionth of the lowest variance frees it and changes no value.
  double lowest = std::numeric_limits<double>::infinity();
  for (const double tau : curve.tau) {
    double v = 0.0;
    for (std::size_t k = 0; k < 5; ++k) v += std::max(0.0, c[k]) * std::pow(tau, static_cast<double>(k) - 2.0);
    lowest = std::min(lowest, v);
  }
  const double free = fitted_k_sigma(curve, c, 1e-6 * lowest);
  return std::isfinite(free) ? std::sqrt(0.5 * (bound * bound + free * free)) : bound;
}

std::vector<TermPrecision> plan_precision(const PlanModel& model, double duration_s, std::span<const PlanTerm> terms,
                                          const PlanOptions& options) {
  if (!model.avar || !(model.dt > 0.0)) throw std::invalid_argument("plan_precision: a model needs dt and avar");
  if (!(duration_s >= 3.0 * model.dt) || !std::isfinite(duration_s))
    throw std::invalid_argument("plan_precision: the record must span three sample periods");
  const double z = ci_factor(options.ci);
  const auto n = static_cast<std::size_t>(std::floor(duration_s / model.dt + 1e-9));
  const ModelCurve mc = model_curve(model, n, options);
  const SlopeReadOffs ro = read_off_noise_terms(mc.curve);
  const NoiseFit fit = fit_noise_terms(mc.curve);
  const ReportedTerms rt = reported_terms(ro, fit, mc.curve);

  std::vector<TermPrecision> out;
  for (const PlanTerm t : terms) {
    switch (t) {
      case PlanTerm::N:
        out.push_back(rt.N.bound() ? unresolved(t, "the curve has no white-noise (-1/2) arm in this record")
                                   : from_estimate(t, rt.N.estimate, z));
        break;
      case PlanTerm::K:
        out.push_back(rt.K.bound()
                          ? unresolved(t, "the curve's rate random walk (+1/2) is not significant in this record")
                          : from_estimate(t, rt.K.estimate, z));
        break;
      case PlanTerm::Q:
        out.push_back(ro.Q.valid ? from_estimate(t, ro.Q, z)
                                 : unresolved(t, "the curve has no quantization (-1) arm in this record"));
        break;
      case PlanTerm::R:
        out.push_back(ro.R.valid ? from_estimate(t, ro.R, z)
                                 : unresolved(t, "the curve has no rate ramp (+1) arm in this record"));
        break;
      case PlanTerm::B:
      case PlanTerm::T: {
        if (rt.no_minimum) {
          out.push_back(unresolved(t, "the curve has no minimum within this record"));
          break;
        }
        TermPrecision p;
        p.term = t;
        p.tau_lo = ro.tau_min_lo;
        p.tau_hi = ro.tau_min_hi;
        p.value = t == PlanTerm::B ? rt.B.value() : rt.T;
        p.precision = z * (t == PlanTerm::B ? rt.B.estimate.sigma / rt.B.value() : rt.T_rel_sigma);
        out.push_back(p);
        break;
      }
    }
  }
  return out;
}

}  // namespace cubecal
namespace cubecal {

namespace {

// The relative half-step of the tau grid: T is one of its taus.
double grid_half_step(const TauGrid& g) {
  switch (g.kind) {
    case TauGrid::Kind::log: return std::pow(10.0, 0.5 / std::max(1u, g.per_decade)) - 1.0;
    case TauGrid::Kind::octave: return std::sqrt(2.0) - 1.0;
    case TauGrid::Kind::decade: return std::sqrt(2.5) - 1.0;
    case TauGrid::Kind::all:
    case TauGrid::Kind::list: return 0.0;
  }
  return 0.0;
}

std::string grid_words(const TauGrid& g) {
  switch (g.kind) {
    case TauGrid::Kind::log: return std::to_string(g.per_decade) + " taus per decade";
    case TauGrid::Kind::octave: return "octave taus";
    case TauGrid::Kind::decade: return "decade taus (1, 2, 4, 10, ...)";
    default: return "the tau grid";
  }
}

std::string years(double s) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.3g years", s / (365.25 * 86400.0));
  return buf;
}

// The local slope of the model's Allan deviation at its first tau.
double first_slope(const PlanModel& model) { return 0.5 * std::log(model.avar(2) / model.avar(1)) / std::log(2.0); }

// Why a term the longest record does not resolve is not resolved.
TermPrecision never_resolved(const PlanModel& model, TermPrecision p, const PlanOptions& opt) {
  const double slope = first_slope(model);
  char rate[64];
  std::snprintf(rate, sizeof rate, "%.4g Hz (first tau %.4g s)", 1.0 / model.dt, model.dt);
  const std::string within = "within " + years(opt.max_duration_s);
  switch (p.term) {
    case PlanTerm::N:
      if (slope > -0.35) {
        p.reason = PlanReason::rate_too_low;
        p.why = std::string("at ") + rate + " the curve is already past its white-noise (-1/2) arm: sample faster";
      } else {
        p.reason = PlanReason::not_in_model;
        p.why = "the model's curve has no white-noise (-1/2) arm";
      }
      break;
    case PlanTerm::Q:
      if (slope > -0.85) {
        p.reason = PlanReason::rate_too_low;
        p.why = std::string("at ") + rate +
                " the curve shows no quantization (-1) arm: sample faster, or the model has none";
      } else {
        p.reason = PlanReason::not_in_model;
        p.why = "the model's curve has no quantization (-1) arm";
      }
      break;
    case PlanTerm::K:
      p.reason = PlanReason::not_in_model;
      p.why = "the model has no rate random walk: its curve does not rise at slope +1/2 " + within;
      break;
    case PlanTerm::R:
      p.reason = PlanReason::not_in_model;
      p.why = "the model has no rate ramp: its curve does not rise at slope +1 " + within;
      break;
    case PlanTerm::B:
    case PlanTerm::T:
      if (slope > 0.0) {
        p.reason = PlanReason::rate_too_low;
        p.why =
            std::string("at ") + rate + " the curve rises from its first tau: its minimum lies below it, sample faster";
      } else {
        p.reason = PlanReason::not_in_model;
        p.why = "the model's curve has no minimum " + within + " (no flicker floor or random walk turns it up)";
      }
      break;
  }
  return p;
}

TargetPlan plan_target(const PlanModel& model, const PlanTarget& target, const PlanOptions& opt) {
  TargetPlan tp;
  tp.target = target;
  tp.duration_s = kNaN;
  const PlanTerm term[1] = {target.term};
  const auto at = [&](double d) { return plan_precision(model, d, term, opt).front(); };
  const auto meets = [&](const TermPrecision& p) {
    return p.reason == PlanReason::none && p.precision <= target.precision;
  };
  const double z = ci_factor(opt.ci);
  if (target.term == PlanTerm::T && target.precision < z * grid_half_step(opt.grid)) {
    tp.at = unresolved(PlanTerm::T, "");
    tp.at.reason = PlanReason::finer_than_model;
    tp.at.why = "T is one of the analysis's taus, " + grid_words(opt.grid) + ": it cannot be known finer than +-" +
                percent(z * grid_half_step(opt.grid)) + " at this confidence; ask for more taus per decade";
    return tp;
  }
  // Scan up in doublings, then bisect the step that first meets the target to 2 %.
  double lo = 0.0, d = std::max(64.0 * model.dt, 10.0);
  TermPrecision p;
  for (;; d *= 2.0) {
    d = std::min(d, opt.max_duration_s);
    p = at(d);
    if (meets(p)) break;
    if (d >= opt.max_duration_s) {
      tp.at = p;
      if (p.reason != PlanReason::none) {
        tp.at = never_resolved(model, p, opt);
      } else {
        tp.at.reason = PlanReason::too_long;
        tp.at.why = "needs more than " + years(opt.max_duration_s) + ": at that length +-" + percent(p.precision);
      }
      return tp;
    }
    lo = d;
  }
  double hi = d;
  if (lo > 0.0) {
    while (hi / lo > 1.02) {
      const double mid = std::sqrt(lo * hi);
      const TermPrecision q = at(mid);
      if (meets(q)) {
        hi = mid;
        p = q;
      } else {
        lo = mid;
      }
    }
  }
  tp.duration_s = hi;
  tp.at = p;
  return tp;
}

}  // namespace

std::vector<TargetPlan> plan_duration(const PlanModel& model, std::span<const PlanTarget> targets,
                                      const PlanOptions& options) {
  if (!model.avar || !(model.dt > 0.0)) throw std::invalid_argument("plan_duration: a model needs dt and avar");
  (void)ci_factor(options.ci);
  std::vector<TargetPlan> out;
  for (const PlanTarget& t : targets) out.push_back(plan_target(model, t, options));
  return out;
}

}  // namespace cubecal
