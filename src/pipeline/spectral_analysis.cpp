// The IEEE 952 terms of a channel seen from the Allan curve and from the
// spectrum, side by side (compare_views). docs/formulas/spectral.md §6.3.
#include "cubecal/pipeline/spectral_analysis.hpp"

#include <cmath>

namespace cubecal::pipeline {

namespace {

const TermEstimate& allan_term(const NoiseFit& f, Term t) {
  switch (t) {
    case Term::Q: return f.Q;
    case Term::N: return f.N;
    case Term::B: return f.B;
    case Term::K: return f.K;
    case Term::R: return f.R;
  }
  return f.N;
}

}  // namespace

std::vector<TermViews> compare_views(const NoiseFit& allan, const SpectralAnalysis& spectral) {
  std::vector<TermViews> out;
  for (const Term t : {Term::N, Term::B, Term::K, Term::Q}) {
    const PsdAllanTerm* s = nullptr;
    for (const PsdAllanTerm& a : spectral.allan_terms)
      if (a.term == t) s = &a;
    if (s == nullptr) continue;
    TermViews v;
    v.term = t;
    v.allan = allan_term(allan, t);
    v.spectrum = s->estimate;
    const double combined = std::hypot(v.spectrum.sigma, v.allan.sigma);
    if (v.allan.valid && v.spectrum.valid && combined > 0.0 && std::isfinite(combined))
      v.difference_sigmas = (v.spectrum.value - v.allan.value) / combined;
    out.push_back(v);
  }
  return out;
}

}  // namespace cubecal::pipeline
