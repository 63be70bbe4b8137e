#include "cubecal/noise/reported_terms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cubecal {

namespace {

// min over the curve of dev(tau) * f(tau): the largest term value the curve
// allows when the term's own AVAR arm is f^-2 (the other arms are >= 0).
// tau_lo = tau_hi = the tau that sets it.
template <class F>
TermEstimate bound_over_curve(const AllanCurve& c, F f) {
  TermEstimate e;
  double b = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!(c.tau[i] > 0.0) || !std::isfinite(c.dev[i])) continue;
    const double v = c.dev[i] * f(c.tau[i]);
    if (v < b) {
      b = v;
      e.tau_lo = e.tau_hi = c.tau[i];
    }
  }
  e.valid = std::isfinite(b);
  e.value = e.valid ? b : 0.0;
  return e;
}

ReportedTerm estimate(const TermEstimate& t, TermSource s) { return {s, t}; }
ReportedTerm bound(const TermEstimate& t) { return {TermSource::upper_bound, t}; }

}  // namespace

std::string_view to_string(TermSource s) noexcept {
  switch (s) {
    case TermSource::fit: return "fit";
    case TermSource::read_off: return "read-off";
    case TermSource::upper_bound: return "UPPER BOUND";
  }
  return "fit";
}

bool significant(const TermEstimate& t) noexcept {
  return t.valid && std::isfinite(t.value) && std::isfinite(t.sigma) && t.value > kSignificanceSigmas * t.sigma;
}

ReportedTerms reported_terms(const SlopeReadOffs& ro, const NoiseFit& fit, const AllanCurve& curve) {
  ReportedTerms r;
  r.constant = std::none_of(curve.dev.begin(), curve.dev.end(), [](double d) { return d > 0.0; });
  if (r.constant) {
    r.N.estimate = r.K.estimate = r.B.estimate = TermEstimate{};
    return r;
  }

  r.N = ro.N.valid ? estimate(ro.N, TermSource::read_off)
                   : bound(bound_over_curve(curve, [](double tau) { return std::sqrt(tau); }));

  r.K_candidate_source = fit.K.valid ? TermSource::fit : TermSource::read_off;
  r.K_candidate = fit.K.valid ? fit.K : ro.K;
  if (significant(fit.K))
    r.K = estimate(fit.K, TermSource::fit);
  else if (significant(ro.K))
    r.K = estimate(ro.K, TermSource::read_off);
  else
    r.K = bound(bound_over_curve(curve, [](double tau) { return std::sqrt(3.0 / tau); }));

  r.no_minimum = !ro.B.valid;
  if (!r.no_minimum) {
    r.B = estimate(ro.B, TermSource::read_off);
  } else {
    // AVAR >= (0.664 B)^2 at every tau: the lowest point bounds B, at
    // whichever end of the record it lies.
    TermEstimate b;
    b.valid = true;
    b.value = ro.sigma_min / kFlickerFloor;
    b.tau_lo = b.tau_hi = ro.tau_min;
    r.B = bound(b);
  }
  return r;
}

}  // namespace cubecal
