// `cubecal model` (pipeline/model_fit.hpp; docs/formulas/noise-terms.md §8a-8b).
#include "cubecal/pipeline/model_fit.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "cubecal/error.hpp"
#include "cubecal/sim/composite_simulator.hpp"

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
  }
  return {};
}

std::string raw_unit(const std::string& name, const std::string& u) {
  if (name == "N") return u + "*sqrt(s)";
  if (name == "Q") return u + "*s";
  if (name == "K") return u + "/sqrt(s)";
  if (name == "R") return u + "/s";
  if (name == "T_c") return "s";
  return u;  // sigma_b
}

Quantity shown(const std::string& name, double value, double sd, const Unit& unit) {
  if (name == "T_c") return {value, sd, "s"};
  const Term term = name == "N"   ? Term::N
                    : name == "Q" ? Term::Q
                    : name == "K" ? Term::K
                    : name == "R" ? Term::R
                                  : Term::B;  // sigma_b: a bias, in the bias instability's unit
  TermEstimate t;
  t.valid = true;
  t.value = value;
  t.sigma = sd;
  return display(t, term, unit);
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(at));
  const std::size_t j = std::min(i + 1, v.size() - 1);
  return v[i] + (at - static_cast<double>(i)) * (v[j] - v[i]);
}

}  // namespace

ModelResult run_model(const io::Series& series, const ModelRequest& req) {
  const CompositeModel structure = parse_composite_model(req.model);
  if (!(req.ci > 0.0 && req.ci < 1.0)) throw UsageError("ci", "the confidence must lie between 0 and 1");
  if (req.bootstrap == 1 || req.bootstrap > 100000)
    throw UsageError("bootstrap", "give 0 (none) or 2 to 100000 bootstrap replicates, not " +
                                      std::to_string(req.bootstrap));
  const std::size_t nch = series.channels.size();
  if (req.units.size() > 1 && req.units.size() != nch)
    throw UsageError("units", "give one unit for all channels or one per channel (" +
                                  std::to_string(req.units.size()) + " units for " + std::to_string(nch) +
                                  " channels)");
  if (series.segments.size() > 1)
    throw UsageError("segments", series.file + ": the record is cut into " + std::to_string(series.segments.size()) +
                                     " pieces at gaps; the wavelet variance needs one contiguous record (fit a "
                                     "piece, or repair the gaps)");
  ModelResult r;
  r.file = series.file;
  r.rate_hz = series.rate_hz;
  r.samples = series.samples();
  r.model = model_name(structure);
  r.ci = req.ci;
  r.bootstrap = req.bootstrap;
  r.seed = req.seed;
  const double dt = 1.0 / series.rate_hz;
  const int threads = req.threads > 0 ? static_cast<int>(req.threads) : omp_get_max_threads();

  // The fits, one channel per thread.
  r.channels.resize(nch);
  std::vector<std::exception_ptr> failure(nch);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (std::size_t c = 0; c < nch; ++c) {
    try {
      ModelChannel& ch = r.channels[c];
      ch.name = series.names[c];
      if (!req.units.empty()) ch.unit = req.units.size() == 1 ? req.units[0] : req.units[c];
      ch.wv = wavelet_variance(series.channels[c], req.ci);
      ch.fit = fit_gmwm(ch.wv, structure, req.gmwm);
    } catch (...) {
      failure[c] = std::current_exception();
    }
  }
  for (const auto& e : failure)
    if (e) std::rethrow_exception(e);

  // The parametric bootstrap: every (channel, replicate) on its own seed,
  // so that the result does not depend on the threads.
  const std::size_t reps = req.bootstrap;
  std::vector<std::vector<std::vector<double>>> draws(nch);  // [channel][replicate] -> quantities in term order
  for (std::size_t c = 0; c < nch; ++c) draws[c].resize(reps);
  if (reps > 0) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (std::size_t k = 0; k < nch * reps; ++k) {
      const std::size_t c = k / reps, b = k % reps;
      const ModelChannel& ch = r.channels[c];
      try {
        const std::vector<double> y = simulate_composite(ch.fit.model, r.samples, req.seed + 1000003ULL * c + b);
        const WaveletVariance wv = wavelet_variance(y, req.ci, ch.wv.size());
        GmwmOptions opt = req.gmwm;
        opt.start = ch.fit.model;
        const GmwmFit f = fit_gmwm(wv, structure, opt);
        std::vector<double> q;
        for (const Process& p : f.model.processes)
          for (const auto& [name, v] : physical(p, dt)) q.push_back(v);
        draws[c][b] = std::move(q);
      } catch (const std::exception&) {
        // A replicate without a fit is left out and counted.
      }
    }
  }

  const Unit u_shown{"u", SensorKind::generic, 1.0, "u"};
  for (std::size_t c = 0; c < nch; ++c) {
    ModelChannel& ch = r.channels[c];
    const Unit& unit = ch.unit.name.empty() ? u_shown : ch.unit;
    std::vector<std::vector<double>> per_quantity;
    for (const auto& d : draws[c]) {
      if (d.empty()) continue;
      ++ch.replicates;
      if (per_quantity.empty()) per_quantity.resize(d.size());
      for (std::size_t i = 0; i < d.size(); ++i) per_quantity[i].push_back(d[i]);
    }
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
          q.lo = quantile(s, 0.5 * (1.0 - req.ci));
          q.hi = quantile(s, 0.5 * (1.0 + req.ci));
        }
        q.display = shown(name, v, q.sd, unit);
        // Every display unit is a factor on the data unit and seconds.
        const double factor = v != 0.0 ? q.display.value / v : 1.0;
        q.display_lo = q.lo * factor;
        q.display_hi = q.hi * factor;
        t.quantities.push_back(std::move(q));
        ++qi;
      }
      ch.terms.push_back(std::move(t));
    }
  }
  return r;
}

}  // namespace cubecal::pipeline
