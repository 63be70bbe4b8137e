/// @file
/// Between spectra and Allan variances: the IEEE 952 terms (noise_terms.hpp)
/// as one-sided power-law coefficients h_alpha and back, IEEE 952's
/// two-sided densities, the closed-form AVAR of each power law, and the AVAR
/// of a measured spectrum by the integral
///   AVAR(tau) = 2 int_0^{f_s/2} S_y(f) sin^4(pi f tau) / (m sin(pi f tau_0))^2 df   (sampled data)
///   AVAR(tau) = 2 int_0^inf     S_y(f) sin^4(pi f tau) / (pi f tau)^2 df            (continuous time)
/// with tau = m tau_0. docs/formulas/spectral.md §6.
#pragma once
#include <span>
#include <vector>

#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/spectral/psd.hpp"

namespace cubecal {

/// The exponent of a term's one-sided density: Q +2, N 0, B -1, K -2.
/// Throws std::invalid_argument for R (a deterministic ramp, no power law).
int power_law_exponent(Term term);

/// h_alpha of a term's value (data unit and seconds):
///   Q: h_2 = 4 pi^2 Q^2 / f_h    N: h_0 = 2 N^2    B: h_-1 = B^2 / pi    K: h_-2 = K^2 / (2 pi^2)
/// f_h, the high cutoff of white PM, matters for Q only (rate / 2 for
/// sampled data).
double power_law_coefficient(Term term, double value, double f_h = 0.0);

/// The term from its coefficient, the uncertainty by the delta method
/// (sigma_T = T sigma_h / (2 h)); valid false (value 0) for h <= 0.
TermEstimate term_from_power_law(Term term, double h, double h_sigma, double f_h = 0.0);

/// IEEE 952's two-sided density of the term at f > 0 (half the one-sided):
/// N^2, B^2 / (2 pi f), K^2 / (2 pi f)^2, (2 pi f)^2 Q^2 / (2 f_h).
double two_sided_density(Term term, double value, double f, double f_h = 0.0);

/// The Allan variance of one-sided h f^alpha in continuous time (NIST SP 1065
/// Table 2): alpha 0: h / (2 tau); -1: 2 ln2 h; -2: (2 pi^2 / 3) h tau;
/// +2 (white PM up to f_h, 2 pi f_h tau >> 1): 3 f_h h / (4 pi^2 tau^2).
/// Throws std::invalid_argument for another alpha.
double power_law_avar(int alpha, double h, double tau, double f_h = 0.0);

/// Which relation between a spectral density and the Allan variance to use.
enum class AllanKernel {
  sampled,     ///< the exact relation for samples every tau_0 averaged over m of them
  continuous,  ///< the continuous-time integral (tau_0 -> 0)
};

/// AVAR at each tau of a one-sided density on the uniform grid f_k = k df,
/// k = 0..n-1, by the sum 2 sum_k S_k kernel(f_k) df: the trapezoid rule
/// when the end values are halved, as the Welch estimator's DC and Nyquist
/// bins are. rate_hz gives tau_0 (the sampled kernel). Throws UsageError
/// ("taus") for a tau below tau_0 with the sampled kernel or not positive.
std::vector<double> avar_from_density(std::span<const double> density, double df, std::span<const double> taus,
                                      double rate_hz, AllanKernel kernel = AllanKernel::sampled);

/// The same over a raw Welch spectrum (std::invalid_argument when binned).
std::vector<double> avar_from_psd(const Psd& raw, std::span<const double> taus,
                                  AllanKernel kernel = AllanKernel::sampled);

}  // namespace cubecal
