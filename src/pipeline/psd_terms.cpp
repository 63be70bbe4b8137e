// The IEEE 952 terms of a fitted power law (pipeline/psd.hpp:
// psd_allan_terms), shared by `cubecal psd` and analyze's spectral view.
// Apart from run_psd so that analysis.json's reader takes it without FFTW.
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/spectral/allan_conversion.hpp"

namespace cubecal::pipeline {

namespace {

// The IEEE 952 term each exponent of the default model stands for.
bool term_of(int alpha, Term& term) {
  switch (alpha) {
    case 2: term = Term::Q; return true;
    case 0: term = Term::N; return true;
    case -1: term = Term::B; return true;
    case -2: term = Term::K; return true;
    default: return false;
  }
}

}  // namespace

std::vector<PsdAllanTerm> psd_allan_terms(const PowerLawFit& fit, const Unit& unit, double rate_hz) {
  // A unit without a name is shown as u.
  const Unit shown = unit.name.empty() ? Unit{std::string(1, 'u'), unit.kind, unit.to_si, unit.si_name} : unit;
  std::vector<PsdAllanTerm> out;
  for (const PowerLawTerm& t : fit.terms) {
    Term term{};
    if (!term_of(t.alpha, term)) continue;
    PsdAllanTerm a;
    a.term = term;
    a.alpha = t.alpha;
    a.estimate = term_from_power_law(term, t.valid ? t.h : 0.0, t.sigma, 0.5 * rate_hz);
    a.display = display(a.estimate, term, shown);
    out.push_back(a);
  }
  return out;
}

}  // namespace cubecal::pipeline
