#include "cubecal/noise/bias_verdict.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cubecal {

namespace {

// printf-style number (the core does not depend on a formatting library).
std::string num(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double model_variance(const NoiseFit& f, double tau) {
  double v = 0.0;
  for (std::size_t k = 0; k < f.c.size(); ++k) v += f.c[k] * std::pow(tau, static_cast<int>(k) - 2);
  return v;
}

}  // namespace

BiasVerdict judge_bias_instability(const SlopeReadOffs& ro, const NoiseFit& fit) {
  BiasVerdict v;
  if (!ro.B.valid) return v;  // no minimum inside the record: nothing to compare with
  const double total = model_variance(fit, ro.tau_min);
  if (total > 0.0) v.other_terms_share = std::clamp((total - fit.c[2]) / total, 0.0, 1.0);
  const bool fit_follows = fit.rms_rel_residual <= kFitMisses;
  const std::string residual = "rms residual " + num("%.0f", 100.0 * fit.rms_rel_residual) + " %";
  if (!fit.B.valid) {
    if (!fit_follows) {
      v.trust = BiasTrust::read_off;
      v.reason = "the fit finds no flicker floor but misses the curve (" + residual +
                 "); the read-off sigma_min/0.664 is measured on the curve (an upper bound on B)";
    } else {
      v.trust = BiasTrust::fit;
      v.reason = "the fit explains the minimum at " + num("%.3g", ro.tau_min) +
                 " s by white noise and random walk alone (" + residual +
                 "); the read-off sigma_min/0.664 then only bounds B from above";
    }
    return v;
  }
  v.compared = true;
  v.ratio = fit.B.value / ro.B.value;
  v.beyond_sigma = std::fabs(fit.B.value - ro.B.value) > std::hypot(fit.B.sigma, ro.B.sigma);
  if (std::fabs(v.ratio - 1.0) <= kBiasDisagreement) {
    v.trust = BiasTrust::agree;
    return v;
  }
  if (!fit_follows) {
    v.trust = BiasTrust::read_off;
    v.reason = "the five power laws miss this curve (" + residual +
               "; a correlated, Gauss-Markov bias makes such bumps), so the fit's B is not reliable; the read-off "
               "sigma_min/0.664 is measured on the curve (an upper bound on B)";
  } else {
    v.trust = BiasTrust::fit;
    v.reason = "white noise and random walk make " + num("%.0f", 100.0 * v.other_terms_share) +
               " % of the variance at the minimum (" + num("%.3g", ro.tau_min) +
               " s), which biases the read-off sigma_min/0.664 high; the fit models all terms together (" + residual +
               ")";
  }
  return v;
}

std::string_view to_string(BiasTrust t) noexcept {
  switch (t) {
    case BiasTrust::agree: return "agree";
    case BiasTrust::read_off: return "read_off";
    case BiasTrust::fit: return "fit";
    case BiasTrust::neither: return "neither";
  }
  return "neither";
}

}  // namespace cubecal
