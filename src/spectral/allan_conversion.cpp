// docs/formulas/spectral.md §6.
#include "cubecal/spectral/allan_conversion.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

constexpr double kPi = std::numbers::pi;

double cutoff(Term term, double f_h) {
  if (term == Term::Q && !(f_h > 0.0))
    throw std::invalid_argument("angle quantization needs the high cutoff f_h of its white PM density");
  return f_h;
}

}  // namespace

int power_law_exponent(Term term) {
  switch (term) {
    case Term::Q: return 2;
    case Term::N: return 0;
    case Term::B: return -1;
    case Term::K: return -2;
    case Term::R: break;
  }
  throw std::invalid_argument("the rate ramp R is deterministic: it has no power-law density");
}

double power_law_coefficient(Term term, double value, double f_h) {
  const double v2 = value * value;
  switch (term) {
    case Term::Q: return 4.0 * kPi * kPi * v2 / cutoff(term, f_h);
    case Term::N: return 2.0 * v2;
    case Term::B: return v2 / kPi;
    case Term::K: return v2 / (2.0 * kPi * kPi);
    case Term::R: break;
  }
  throw std::invalid_argument("the rate ramp R is deterministic: it has no power-law density");
}

TermEstimate term_from_power_law(Term term, double h, double h_sigma, double f_h) {
  TermEstimate t;
  const double unit = power_law_coefficient(term, 1.0, f_h);  // h of a term of value 1
  if (!(h > 0.0)) return t;
  t.valid = true;
  t.value = std::sqrt(h / unit);
  t.sigma = t.value * h_sigma / (2.0 * h);
  return t;
}

double two_sided_density(Term term, double value, double f, double f_h) {
  return 0.5 * power_law_coefficient(term, value, f_h) * std::pow(f, power_law_exponent(term));
}

double power_law_avar(int alpha, double h, double tau, double f_h) {
  switch (alpha) {
    case 0: return h / (2.0 * tau);
    case -1: return 2.0 * std::numbers::ln2 * h;
    case -2: return 2.0 * kPi * kPi / 3.0 * h * tau;
    case 2:
      if (!(f_h > 0.0)) throw std::invalid_argument("white PM needs its high cutoff f_h");
      return 3.0 * f_h * h / (4.0 * kPi * kPi * tau * tau);
    default: break;
  }
  throw std::invalid_argument("power_law_avar: alpha must be 2, 0, -1 or -2");
}

std::vector<double> avar_from_density(std::span<const double> density, double df, std::span<const double> taus,
                                      double rate_hz, AllanKernel kernel) {
  const double tau0 = 1.0 / rate_hz;
  std::vector<double> out;
  out.reserve(taus.size());
  for (const double tau : taus) {
    if (!(tau > 0.0) || !std::isfinite(tau) || (kernel == AllanKernel::sampled && tau < tau0 * (1.0 - 1e-12)))
      throw UsageError(Field::taus, "an Allan variance needs tau >= 1/rate (" + std::to_string(tau) + " s)");
    const double m = tau / tau0;
    double sum = 0.0;
    // k = 0: the kernel is 0 at f = 0 (sin^4 over a square).
    for (std::size_t k = 1; k < density.size(); ++k) {
      const double f = static_cast<double>(k) * df;
      const double s = std::sin(kPi * f * tau);
      const double den = kernel == AllanKernel::sampled ? m * std::sin(kPi * f * tau0) : kPi * f * tau;
      sum += density[k] * (s * s) * (s * s) / (den * den);
    }
    out.push_back(2.0 * sum * df);
  }
  return out;
}

std::vector<double> avar_from_psd(const Psd& raw, std::span<const double> taus, AllanKernel kernel) {
  if (raw.bins_per_decade != 0) throw std::invalid_argument("avar_from_psd: give the raw spectrum");
  return avar_from_density(raw.density, raw.resolution_hz(), taus, raw.rate_hz, kernel);
}

}  // namespace cubecal
