// Monte Carlo validation of the GMWM by truth (issue 16, item 4): seeded
// records of a known composite process (sim/composite_simulator.hpp) are
// fitted as `cubecal model` fits them (pipeline::run_model: the Haar wavelet
// variance, the GMWM fit, the parametric-bootstrap percentile intervals), and
// the IEEE 952 route (the OADEV curve as `analyze` takes it, the weighted
// five-term fit and the slope read-offs) is run on the same records. Per
// model and record length it prints Markdown tables of each physical
// quantity's truth, mean, bias, the bias's Monte Carlo standard error
// (sd / sqrt(seeds)), bias / SE, the Monte Carlo spread and, with a
// bootstrap, the share of seeds whose interval holds the truth; with
// --mode select, the share of seeds in which the Wavelet Information
// Criterion (noise/wic.hpp) picks the true model among
// default_candidate_models(). docs/validation/gmwm-monte-carlo.md has the
// results and the commands.
//
//   gmwm_monte_carlo [--mode fit|select] [--model all|WN+RW,WN+GM,WN+2*GM+RW,WN+QN+GM]
//                    [--samples 100000,1000000] [--seeds 100] [--first-seed 1]
//                    [--bootstrap B] [--ci 0.95] [--selection-replicates R]
//                    [--threads T] [--natural] [--raw FILE.jsonl] [--rw-k K]
//
// The true models carry the per-sample parameters of tests/test_gmwm.cpp
// (unit u, one sample per second: N in u sqrt(s) equals the white noise's
// per-sample standard deviation, T_c is in samples). Record seed s draws the
// record; its bootstrap replicate b draws from 1e9 + 1e4 s + b, the
// selection's replicates from 2e9 + 1e3 s + b, so no replicate shares its
// innovations with a record. Seeds run in parallel (one per thread), each
// seed's fit, bootstrap and selection on its thread; the results do not
// depend on the thread count.
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/model_selection.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace {

using namespace cubecal;

constexpr double kDt = 1.0;  // s: the per-sample parameters are the physical ones

const std::vector<std::string> kModels = {"WN+RW", "WN+GM", "WN+2*GM+RW", "WN+QN+GM"};

// --rw-k: the random walk's K (per sample) of the truths that have one,
// instead of their own (how selection depends on the random walk's share
// of the longest scales).
double g_rw_k = 0.0;

// The true processes (tests/test_gmwm.cpp): white noise of unit variance,
// quantization half of it, a random walk that crosses the white noise at
// tau ~ 1.7e3 samples (WN+RW) or ~1.7e4 (beside Gauss-Markov terms),
// Gauss-Markov biases of T_c 40 and 4000 samples (WN+2*GM+RW) or 600.
CompositeModel truth(const std::string& name) {
  if (std::find(kModels.begin(), kModels.end(), name) == kModels.end())
    throw std::invalid_argument("--model: " + name + " is not one of WN+RW, WN+GM, WN+2*GM+RW, WN+QN+GM (or all)");
  CompositeModel m = parse_composite_model(name);
  std::size_t gm = 0;
  for (Process& p : m.processes) {
    switch (p.kind) {
      case ProcessKind::wn: p.value = 1.0; break;
      case ProcessKind::qn: p.value = 0.5; break;
      case ProcessKind::rw: p.value = g_rw_k > 0.0 ? g_rw_k * g_rw_k : name == "WN+RW" ? 1e-6 : 1e-8; break;
      case ProcessKind::dr: p.value = 1e-5; break;
      case ProcessKind::gm:
        p = gm == 0 ? gm_process(name == "WN+2*GM+RW" ? 40.0 : 600.0, name == "WN+2*GM+RW" ? 0.3 : 0.25, kDt)
                    : gm_process(4000.0, 0.15, kDt);
        ++gm;
        break;
      case ProcessKind::ma1:
      case ProcessKind::sin: break;  // in none of kModels
    }
  }
  return m;
}

// The physical quantities of a model, in run_model's order (each term's, GM:
// sigma_b then T_c), numbered when the model has several Gauss-Markov terms.
struct Named {
  std::string name;
  double value = 0.0;
};

std::vector<Named> physical(const CompositeModel& m) {
  const auto gms =
      std::count_if(m.processes.begin(), m.processes.end(), [](const Process& p) { return p.kind == ProcessKind::gm; });
  std::vector<Named> out;
  int g = 0;
  for (const Process& p : m.processes) {
    switch (p.kind) {
      case ProcessKind::wn: out.push_back({"N", std::sqrt(p.value * kDt)}); break;
      case ProcessKind::qn: out.push_back({"Q", std::sqrt(p.value) * kDt}); break;
      case ProcessKind::rw: out.push_back({"K", std::sqrt(p.value / kDt)}); break;
      case ProcessKind::dr: out.push_back({"R", std::abs(p.value) / kDt}); break;
      case ProcessKind::gm: {
        const GaussMarkovTerm t = gauss_markov_term(p, kDt);
        const std::string k = gms > 1 ? std::to_string(++g) : "";
        out.push_back({"sigma_b" + k, t.sigma_b});
        out.push_back({"T_c" + k, t.tau_c});
        break;
      }
      case ProcessKind::ma1: {
        const MovingAverageTerm t = moving_average_term(p, kDt);
        out.push_back({"N", t.n});
        out.push_back({"theta", t.theta});
        break;
      }
      case ProcessKind::sin: {
        const SineTerm t = sine_term(p, kDt);
        out.push_back({"A", t.amplitude});
        out.push_back({"f", t.frequency_hz});
        break;
      }
    }
  }
  return out;
}

// The fit's own per-sample parameters (--natural): each term's variance (DR:
// omega) and a Gauss-Markov term's a = -ln(phi), the parameters the fit moves.
std::vector<Named> natural(const CompositeModel& m) {
  const auto gms =
      std::count_if(m.processes.begin(), m.processes.end(), [](const Process& p) { return p.kind == ProcessKind::gm; });
  std::vector<Named> out;
  int g = 0;
  for (const Process& p : m.processes) {
    const std::string kind(to_string(p.kind));
    if (p.kind == ProcessKind::gm) {
      const std::string k = gms > 1 ? std::to_string(++g) : "";
      out.push_back({"GM" + k + " sigma2", p.value});
      out.push_back({"GM" + k + " a", -std::log(p.phi)});
    } else {
      out.push_back({kind + (p.kind == ProcessKind::dr   ? " omega"
                             : p.kind == ProcessKind::rw ? " gamma2"
                             : p.kind == ProcessKind::qn ? " Q2"
                                                         : " sigma2"),
                     p.value});
    }
  }
  return out;
}

// One estimate of one quantity on one record.
struct Estimate {
  bool valid = false;
  double value = 0.0;
  double lo = 0.0, hi = 0.0, sd = 0.0;  // GMWM with a bootstrap
};

struct SeedResult {
  bool ok = false;
  std::string error;
  std::vector<Estimate> gmwm;                    // physical(truth) order
  std::vector<Estimate> gmwm_natural;            // natural(truth) order
  std::map<std::string, Estimate> fit, readoff;  // IEEE 952: N, K, Q
  std::size_t replicates = 0;
  bool converged = false;
  std::string selected;        // --mode select
  std::size_t truth_rank = 0;  // 1: selected
  nlohmann::json ranking;
  double seconds = 0.0;
};

struct Options {
  std::string mode = "fit";
  std::vector<std::string> models = kModels;
  std::vector<std::size_t> samples = {100000, 1000000};
  std::size_t seeds = 100;
  std::uint64_t first_seed = 1;
  std::size_t bootstrap = 0;
  double ci = 0.95;
  std::size_t selection_replicates = 50;
  unsigned threads = 0;
  bool natural = false;
  std::string raw;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string piece;
  while (std::getline(in, piece, ','))
    if (!piece.empty()) out.push_back(piece);
  return out;
}

std::size_t count_of(const std::string& flag, const std::string& v) {
  std::size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || !(x >= 0.0) || x != std::floor(x) || x > 1e12)
    throw std::invalid_argument(flag + ": '" + v + "' is not a whole number (1e6 and 1000000 both work)");
  return static_cast<std::size_t>(x);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--natural") {
      o.natural = true;
      continue;
    }
    if (i + 1 >= argc) throw std::invalid_argument(a + ": needs a value (see the comment at the top of the source)");
    const std::string v = argv[++i];
    if (a == "--mode") {
      if (v != "fit" && v != "select") throw std::invalid_argument("--mode: give fit or select, not " + v);
      o.mode = v;
    } else if (a == "--model") {
      o.models = v == "all" ? kModels : split(v);
      for (auto& m : o.models) m = model_name(parse_composite_model(m));
      for (const auto& m : o.models) (void)truth(m);
    } else if (a == "--samples") {
      o.samples.clear();
      for (const auto& s : split(v)) o.samples.push_back(count_of(a, s));
    } else if (a == "--seeds") {
      o.seeds = count_of(a, v);
    } else if (a == "--first-seed") {
      o.first_seed = count_of(a, v);
    } else if (a == "--bootstrap") {
      o.bootstrap = count_of(a, v);
    } else if (a == "--ci") {
      o.ci = std::stod(v);
    } else if (a == "--selection-replicates") {
      o.selection_replicates = count_of(a, v);
    } else if (a == "--threads") {
      o.threads = static_cast<unsigned>(count_of(a, v));
    } else if (a == "--raw") {
      o.raw = v;
    } else if (a == "--rw-k") {
      g_rw_k = std::stod(v);
      if (!(g_rw_k > 0.0)) throw std::invalid_argument("--rw-k: give a positive K per sample, not " + v);
    } else {
      throw std::invalid_argument(a + ": unknown option (see the comment at the top of the source)");
    }
  }
  if (o.seeds < 2) throw std::invalid_argument("--seeds: give at least 2 seeds (a spread needs two)");
  for (std::size_t n : o.samples)
    if (n < 1024) throw std::invalid_argument("--samples: give at least 1024 samples per record");
  return o;
}

Estimate of(const TermEstimate& t) {
  Estimate e;
  e.valid = t.valid && std::isfinite(t.value);
  e.value = t.value;
  return e;
}

// The IEEE 952 route as `cubecal analyze` takes it: the OADEV on the log:10
// grid with 68.3 % intervals (conservative below 30 averages), then the
// five-term fit and the slope read-offs of the curve.
void ieee952(const std::vector<double>& y, const CompositeModel& m, SeedResult& r) {
  const StabilityRecord rec(y, DataType::freq, kDt, Stat::oadev);
  const std::vector<std::size_t> ms =
      averaging_factors(parse_tau_grid("log:10"), rec.max_m(), kDt * tau_per_factor(Stat::oadev));
  StabilityOptions so;
  so.ci = 0.683;
  so.conservative_short = true;
  const AllanCurve curve = to_allan_curve(rec.evaluate(ms, so));
  const NoiseFit f = fit_noise_terms(curve);
  const SlopeReadOffs ro = read_off_noise_terms(curve);
  r.fit["N"] = of(f.N);
  r.readoff["N"] = of(ro.N);
  for (const Process& p : m.processes) {
    if (p.kind == ProcessKind::rw) {
      r.fit["K"] = of(f.K);
      r.readoff["K"] = of(ro.K);
    }
    if (p.kind == ProcessKind::qn) {
      r.fit["Q"] = of(f.Q);
      r.readoff["Q"] = of(ro.Q);
    }
  }
}

SeedResult run_seed(const Options& o, const std::string& name, std::size_t n, std::uint64_t seed) {
  SeedResult r;
  const double t0 = omp_get_wtime();
  try {
    const CompositeModel m = truth(name);
    std::vector<double> y = simulate_composite(m, n, seed);
    if (o.mode == "select") {
      const WaveletVariance wv = wavelet_variance(y, 0.95);
      pipeline::WicOptions wo;
      wo.replicates = o.selection_replicates;
      wo.seed = 2'000'000'000ULL + 1000ULL * seed;
      wo.threads = 1;
      const pipeline::ModelSelection sel = pipeline::select_composite_model(wv, n, default_candidate_models(), wo);
      r.selected = model_name(sel.ranked.front().structure);
      r.ranking = nlohmann::json::array();
      for (std::size_t i = 0; i < sel.ranked.size(); ++i) {
        const CandidateFit& c = sel.ranked[i];
        if (model_name(c.structure) == name) r.truth_rank = i + 1;
        r.ranking.push_back(nlohmann::json{{"model", model_name(c.structure)},
                                           {"wic", c.score.wic},
                                           {"loss", c.score.loss},
                                           {"optimism", c.score.optimism}});
      }
      for (const auto& f : sel.failed) r.ranking.push_back(nlohmann::json{{"failed", f}});
    } else {
      ieee952(y, m, r);
      io::Series s;
      s.file = "simulated";
      s.rate_hz = 1.0 / kDt;
      s.tau0 = kDt;
      s.names = {"y"};
      s.segments = {IndexRange{0, n}};
      s.channels.push_back(std::move(y));
      pipeline::ModelRequest req;
      req.model = name;
      req.ci = o.ci;
      req.bootstrap = o.bootstrap;
      req.seed = 1'000'000'000ULL + 10'000ULL * seed;
      req.threads = 1;
      const pipeline::ModelResult fit = pipeline::run_model(s, req);
      const pipeline::ModelChannel& ch = fit.channels.at(0);
      r.converged = ch.fit.converged;
      r.replicates = ch.replicates;
      for (const auto& t : ch.terms)
        for (const auto& q : t.quantities) {
          Estimate e;
          e.valid = std::isfinite(q.value);
          e.value = q.value;
          e.lo = q.interval.lo;
          e.hi = q.interval.hi;
          e.sd = q.sd;
          r.gmwm.push_back(e);
        }
      for (const auto& q : natural(ch.fit.model)) r.gmwm_natural.push_back({true, q.value, 0.0, 0.0, 0.0});
    }
    r.ok = true;
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  r.seconds = omp_get_wtime() - t0;
  return r;
}

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

struct Summary {
  std::size_t valid = 0;
  double mean = 0.0, sd = 0.0, median = 0.0;
  double se() const { return valid > 1 ? sd / std::sqrt(static_cast<double>(valid)) : 0.0; }
};

Summary summarise(std::vector<double> v) {
  Summary s;
  s.valid = v.size();
  if (v.empty()) return s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  s.median = v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
  return s;
}

// One row of a bias table: truth, mean, bias, SE, bias / SE, MC sd, median,
// bias relative to the truth, and whether |bias| < 2 SE.
std::string bias_cells(double truth, const Summary& s) {
  const double bias = s.mean - truth, se = s.se();
  const double z = se > 0.0 ? bias / se : 0.0;
  return num(truth) + " | " + num(s.mean) + " | " + num(bias) + " | " + num(se) + " | " + fixed(z, 2) + " | " +
         num(s.sd) + " | " + num(s.median) + " | " + fixed(100.0 * bias / truth, 2) + " % | " +
         (std::abs(z) < 2.0 ? "yes" : "**no**");
}

void report_fit(const Options& o, const std::string& name, const std::vector<SeedResult>& res) {
  const CompositeModel m = truth(name);
  const std::vector<Named> q = physical(m);
  std::vector<const SeedResult*> ok;
  std::size_t unconverged = 0, replicates = 0;
  for (const auto& r : res) {
    if (!r.ok) continue;
    ok.push_back(&r);
    unconverged += !r.converged;
    replicates += r.replicates;
  }
  std::printf("\nGMWM fits: %zu of %zu seeds (%zu whose last Levenberg-Marquardt run met no convergence test)",
              ok.size(), res.size(), unconverged);
  if (o.bootstrap > 0)
    std::printf("; bootstrap replicates with a fit: %zu of %zu", replicates, ok.size() * o.bootstrap);
  std::printf(".\n\n");
  std::printf("| quantity | truth | mean | bias | SE | bias/SE | MC sd | median | bias/truth | within 2 SE |%s\n",
              o.bootstrap > 0 ? " coverage | mean bootstrap sd |" : "");
  std::printf("|---|---|---|---|---|---|---|---|---|---|%s\n", o.bootstrap > 0 ? "---|---|" : "");
  for (std::size_t i = 0; i < q.size(); ++i) {
    std::vector<double> v, bsd;
    std::size_t covered = 0, intervals = 0;
    for (const SeedResult* r : ok) {
      if (i >= r->gmwm.size() || !r->gmwm[i].valid) continue;
      v.push_back(r->gmwm[i].value);
      if (o.bootstrap > 0 && r->replicates >= 2) {
        ++intervals;
        covered += r->gmwm[i].lo <= q[i].value && q[i].value <= r->gmwm[i].hi;
        bsd.push_back(r->gmwm[i].sd);
      }
    }
    std::printf("| %s | %s |", q[i].name.c_str(), bias_cells(q[i].value, summarise(v)).c_str());
    if (o.bootstrap > 0) {
      const double rate = intervals ? static_cast<double>(covered) / static_cast<double>(intervals) : 0.0;
      const bool in = rate >= 0.90 && rate <= 0.98;
      std::printf(" %zu/%zu = %s %%%s | %s |", covered, intervals, fixed(100.0 * rate, 0).c_str(),
                  in ? "" : " (**outside 90-98 %**)", num(summarise(bsd).mean).c_str());
    }
    std::printf("\n");
  }
  if (o.natural) {
    const std::vector<Named> p = natural(m);
    std::printf("\nThe fit's per-sample parameters:\n\n");
    std::printf("| parameter | truth | mean | bias | SE | bias/SE | MC sd | median | bias/truth | within 2 SE |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    for (std::size_t i = 0; i < p.size(); ++i) {
      std::vector<double> v;
      for (const SeedResult* r : ok)
        if (i < r->gmwm_natural.size()) v.push_back(r->gmwm_natural[i].value);
      std::printf("| %s | %s |\n", p[i].name.c_str(), bias_cells(p[i].value, summarise(v)).c_str());
    }
  }

  // The IEEE 952 route on the same records, beside the GMWM.
  std::printf("\nIEEE 952 on the same records (OADEV log:10, 68.3 %% intervals) beside the GMWM:\n\n");
  std::printf(
      "| quantity | estimator | valid | truth | mean | bias | SE | bias/SE | MC sd | median | bias/truth | "
      "within 2 SE | RMSE/truth |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const char* qn : {"N", "Q", "K"}) {
    std::size_t qi = q.size();
    for (std::size_t i = 0; i < q.size(); ++i)
      if (q[i].name == qn) qi = i;
    if (qi == q.size()) continue;
    const double t = q[qi].value;
    const auto row = [&](const char* est, const std::vector<double>& v) {
      const Summary s = summarise(v);
      if (s.valid == 0) {
        std::printf("| %s | %s | 0/%zu | %s | - | - | - | - | - | - | - | - | - |\n", qn, est, ok.size(),
                    num(t).c_str());
        return;
      }
      const double rmse =
          std::sqrt((s.mean - t) * (s.mean - t) + s.sd * s.sd * static_cast<double>(s.valid - 1) /
                                                      static_cast<double>(std::max<std::size_t>(s.valid, 1)));
      std::printf("| %s | %s | %zu/%zu | %s | %s |\n", qn, est, s.valid, ok.size(), bias_cells(t, s).c_str(),
                  s.valid ? fixed(100.0 * rmse / t, 2).append(" %").c_str() : "-");
    };
    std::vector<double> g, f, r;
    for (const SeedResult* s : ok) {
      if (qi < s->gmwm.size() && s->gmwm[qi].valid) g.push_back(s->gmwm[qi].value);
      if (const auto it = s->fit.find(qn); it != s->fit.end() && it->second.valid) f.push_back(it->second.value);
      if (const auto it = s->readoff.find(qn); it != s->readoff.end() && it->second.valid)
        r.push_back(it->second.value);
    }
    row("GMWM", g);
    row("IEEE 952 five-term fit", f);
    row("IEEE 952 slope read-off", r);
  }
}

void report_select(const Options& o, const std::string& name, const std::vector<SeedResult>& res) {
  std::size_t ok = 0, right = 0;
  std::map<std::string, std::size_t> picks;
  std::map<std::size_t, std::size_t> ranks;
  for (const auto& r : res) {
    if (!r.ok) continue;
    ++ok;
    right += r.selected == name;
    ++picks[r.selected];
    ++ranks[r.truth_rank];
  }
  const double rate = ok ? static_cast<double>(right) / static_cast<double>(ok) : 0.0;
  std::printf(
      "\nSelection among default_candidate_models() (WIC, %zu replicates per candidate): the true %s "
      "picked in %zu of %zu seeds = %s %%.\n\n",
      o.selection_replicates, name.c_str(), right, ok, fixed(100.0 * rate, 0).c_str());
  std::printf("| selected | seeds |\n|---|---|\n");
  std::vector<std::pair<std::string, std::size_t>> sorted(picks.begin(), picks.end());
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  for (const auto& [model, count] : sorted)
    std::printf("| %s%s | %zu |\n", model.c_str(), model == name ? " (true)" : "", count);
  std::printf("\nRank of the true model: ");
  for (const auto& [rank, count] : ranks)
    std::printf("%s%s: %zu; ", rank == 0 ? "no fit" : "rank ", rank == 0 ? "" : std::to_string(rank).c_str(), count);
  std::printf("\n");
}

nlohmann::json raw_line(const Options& o, const std::string& name, std::size_t n, std::uint64_t seed,
                        const SeedResult& r) {
  nlohmann::json j = {{"model", name}, {"samples", n}, {"seed", seed}, {"seconds", r.seconds}, {"ok", r.ok}};
  if (!r.ok) {
    j["error"] = r.error;
    return j;
  }
  if (o.mode == "select") {
    j["selected"] = r.selected;
    j["truth_rank"] = r.truth_rank;
    j["ranking"] = r.ranking;
    return j;
  }
  const CompositeModel m = truth(name);
  const auto q = physical(m);
  const auto p = natural(m);
  for (std::size_t i = 0; i < q.size() && i < r.gmwm.size(); ++i)
    j["gmwm"][q[i].name] = {{"value", r.gmwm[i].value},
                            {"lo", r.gmwm[i].lo},
                            {"hi", r.gmwm[i].hi},
                            {"sd", r.gmwm[i].sd},
                            {"truth", q[i].value}};
  for (std::size_t i = 0; i < p.size() && i < r.gmwm_natural.size(); ++i)
    j["natural"][p[i].name] = {{"value", r.gmwm_natural[i].value}, {"truth", p[i].value}};
  for (const auto& [k, e] : r.fit) j["ieee_fit"][k] = e.valid ? nlohmann::json(e.value) : nlohmann::json();
  for (const auto& [k, e] : r.readoff) j["ieee_readoff"][k] = e.valid ? nlohmann::json(e.value) : nlohmann::json();
  j["converged"] = r.converged;
  j["replicates"] = r.replicates;
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    o = parse(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gmwm_monte_carlo: %s\n", e.what());
    return 2;
  }
  std::ofstream raw;
  if (!o.raw.empty()) {
    raw.open(o.raw, std::ios::app);
    if (!raw) {
      std::fprintf(stderr, "gmwm_monte_carlo: --raw: cannot open %s for appending\n", o.raw.c_str());
      return 2;
    }
  }
  const int threads = o.threads > 0 ? static_cast<int>(o.threads) : omp_get_max_threads();
  std::printf("# GMWM Monte Carlo: mode %s, seeds %llu-%llu, %s, %d threads\n", o.mode.c_str(),
              static_cast<unsigned long long>(o.first_seed),
              static_cast<unsigned long long>(o.first_seed + o.seeds - 1),
              o.mode == "select" ? ("WIC replicates " + std::to_string(o.selection_replicates)).c_str()
              : o.bootstrap > 0  ? ("bootstrap B = " + std::to_string(o.bootstrap) + " at ci " + num(o.ci)).c_str()
                                 : "no bootstrap",
              threads);
  for (const std::string& name : o.models) {
    for (const std::size_t n : o.samples) {
      std::printf("\n## %s, %zu samples, %zu seeds\n\n", name.c_str(), n, o.seeds);
      std::printf("Truth (per sample, unit u, 1 sample/s):");
      for (const auto& q : physical(truth(name))) std::printf(" %s = %s", q.name.c_str(), num(q.value).c_str());
      std::printf(".\n");
      std::fflush(stdout);
      std::vector<SeedResult> res(o.seeds);
      const double w0 = omp_get_wtime(), c0 = cpu_seconds();
      std::size_t done = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
      for (std::size_t i = 0; i < o.seeds; ++i) {
        res[i] = run_seed(o, name, n, o.first_seed + i);
#pragma omp critical
        {
          ++done;
          if (done % 10 == 0 || done == o.seeds)
            std::fprintf(stderr, "  %s N=%zu: %zu/%zu seeds, %.0f s\n", name.c_str(), n, done, o.seeds,
                         omp_get_wtime() - w0);
        }
      }
      const double wall = omp_get_wtime() - w0, cpu = cpu_seconds() - c0;
      std::size_t failed = 0;
      for (std::size_t i = 0; i < o.seeds; ++i) {
        if (!res[i].ok) {
          ++failed;
          std::printf("seed %llu failed: %s\n", static_cast<unsigned long long>(o.first_seed + i),
                      res[i].error.c_str());
        }
        if (raw) raw << raw_line(o, name, n, o.first_seed + i, res[i]).dump() << '\n';
      }
      if (o.mode == "select")
        report_select(o, name, res);
      else
        report_fit(o, name, res);
      std::printf("\nTime: %.1f s wall, %.1f s CPU (%.2f CPU s per seed)%s.\n", wall, cpu,
                  cpu / static_cast<double>(o.seeds), failed ? "; some seeds failed (above)" : "");
      std::fflush(stdout);
    }
  }
  return 0;
}
