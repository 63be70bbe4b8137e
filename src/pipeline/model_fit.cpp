// `cubecal model` (pipeline/model_fit.hpp; docs/formulas/noise-terms.md §8a-8b).
#include "cubecal/pipeline/model_fit.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <span>

#include "cubecal/error.hpp"
#include "cubecal/noise/gmwm_asymptotics.hpp"
#include "cubecal/pipeline/model_selection.hpp"
#include "cubecal/pipeline/welch_psd.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/robust_wavelet_variance.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

namespace {

// A term's physical quantities, in the data unit and seconds, from its
// per-sample parameters (composite_model.hpp).
std::vector<std::pair<std::string, double>> physical(const Process& p, double dt) {
  switch (p.kind) {
    case ProcessKind::wn: return {{"N", std::sqrt(p.value * dt)}};
    case ProcessKind::qn: return {{"Q", std::sqrt(p.value) * dt}};
    case ProcessKind::rw: return {{"K", std::sqrt(p.value / dt)}};
    case ProcessKind::dr: return {{"R", std::abs(p.value) / dt}};
    case ProcessKind::gm: {
      const GaussMarkovTerm g = gauss_markov_term(p, dt);
      return {{"sigma_b", g.sigma_b}, {"T_c", g.tau_c}};
    }
    case ProcessKind::ma1: {
      const MovingAverageTerm m = moving_average_term(p, dt);
      return {{"N", m.n}, {"theta", m.theta}};
    }
    case ProcessKind::sin: {
      const SineTerm l = sine_term(p, dt);
      return {{"A", l.amplitude}, {"f", l.frequency_hz}};
    }
  }
  return {};
}

std::string raw_unit(const std::string& name, const std::string& u) {
  if (name == "N") return u + "*sqrt(s)";
  if (name == "Q") return u + "*s";
  if (name == "K") return u + "/sqrt(s)";
  if (name == "R") return u + "/s";
  if (name == "T_c") return "s";
  if (name == "theta") return "";
  if (name == "f") return "Hz";
  return u;  // sigma_b, A
}

Quantity shown(const std::string& name, double value, double sd, const Unit& unit) {
  if (name == "T_c") return {value, sd, "s"};
  if (name == "theta") return {value, sd, ""};
  if (name == "f") return {value, sd, "Hz"};
  const Term term = name == "N"   ? Term::N
                    : name == "Q" ? Term::Q
                    : name == "K" ? Term::K
                    : name == "R" ? Term::R
                                  : Term::B;  // sigma_b, A: a bias, in the bias instability's unit
  TermEstimate t;
  t.valid = true;
  t.value = value;
  t.sigma = sd;
  return display(t, term, unit);
}

// The sandwich standard deviations of every term's quantities, in the
// order of physical(), by the delta method from the covariance of the
// fit's log-parameters (noise/gmwm_asymptotics.hpp): N, Q, K and R carry
// half the relative sd of their variance, T_c = dt / a that of a, and
// ln sigma_b = (ln sigma2 - ln(1 - e^-2a)) / 2; an MA1's
// ln N = ln sigma2 / 2 + ln(1 + theta) + const and theta = tanh z, so
// d ln N / dz = 1 - theta, d theta / dz = 1 - theta^2. NaN for all when the fit
// does not determine its parameters. `inflation`: 1, or 1 / efficiency for
// the robust wavelet variance (an upper bound of its variance's ratio).
std::vector<double> asymptotic_sds(const ModelChannel& ch, std::size_t samples, double dt, double inflation) {
  std::vector<double> out;
  try {
    const GmwmAsymptotics as = gmwm_asymptotics(ch.fit, ch.wv, samples, inflation);
    const auto C = [&](std::size_t i, std::size_t k) { return as.covariance(i, k); };
    std::size_t k = 0;
    for (const Process& p : ch.fit.model.processes) {
      const auto values = physical(p, dt);
      if (p.kind == ProcessKind::sin) {  // A = sqrt(value), f = omega / (2 pi dt), omega = pi / (1 + e^-z)
        out.push_back(0.5 * values[0].second * std::sqrt(C(k, k)));
        out.push_back(values[1].second * (1.0 - p.omega / std::numbers::pi) * std::sqrt(C(k + 1, k + 1)));
        k += 2;
        continue;
      }
      if (p.kind == ProcessKind::ma1) {
        const double g = 1.0 - p.theta;
        const double var_n = 0.25 * C(k, k) + g * C(k, k + 1) + g * g * C(k + 1, k + 1);
        out.push_back(values[0].second * std::sqrt(std::max(var_n, 0.0)));
        out.push_back((1.0 - p.theta * p.theta) * std::sqrt(C(k + 1, k + 1)));
        k += 2;
        continue;
      }
      if (p.kind != ProcessKind::gm) {
        out.push_back(0.5 * values[0].second * std::sqrt(C(k, k)));
        ++k;
        continue;
      }
      const double a = -std::log(p.phi);
      const double g = -a / std::expm1(2.0 * a);
      const double var_sigma_b = 0.25 * C(k, k) + g * C(k, k + 1) + g * g * C(k + 1, k + 1);
      out.push_back(values[0].second * std::sqrt(std::max(var_sigma_b, 0.0)));
      out.push_back(values[1].second * std::sqrt(C(k + 1, k + 1)));
      k += 2;
    }
  } catch (const CalibrationError&) {
    out.clear();
  }
  return out;
}

// The q-quantile of B replicates at the (B + 1) q-th order statistic,
// interpolated (Davison & Hinkley 1997, §5.2; Hyndman & Fan's type 6): a
// percentile interval then holds a further draw of the same law with the
// probability asked for. The (B - 1) q + 1 positions of type 7 narrow it:
// 95 % intervals from 40 replicates hold 90.4 %, from 100 93.1 %
// (docs/validation/gmwm-monte-carlo.md).
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() + 1) - 1.0;  // 0-based
  if (at <= 0.0) return v.front();
  if (at >= static_cast<double>(v.size() - 1)) return v.back();
  const auto i = static_cast<std::size_t>(std::floor(at));
  return v[i] + (at - static_cast<double>(i)) * (v[i + 1] - v[i]);
}

}  // namespace

bool is_twin(const std::string& model) {
  std::string t;
  for (char c : model)
    if (c != ' ' && c != '\t') t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return t == "twin";
}

ModelRequest twin_request() {
  ModelRequest m;
  m.model = "twin";
  return m;
}

namespace {

// The twin of a channel (noise/twin_selection.hpp): the lines of its Welch
// spectrum, the forward search, and the selected model refitted as a lone
// fit is (reweighted at its own curve) from its fit with the common weights.
void fit_twin(ModelChannel& ch, std::span<const double> y, double rate_hz, std::size_t samples,
              const ModelRequest& req) {
  try {
    ch.lines = find_spectral_lines(welch_psd(y, rate_hz));
  } catch (const UsageError& e) {
    ch.lines_error = face_words(e.text());  // a record too short for one segment
  }
  const TwinSelection sel = select_twin(ch.wv, samples, rate_hz, ch.lines, req.twin);
  for (const TwinCandidate& c : sel.ranked)
    ch.candidates.push_back({model_name(c.structure), parameter_count(c.structure), c.score, c.fit.objective});
  ch.failed = sel.failed;
  const TwinCandidate& chosen = sel.ranked.front();
  // The twin's parameters from the scales between the octaves too (a
  // line's curve swings between them; noise/twin_selection.hpp), refitted
  // as a lone fit is, from its fit with the common weights.
  if (!req.robust) ch.wv = wavelet_variance_at(y, octave_and_half_factors(y.size() / 4), req.ci);
  GmwmOptions refit = req.gmwm;
  refit.start = chosen.fit.model;
  ch.fit = fit_gmwm(ch.wv, chosen.structure, refit);
  ch.fidelity = twin_fidelity(ch.wv, ch.fit.nu2_model);
  // The reweighting weighs each scale at the model's own value, so a model
  // far above a scale of one or two degrees of freedom pays little for it:
  // on a short record the lone fit can rise above the last scales. The fit
  // with the curve's own spread as fixed weights is kept instead when it
  // lies inside at more scales (or as many, closer). Tried only when the
  // lone fit is not faithful.
  if (!twin_faithful(*ch.fidelity)) {
    GmwmOptions fixed = refit;
    for (std::size_t j = 0; j < ch.wv.size(); ++j)
      fixed.fixed_sd.push_back(ch.wv.nu2[j] * std::sqrt(2.0 / ch.wv.edf[j]));
    try {
      GmwmFit f = fit_gmwm(ch.wv, chosen.structure, fixed);
      const TwinFidelity ff = twin_fidelity(ch.wv, f.nu2_model);
      if (ff.inside > ch.fidelity->inside ||
          (ff.inside == ch.fidelity->inside && ff.max_error < ch.fidelity->max_error)) {
        ch.fit = std::move(f);
        ch.fidelity = ff;
      }
    } catch (const CalibrationError&) {
      // No fit with fixed weights: the lone fit stands.
    }
  }
  ch.faithful = twin_faithful(*ch.fidelity);
}

}  // namespace

namespace {

// The request's checks that need the record, before any work.
void check_model_request(const io::Series& series, const ModelRequest& req, bool selecting) {
  if (selecting && req.selection_replicates == 1)
    throw UsageError(Field::wic_replicates,
                     "give 0 (the WIC's asymptotic optimism) or at least 2 bootstrap replicates, not 1");
  if (!(req.ci > 0.0 && req.ci < 1.0)) throw UsageError(Field::ci, "the confidence must lie between 0 and 1");
  if (req.bootstrap == 1 || req.bootstrap > 100000)
    throw UsageError(Field::bootstrap,
                     "give 0 (none) or 2 to 100000 bootstrap replicates, not " + std::to_string(req.bootstrap));
  const std::size_t nch = series.channels.size();
  if (req.units.size() > 1 && req.units.size() != nch)
    throw UsageError(Field::units, "give one unit for all channels or one per channel (" +
                                       std::to_string(req.units.size()) + " units for " + std::to_string(nch) +
                                       " channels)");
  if (series.segments.size() > 1)
    throw UsageError(Field::segments, series.file + ": the record is cut into " +
                                          std::to_string(series.segments.size()) +
                                          " pieces at gaps; the wavelet variance needs one contiguous record (fit a "
                                          "piece, or repair the gaps)");
}

// The result's record and settings, without its channels.
ModelResult model_settings(const io::Series& series, const ModelRequest& req,
                           const std::vector<CompositeModel>& candidates, bool twin, bool selecting) {
  ModelResult r;
  r.file = series.file;
  r.rate_hz = series.rate_hz;
  r.samples = series.samples();
  for (const CompositeModel& m : candidates) {
    if (twin) {
      r.model = "twin";
      break;
    }
    if (!r.model.empty()) r.model += ',';
    r.model += model_name(m);
  }
  r.selection_replicates = selecting ? req.selection_replicates : 0;
  r.ci = req.ci;
  r.bootstrap = req.bootstrap;
  r.seed = req.seed;
  r.robust = req.robust;
  r.robust_efficiency = req.robust_efficiency;
  return r;
}

// The channel's and every replicate's wavelet variance, robust on request.
WaveletVariance wavelet_variance_of(std::span<const double> y, std::size_t scales, const ModelRequest& req) {
  return req.robust ? robust_wavelet_variance(y, req.ci, req.robust_efficiency, scales)
                    : wavelet_variance(y, req.ci, scales);
}

// A selection among the candidates (their replicates on the threads), the
// selected model refitted as a lone fit is (reweighted at its own curve),
// from its fit with the common weights; returns the selected structure.
CompositeModel select_and_refit(ModelChannel& ch, std::size_t samples, const std::vector<CompositeModel>& candidates,
                                const ModelRequest& req, int threads) {
  WicOptions wo;
  wo.replicates = req.selection_replicates;
  wo.seed = req.seed;
  wo.gmwm = req.gmwm;
  wo.threads = static_cast<unsigned>(threads);
  wo.robust_efficiency = req.robust ? req.robust_efficiency : 0.0;
  ModelSelection sel = select_composite_model(ch.wv, samples, candidates, wo);
  for (const CandidateFit& cf : sel.ranked) {
    ch.candidates.push_back({model_name(cf.structure), parameter_count(cf.structure), cf.score, cf.fit.objective});
  }
  ch.failed = std::move(sel.failed);
  // The selected model refitted as a lone fit is (reweighted at
  // its own curve), from its fit with the common weights.
  CompositeModel structure = sel.ranked.front().structure;
  GmwmOptions refit = req.gmwm;
  refit.start = sel.ranked.front().fit.model;
  ch.fit = fit_gmwm(ch.wv, structure, refit);
  return structure;
}

// The fits, one channel per thread; a selection, one channel at a time
// with the candidates and their replicates on the threads. Returns each
// channel's fitted structure.
std::vector<CompositeModel> fit_channels(ModelResult& r, const io::Series& series, const ModelRequest& req,
                                         const std::vector<CompositeModel>& candidates, bool twin, bool selecting,
                                         int threads) {
  const std::size_t nch = series.channels.size();
  r.channels.resize(nch);
  std::vector<CompositeModel> structure(nch, candidates.front());
  cubecal::detail::for_channels(nch, cubecal::detail::Team{selecting ? 1 : threads}, [&](std::size_t c) {
    ModelChannel& ch = r.channels[c];
    ch.name = series.names[c];
    if (!req.units.empty()) ch.unit = req.units.size() == 1 ? req.units[0] : req.units[c];
    ch.wv = wavelet_variance_of(series.channels[c], 0, req);
    if (twin) {
      fit_twin(ch, series.channels[c], series.rate_hz, r.samples, req);
      structure[c] = ch.fit.model;
    } else if (!selecting) {
      ch.fit = fit_gmwm(ch.wv, structure[c], req.gmwm);
    } else {
      structure[c] = select_and_refit(ch, r.samples, candidates, req, threads);
    }
    ch.model = model_name(structure[c]);
  });
  return structure;
}

// The parametric bootstrap: every (channel, replicate) on its own seed,
// so that the result does not depend on the threads. Returns
// [channel][replicate] -> quantities in term order (empty: no fit).
std::vector<std::vector<std::vector<double>>> bootstrap_draws(const ModelResult& r,
                                                              const std::vector<CompositeModel>& structure,
                                                              const ModelRequest& req, bool twin, int threads) {
  const std::size_t nch = r.channels.size();
  const double dt = 1.0 / r.rate_hz;
  const std::size_t reps = req.bootstrap;
  std::vector<std::vector<std::vector<double>>> draws(nch);  // [channel][replicate] -> quantities in term order
  for (std::size_t c = 0; c < nch; ++c) draws[c].resize(reps);
  const std::size_t total = nch * reps;
  std::atomic<std::size_t> done{0};
  std::size_t reported = 0;  // touched by the calling thread (OpenMP thread 0) only
  const auto report = [&] {
    if (!req.bootstrap_progress || omp_get_thread_num() != 0) return;
    const std::size_t now = done.load();
    if (now <= reported) return;
    reported = now;
    req.bootstrap_progress(now, total);
  };
  if (reps > 0) {
    if (req.bootstrap_progress) req.bootstrap_progress(0, total);
    cubecal::detail::for_channels(nch * reps, cubecal::detail::Team{threads}, [&](std::size_t k) {
      const std::size_t c = k / reps, b = k % reps;
      const ModelChannel& ch = r.channels[c];
      try {
        const std::vector<double> y = simulate_composite(ch.fit.model, r.samples, req.seed + 1000003ULL * c + b);
        // At the channel's scales (a twin's: the octaves and the half-octaves between).
        std::vector<std::size_t> ms;
        for (double t : ch.wv.tau) ms.push_back(static_cast<std::size_t>(t / 2.0));
        const WaveletVariance wv =
            twin && !req.robust ? wavelet_variance_at(y, ms, req.ci) : wavelet_variance_of(y, ch.wv.size(), req);
        GmwmOptions opt = req.gmwm;
        opt.start = ch.fit.model;
        const GmwmFit f = fit_gmwm(wv, structure[c], opt);
        std::vector<double> q;
        for (const Process& p : f.model.processes)
          for (const auto& [name, v] : physical(p, dt)) q.push_back(v);
        draws[c][b] = std::move(q);
      } catch (const std::exception&) {
        // A replicate without a fit is left out and counted.
      }
      done.fetch_add(1);
      report();
    });
    report();  // the last replicates may have ended on other threads
  }
  return draws;
}

// The channel's terms: each quantity with its display value and, from the
// replicates with a fit, its spread and interval.
void model_terms(ModelChannel& ch, const std::vector<std::vector<double>>& draws, std::size_t samples, double dt,
                 const ModelRequest& req) {
  const Unit u_shown{"u", SensorKind::generic, 1.0, "u"};
  const Unit& unit = ch.unit.name.empty() ? u_shown : ch.unit;
  std::vector<std::vector<double>> per_quantity;
  for (const auto& d : draws) {
    if (d.empty()) continue;
    ++ch.replicates;
    if (per_quantity.empty()) per_quantity.resize(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) per_quantity[i].push_back(d[i]);
  }
  const std::vector<double> asym = asymptotic_sds(ch, samples, dt, req.robust ? 1.0 / req.robust_efficiency : 1.0);
  std::size_t qi = 0;
  for (const Process& p : ch.fit.model.processes) {
    ModelTerm t;
    t.kind = p.kind;
    t.process = p;
    for (const auto& [name, v] : physical(p, dt)) {
      ModelQuantity q;
      q.name = name;
      q.value = v;
      q.unit = raw_unit(name, unit.name);
      if (ch.replicates >= 2) {
        const std::vector<double>& s = per_quantity[qi];
        double mean = 0.0, var = 0.0;
        for (double x : s) mean += x;
        mean /= static_cast<double>(s.size());
        for (double x : s) var += (x - mean) * (x - mean);
        q.sd = std::sqrt(var / static_cast<double>(s.size() - 1));
        q.interval = {quantile(s, 0.5 * (1.0 - req.ci)), quantile(s, 0.5 * (1.0 + req.ci))};
      }
      q.display = shown(name, v, q.sd, unit);
      // Every display unit is a factor on the data unit and seconds.
      const double factor = v != 0.0 ? q.display.value / v : 1.0;
      q.display_interval = {q.interval.lo * factor, q.interval.hi * factor};
      q.asymptotic_sd = qi < asym.size() ? asym[qi] : std::numeric_limits<double>::quiet_NaN();
      q.display_asymptotic_sd = q.asymptotic_sd * factor;
      t.quantities.push_back(std::move(q));
      ++qi;
    }
    ch.terms.push_back(std::move(t));
  }
}

}  // namespace

ModelResult run_model(const io::Series& series, const ModelRequest& req) {
  const bool twin = is_twin(req.model);
  const std::vector<CompositeModel> candidates =
      twin ? std::vector<CompositeModel>{CompositeModel{}} : parse_candidate_models(req.model);
  const bool selecting = !twin && candidates.size() > 1;
  check_model_request(series, req, selecting);
  ModelResult r = model_settings(series, req, candidates, twin, selecting);
  if (req.robust) (void)biweight_tuning(req.robust_efficiency);  // an efficiency out of range fails before the work
  const double dt = 1.0 / series.rate_hz;
  const int threads = req.threads > 0 ? static_cast<int>(req.threads) : omp_get_max_threads();
  const std::vector<CompositeModel> structure = fit_channels(r, series, req, candidates, twin, selecting, threads);
  const auto draws = bootstrap_draws(r, structure, req, twin, threads);
  for (std::size_t c = 0; c < r.channels.size(); ++c) model_terms(r.channels[c], draws[c], r.samples, dt, req);
  return r;
}

}  // namespace cubecal::pipeline
