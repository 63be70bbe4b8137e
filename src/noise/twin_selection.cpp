// The twin of a channel: a forward search over composite models on the WIC,
// with a fidelity rule (noise/twin_selection.hpp; docs/formulas/noise-terms.md §8f).
#include "cubecal/noise/twin_selection.hpp"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <numbers>
#include <exception>
#include <optional>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

constexpr double kPi = std::numbers::pi;

// The order terms are written in: the white part, QN, RW, DR, the
// Gauss-Markov terms, the lines.
int rank_of(ProcessKind k) {
  switch (k) {
    case ProcessKind::wn:
    case ProcessKind::ma1: return 0;
    case ProcessKind::qn: return 1;
    case ProcessKind::rw: return 2;
    case ProcessKind::dr: return 3;
    case ProcessKind::gm: return 4;
    case ProcessKind::sin: return 5;
  }
  return 6;
}

void canonical(CompositeModel& m) {
  std::stable_sort(m.processes.begin(), m.processes.end(),
                   [](const Process& a, const Process& b) { return rank_of(a.kind) < rank_of(b.kind); });
}

std::size_t count(const CompositeModel& m, ProcessKind k) {
  return static_cast<std::size_t>(
      std::count_if(m.processes.begin(), m.processes.end(), [k](const Process& p) { return p.kind == k; }));
}

// The most scales a model of J may leave outside its 95 % intervals and
// still be the true one: the 99 % quantile of Binomial(J, 0.05).
std::size_t allowed_outside(std::size_t J) {
  const boost::math::binomial law(static_cast<double>(J), 0.05);
  std::size_t k = 0;
  while (k < J && boost::math::cdf(law, static_cast<double>(k)) < 0.99) ++k;
  return k;
}

// A grown model: its structure (SIN terms carry their line's start) and
// a start with every parameter, the fitted model plus the new term placed
// where the curve lies above the fit.
struct Move {
  CompositeModel structure;
  CompositeModel start;
};

class Search {
 public:
  Search(const WaveletVariance& wv, std::size_t samples, double rate_hz, const std::vector<SpectralLine>& lines,
         const TwinOptions& options)
      : wv_(wv), samples_(samples), dt_(1.0 / rate_hz), lines_(lines), options_(options) {
    for (std::size_t j = 0; j < wv.size(); ++j) sd_.push_back(wv.nu2[j] * std::sqrt(2.0 / wv.edf[j]));
  }

  // A fit and its WIC with the weights sd; nullopt (and why) when there is none.
  std::optional<TwinCandidate> fit(const CompositeModel& structure, const std::vector<CompositeModel>& warm,
                                   const std::vector<double>& sd, std::size_t scattered, std::size_t step) {
    TwinCandidate c;
    c.structure = structure;
    c.step = step;
    try {
      GmwmOptions o;
      o.starts = scattered;
      o.max_iterations = options_.max_iterations;
      o.seed = options_.seed + step;
      o.fixed_sd = sd;
      o.warm_starts = warm;
      if (scattered == 0 && warm.empty()) o.starts = 1;
      c.fit = fit_gmwm(wv_, structure, o);
      c.score = wic_score_asymptotic(wv_, sd, c.fit, samples_, 1.0, true);
      if (!std::isfinite(c.score.wic))
        throw CalibrationError(CalibrationReason::degenerate, "a WIC that is not finite");
    } catch (const std::exception& e) {
      failed_.push_back(model_name(structure) + ": " + e.what());
      return std::nullopt;
    }
    return c;
  }

  std::vector<Move> moves(const TwinCandidate& at, std::size_t lines_used) const {
    const CompositeModel& s = at.structure;
    const CompositeModel& m = at.fit.model;
    const std::size_t J = wv_.size();
    // Where the curve lies above the fit, in its own spread.
    std::vector<double> gap(J);
    for (std::size_t j = 0; j < J; ++j) gap[j] = std::max(wv_.nu2[j] - at.fit.nu2_model[j], 0.0);
    const auto floor_of = [&](std::size_t j) { return std::max(gap[j], 1e-3 * wv_.nu2[j]); };
    std::vector<Move> out;
    const auto add = [&](Process structural, Process started, const CompositeModel* replace_white = nullptr) {
      Move mv;
      mv.structure = replace_white ? *replace_white : s;
      mv.start = m;
      if (replace_white) {
        for (std::size_t i = 0; i < mv.start.processes.size(); ++i)
          if (mv.start.processes[i].kind == ProcessKind::wn) mv.start.processes[i] = started;
      } else {
        mv.structure.processes.push_back(structural);
        mv.start.processes.push_back(started);
      }
      canonical(mv.structure);
      canonical(mv.start);
      if (parameter_count(mv.structure) + 1 <= J) out.push_back(std::move(mv));
    };
    const std::size_t wn = count(s, ProcessKind::wn), qn = count(s, ProcessKind::qn);
    if (wn == 1 && qn == 0) {
      // WN -> MA1: the same white level, theta 0.2 (a sensor's averaging filter).
      CompositeModel st = s;
      for (Process& p : st.processes)
        if (p.kind == ProcessKind::wn) p = Process{ProcessKind::ma1, 0.0, 0.0, 0.0};
      double white = 0.0;
      for (const Process& p : m.processes)
        if (p.kind == ProcessKind::wn) white = p.value;
      add({}, Process{ProcessKind::ma1, std::max(white, 1e-3 * wv_.nu2[0] * wv_.tau[0]) / 1.44, 0.0, 0.2}, &st);
      add(Process{ProcessKind::qn}, Process{ProcessKind::qn, floor_of(0) * wv_.tau[0] * wv_.tau[0] / 6.0});
    }
    // A model the backward half left without a white term may take one back.
    if (wn == 0 && count(s, ProcessKind::ma1) == 0)
      add(Process{ProcessKind::wn}, Process{ProcessKind::wn, floor_of(0) * wv_.tau[0]});
    const double tJ = wv_.tau[J - 1];
    if (count(s, ProcessKind::rw) == 0)
      add(Process{ProcessKind::rw}, Process{ProcessKind::rw, floor_of(J - 1) * 12.0 * tJ / (tJ * tJ + 2.0)});
    if (count(s, ProcessKind::dr) == 0)
      add(Process{ProcessKind::dr}, Process{ProcessKind::dr, std::sqrt(floor_of(J - 1) * 16.0) / tJ});
    if (count(s, ProcessKind::gm) < options_.max_gm) {
      // At the scale the curve stands furthest above the fit, in its spread.
      std::size_t jb = 0;
      double best = -1.0;
      for (std::size_t j = 0; j < J; ++j) {
        const double z = gap[j] / at.fit.sd[j];
        if (z > best) best = z, jb = j;
      }
      const double tc = std::max(wv_.tau[jb] / 3.8, 0.5);
      const double phi = std::exp(-1.0 / tc);
      const double sb2 = floor_of(jb) / 0.22;
      add(Process{ProcessKind::gm}, Process{ProcessKind::gm, sb2 * (1.0 - phi * phi), phi});
    }
    if (lines_used < std::min(options_.max_lines, lines_.size())) {
      const SpectralLine& l = lines_[lines_used];
      const double omega = 2.0 * kPi * l.frequency_hz * dt_;
      if (omega > 0.0 && omega < kPi) {
        Process p{ProcessKind::sin, 2.0 * l.power, 0.0, 0.0, omega};
        add(p, p);
      }
    }
    return out;
  }

  // The model less one term, and with one term swapped for its nearest
  // other (MA1 -> WN, DR -> RW, RW -> DR, the slowest GM -> RW): the
  // backward half of the search, from where the forward half stopped.
  std::vector<Move> variants(const TwinCandidate& at) const {
    const CompositeModel& s = at.structure;
    const CompositeModel& m = at.fit.model;
    const std::size_t J = wv_.size();
    std::vector<Move> out;
    const auto push = [&](Move mv) {
      if (mv.structure.processes.empty() || parameter_count(mv.structure) + 1 > J) return;
      canonical(mv.structure);
      canonical(mv.start);
      out.push_back(std::move(mv));
    };
    // The GM with the longest correlation time (m's GMs are sorted, shortest first).
    std::size_t slowest = m.processes.size();
    for (std::size_t i = 0; i < m.processes.size(); ++i)
      if (m.processes[i].kind == ProcessKind::gm) slowest = i;
    const double tJ = wv_.tau[J - 1];
    for (std::size_t i = 0; i < s.processes.size(); ++i) {
      const ProcessKind k = s.processes[i].kind;
      Move drop{s, m};
      drop.structure.processes.erase(drop.structure.processes.begin() + static_cast<std::ptrdiff_t>(i));
      drop.start.processes.erase(drop.start.processes.begin() + static_cast<std::ptrdiff_t>(i));
      push(drop);  // the white term too: a filtered or oversampled sensor's curve rises from the first scale
      Move swap{s, m};
      Process& ps = swap.structure.processes[i];
      Process& pm = swap.start.processes[i];
      if (k == ProcessKind::ma1) {
        ps = Process{ProcessKind::wn};
        pm = Process{ProcessKind::wn,
                     m.processes[i].value * (1.0 + m.processes[i].theta) * (1.0 + m.processes[i].theta)};
      } else if (k == ProcessKind::dr) {
        ps = Process{ProcessKind::rw};
        pm = Process{ProcessKind::rw, haar_wavelet_variance(m.processes[i], tJ) * 12.0 * tJ / (tJ * tJ + 2.0)};
      } else if (k == ProcessKind::rw) {
        ps = Process{ProcessKind::dr};
        pm = Process{ProcessKind::dr, std::sqrt(haar_wavelet_variance(m.processes[i], tJ) * 16.0) / tJ};
      } else if (k == ProcessKind::gm && i == slowest) {
        ps = Process{ProcessKind::rw};
        pm = Process{ProcessKind::rw, std::max(haar_wavelet_variance(m.processes[i], tJ), 1e-3 * wv_.nu2[J - 1]) *
                                          12.0 * tJ / (tJ * tJ + 2.0)};
      } else {
        continue;
      }
      // A swap that repeats a term the model has (RW beside RW) is no model.
      if (count(swap.structure, ps.kind) > 1 && ps.kind != ProcessKind::gm) continue;
      push(swap);
    }
    return out;
  }

  std::vector<double> sd_;
  std::vector<std::string> failed_;

 private:
  const WaveletVariance& wv_;
  std::size_t samples_;
  double dt_;
  const std::vector<SpectralLine>& lines_;
  const TwinOptions& options_;
};

}  // namespace

TwinFidelity twin_fidelity(const WaveletVariance& wv, const std::vector<double>& nu2_model) {
  TwinFidelity f;
  f.scales = std::min(wv.size(), nu2_model.size());
  for (std::size_t j = 0; j < f.scales; ++j) {
    // The 95 % chi-square interval of the scale, whatever wv.lo/hi hold.
    const boost::math::chi_squared law(wv.edf[j]);
    const double lo = wv.nu2[j] * wv.edf[j] / boost::math::quantile(boost::math::complement(law, 0.025));
    const double hi = wv.nu2[j] * wv.edf[j] / boost::math::quantile(law, 0.025);
    if (nu2_model[j] >= lo && nu2_model[j] <= hi) ++f.inside;
    const double e = std::abs(std::sqrt(nu2_model[j] / wv.nu2[j]) - 1.0);
    if (!(e <= f.max_error)) {
      f.max_error = e;
      f.max_error_tau = wv.tau[j];
    }
  }
  f.share_inside = f.scales ? static_cast<double>(f.inside) / static_cast<double>(f.scales) : 0.0;
  return f;
}

bool twin_faithful(const TwinFidelity& f) { return f.scales - f.inside <= allowed_outside(f.scales); }

namespace {

// Every model the search fitted, kept once by structure: the lowest-WIC fit.
void keep_lowest(std::vector<TwinCandidate>& seen, const TwinCandidate& c) {
  const std::string name = model_name(c.structure);
  for (TwinCandidate& s : seen)
    if (model_name(s.structure) == name) {
      if (c.score.wic < s.score.wic) s = c;
      return;
    }
  seen.push_back(c);
}

// The forward search with the curve's own spread as weights, from `start`:
// the models where it went (path) and every model it fitted (seen).
struct SearchTrail {
  std::vector<TwinCandidate> path;
  std::vector<TwinCandidate> seen;
};

SearchTrail forward_search(Search& search, TwinCandidate start, const TwinOptions& options) {
  const std::size_t scattered = options.starts > 0 ? options.starts - 1 : 0;
  SearchTrail trail;
  std::vector<TwinCandidate>& path = trail.path;
  const auto keep = [&trail](const TwinCandidate& c) { keep_lowest(trail.seen, c); };
  std::optional<TwinCandidate> at = std::move(start);
  std::size_t lines_used = 0;
  // Each step lowers the WIC; the cap only bounds a pathological curve.
  constexpr std::size_t kMaxSteps = 40;
  for (std::size_t step = 1; step <= kMaxSteps; ++step) {
    path.push_back(*at);
    keep(*at);
    std::optional<TwinCandidate> best;
    bool best_is_line = false;
    for (const Move& mv : search.moves(*at, lines_used)) {
      std::optional<TwinCandidate> c = search.fit(mv.structure, {mv.start}, search.sd_, scattered, step);
      if (c) keep(*c);
      if (c && (!best || c->score.wic < best->score.wic)) {
        best_is_line = count(mv.structure, ProcessKind::sin) > lines_used;
        best = std::move(c);
      }
    }
    if (!best || !(best->score.wic < at->score.wic - options.band)) {
      // The backward half: a smaller or swapped model that scores lower
      // goes on from there (each structure once).
      std::optional<TwinCandidate> back;
      for (const Move& mv : search.variants(*at)) {
        const std::string name = model_name(mv.structure);
        if (std::any_of(path.begin(), path.end(),
                        [&](const TwinCandidate& c) { return model_name(c.structure) == name; }))
          continue;
        std::optional<TwinCandidate> c = search.fit(mv.structure, {mv.start}, search.sd_, scattered, step);
        if (c) keep(*c);
        if (c && (!back || c->score.wic < back->score.wic)) back = std::move(c);
      }
      if (!back || !(back->score.wic < at->score.wic)) break;
      lines_used = count(back->structure, ProcessKind::sin);
      at = std::move(back);
      continue;
    }
    if (best_is_line) ++lines_used;
    at = std::move(best);
  }
  return trail;
}

// Every model the search fitted, refitted with common weights, the spread
// at a reference curve, each from its own fit. The reference: the
// geometric mean of the measured curve and that of the model where the
// search stopped, so that a scale which came out low is not weighed
// without bound, nor a model far above the last scales excused (at the
// model's own curve alone, one of a few degrees of freedom would weigh
// next to nothing where the model overshoots it).
void refit_with_common_weights(Search& search, const WaveletVariance& wv, const SearchTrail& trail,
                               std::vector<CandidateFit>& scored, std::vector<TwinCandidate>& refit) {
  const std::vector<TwinCandidate>& path = trail.path;
  const std::vector<TwinCandidate>& seen = trail.seen;
  std::vector<double> reference(wv.size());
  for (std::size_t j = 0; j < wv.size(); ++j) reference[j] = std::sqrt(wv.nu2[j] * path.back().fit.nu2_model[j]);
  std::vector<double> sd = wic_weights(wv, reference);
  for (const TwinCandidate& c : seen) {
    std::optional<TwinCandidate> r = search.fit(c.structure, {c.fit.model}, sd, 0, c.step);
    if (!r) continue;
    r->fidelity = twin_fidelity(wv, r->fit.nu2_model);
    scored.push_back({r->structure, r->fit, r->score});
    refit.push_back(std::move(*r));
  }
}

// The refitted models by WIC, the selected first, then the first faithful
// one moved to the front.
void rank_twins(TwinSelection& sel, std::vector<CandidateFit>& scored, std::vector<TwinCandidate>& refit,
                const TwinOptions& options) {
  // By WIC, the selected first: the fewest parameters within rank_band of
  // the lowest (rank_by_wic's rule, with the twin's band).
  std::stable_sort(scored.begin(), scored.end(), [](const CandidateFit& a, const CandidateFit& b) {
    if (a.score.wic != b.score.wic) return a.score.wic < b.score.wic;
    return parameter_count(a.structure) < parameter_count(b.structure);
  });
  {
    const double limit = scored.front().score.wic + options.rank_band;
    std::size_t pick = 0;
    for (std::size_t i = 1; i < scored.size() && scored[i].score.wic <= limit; ++i)
      if (parameter_count(scored[i].structure) < parameter_count(scored[pick].structure)) pick = i;
    std::rotate(scored.begin(), scored.begin() + static_cast<std::ptrdiff_t>(pick),
                scored.begin() + static_cast<std::ptrdiff_t>(pick) + 1);
  }
  std::vector<TwinCandidate> ranked;
  for (const CandidateFit& s : scored)
    for (TwinCandidate& r : refit)
      if (model_name(r.structure) == model_name(s.structure) && r.fit.objective == s.fit.objective) {
        ranked.push_back(r);
        break;
      }
  // The first faithful one in that order; none: the WIC's choice, said so.
  for (std::size_t i = 0; i < ranked.size(); ++i) {
    if (twin_faithful(ranked[i].fidelity)) {
      std::rotate(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(i),
                  ranked.begin() + static_cast<std::ptrdiff_t>(i) + 1);
      sel.faithful = true;
      break;
    }
  }
  sel.ranked = std::move(ranked);
}

}  // namespace

TwinSelection select_twin(const WaveletVariance& wv, std::size_t samples, double rate_hz,
                          const std::vector<SpectralLine>& lines, const TwinOptions& options) {
  if (wv.size() < 3)
    throw UsageError(Field::model,
                     "the record gives " + std::to_string(wv.size()) +
                         " wavelet-variance scales, too few for a twin (at least 3: a record of 16 samples "
                         "or more)");
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw UsageError(Field::rate, "the sample rate must be positive");
  Search search(wv, samples, rate_hz, lines, options);

  // The forward search with the curve's own spread as weights. Every
  // model it fits is kept (the lowest-WIC fit of each structure) for the
  // ranking.
  std::optional<TwinCandidate> at =
      search.fit(parse_composite_model("WN"), {}, search.sd_, std::max<std::size_t>(options.starts, 1), 0);
  if (!at)
    throw CalibrationError(CalibrationReason::degenerate,
                           "no white noise fits the curve (" + search.failed_.front() + ")");
  const SearchTrail trail = forward_search(search, std::move(*at), options);

  TwinSelection sel;
  std::vector<CandidateFit> scored;
  std::vector<TwinCandidate> refit;
  refit_with_common_weights(search, wv, trail, scored, refit);
  sel.failed = search.failed_;
  if (refit.empty())
    throw CalibrationError(CalibrationReason::degenerate,
                           "no model of the twin's search kept a fit with common weights (" + sel.failed.front() + ")");
  rank_twins(sel, scored, refit, options);
  return sel;
}

}  // namespace cubecal
