#include "cubecal/pipeline/analysis_json.hpp"

#include "cubecal/pipeline/psd_json.hpp"
#include "detail/matrix_json.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>

#include "cubecal/error.hpp"
#include "cubecal/noise/bias_verdict.hpp"
#include "cubecal/pipeline/psd_json.hpp"
#include "detail/matrix_json.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/spectral_analysis.hpp"
#include "cubecal/spectral/allan_conversion.hpp"
#include "cubecal/spectral/density_unit.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "detail/curve_json.hpp"
#include "detail/json_node.hpp"

namespace cubecal::pipeline {

namespace {

using nlohmann::json;

// ---------------------------------------------------------------------------
// Writing

json quantity(const Quantity& q, bool valid) {
  json j;
  j["value"] = valid ? json(q.value) : json(nullptr);
  j["sigma"] = valid ? json(q.sigma) : json(nullptr);
  j["unit"] = q.unit;
  return j;
}

json term(const TermEstimate& t, Term which, const Unit& u) {
  json j = quantity(display(t, which, u), t.valid);
  if (t.valid) j["tau_range_s"] = {t.tau_lo, t.tau_hi};
  return j;
}

using detail::curve_json;

// A reported term (reported_terms.hpp): the estimate or the upper bound,
// with its source.
json reported_json(const ReportedTerm& t, Term which, const Unit& u) {
  json j = term(t.estimate, which, u);
  j["source"] = to_string(t.source);
  j["upper_bound"] = t.bound();
  if (t.bound()) j["sigma"] = nullptr;
  return j;
}

json noise_json(const NoiseAnalysis& n, const Unit& u) {
  json j;
  const SlopeReadOffs& r = n.readoffs;
  const NoiseFit& f = n.fit;
  const ReportedTerms rt = reported_terms(r, f, to_allan_curve(n.adev));
  j["method"] =
      "slope read-offs (IEEE 952): N on the -1/2 line read at tau = 1 s (the line through the curve's points "
      "within 2x of 1 s when the -1/2 region contains 1 s, else the line tangent to the region; tau_range_s: "
      "the points it was read over), B = sigma_min / 0.664, K at tau = 3 s";
  j["arw"] = term(r.N, Term::N, u);
  j["arw"]["read_at_tau_s"] = 1.0;
  j["arw"]["white_at_read_tau"] = r.N.valid && r.N.tau_lo <= 1.0 && 1.0 <= r.N.tau_hi;
  j["bias_instability"] = term(r.B, Term::B, u);
  j["bias_instability"]["no_minimum_within_record"] = rt.no_minimum && !rt.constant;
  // T only where the curve has a minimum inside the record.
  j["time_constant_s"] = r.B.valid ? json(r.tau_min) : json(nullptr);
  j["time_constant_range_s"] = r.B.valid ? json({r.tau_min_lo, r.tau_min_hi}) : json(nullptr);
  // T's relative uncertainty: half the central interval of ln T over records at the analysis's confidence
  // (noise/minimum_spread.hpp).
  j["time_constant_rel_sigma"] = r.B.valid && rt.T_rel_sigma > 0.0 ? json(rt.T_rel_sigma) : json(nullptr);
  // Where the curve is lowest, minimum inside the record or not.
  j["curve_minimum"] = {{"tau_s", r.tau_min}, {"tau_range_s", {r.tau_min_lo, r.tau_min_hi}}};
  j["sigma_min"] = {{"value", r.sigma_min}, {"unit", u.name}};
  j["rate_random_walk"] = term(r.K, Term::K, u);
  j["rate_random_walk"]["significant"] = significant(r.K);
  j["quantization"] = term(r.Q, Term::Q, u);
  j["rate_ramp"] = term(r.R, Term::R, u);
  json fit;
  fit["method"] = "weighted non-negative least squares of sigma^2(tau) = sum C_k tau^k, k = -2..2";
  fit["note"] = "the fit's own terms; the N reported everywhere is noise.arw (= noise.reported.white_noise)";
  fit["quantization"] = term(f.Q, Term::Q, u);
  fit["arw"] = term(f.N, Term::N, u);
  fit["bias_instability"] = term(f.B, Term::B, u);
  fit["rate_random_walk"] = term(f.K, Term::K, u);
  fit["rate_random_walk"]["significant"] = significant(f.K);
  fit["rate_ramp"] = term(f.R, Term::R, u);
  fit["coefficients"] = f.c;
  fit["coefficients_sigma"] = f.c_sigma;
  fit["chi2"] = f.chi2;
  fit["dof"] = f.dof;
  fit["rms_rel_residual"] = f.rms_rel_residual;
  j["fit"] = fit;
  // The terms every output reports (console, estimator files, report):
  // one N, K only when significant, B only with a minimum in the record.
  json rep;
  rep["white_noise"] = reported_json(rt.N, Term::N, u);
  rep["rate_random_walk"] = reported_json(rt.K, Term::K, u);
  rep["rate_random_walk"]["significant"] = !rt.K.bound() && rt.K.estimate.valid;
  rep["rate_random_walk"]["significance_sigmas"] = kSignificanceSigmas;
  rep["rate_random_walk"]["estimate"] =
      rt.K_candidate.valid ? quantity(display(rt.K_candidate, Term::K, u), true) : json(nullptr);
  if (rt.K_candidate.valid) rep["rate_random_walk"]["estimate"]["source"] = to_string(rt.K_candidate_source);
  rep["bias_instability"] = reported_json(rt.B, Term::B, u);
  rep["bias_instability"]["no_minimum_within_record"] = rt.no_minimum && !rt.constant;
  j["reported"] = rep;
  // Densities of the reported N and K (an upper bound is marked as such).
  const TermEstimate& N = rt.N.estimate;
  const TermEstimate& K = rt.K.estimate;
  j["densities"] = {{"white", quantity(white_density(N, u, false), N.valid)},
                    {"random_walk", quantity(random_walk_density(K, u, false), K.valid)},
                    {"white_si", quantity(white_density(N, u, true), N.valid)},
                    {"random_walk_si", quantity(random_walk_density(K, u, true), K.valid)},
                    {"white_source", to_string(rt.N.source)},
                    {"random_walk_source", to_string(rt.K.source)}};
  for (const char* key : {"white", "white_si"})
    if (rt.N.bound()) j["densities"][key]["sigma"] = nullptr;
  for (const char* key : {"random_walk", "random_walk_si"})
    if (rt.K.bound()) j["densities"][key]["sigma"] = nullptr;
  if (u.kind == SensorKind::acceleration) {
    // The same terms in the units inertial navigation quotes (added fields:
    // readers of the terms above need nothing from them).
    const auto accel = [&](const TermEstimate& t, Term which) {
      json a = json::array();
      for (const Quantity& q : accelerometer_display(t, which, u)) a.push_back(quantity(q, t.valid));
      return a;
    };
    j["accelerometer"] = {{"read_off",
                           {{"velocity_random_walk", accel(r.N, Term::N)},
                            {"bias_instability", accel(r.B, Term::B)},
                            {"acceleration_random_walk", accel(r.K, Term::K)}}},
                          {"fit",
                           {{"velocity_random_walk", accel(f.N, Term::N)},
                            {"bias_instability", accel(f.B, Term::B)},
                            {"acceleration_random_walk", accel(f.K, Term::K)}}}};
  }
  const BiasVerdict v = judge_bias_instability(r, f);
  j["bias_instability_choice"] = {{"trust", to_string(v.trust)},
                                  {"fit_over_read_off", v.compared ? json(v.ratio) : json(nullptr)},
                                  {"beyond_combined_sigma", v.beyond_sigma},
                                  {"other_terms_share_at_minimum", v.other_terms_share},
                                  {"reason", v.reason}};
  return j;
}

json model_json(const ModelAnalysis& m, const Unit& u, std::size_t record_samples) {
  json j;
  j["unit"] = u.name;
  j["samples"] = m.samples;
  if (m.ok) {
    j["sigma_n"] = m.random_walk.sigma_n;
    j["sigma_mu"] = m.random_walk.sigma_mu;
    j["sigma_mu_unit"] = u.name + "/s";
    j["lsb"] = m.random_walk.lsb;
    j["residual_rms_log"] = m.random_walk_residual.rms_log;
    j["residual_chi2"] = m.random_walk_residual.chi2;
  } else {
    j["sigma_n"] = nullptr;
    j["sigma_mu"] = nullptr;
    j["error"] = m.error;
    j["lsb"] = m.random_walk.lsb;
  }
  if (m.gm_ok) {
    j["gauss_markov"] = {{"sigma", m.gauss_markov.sigma_b},
                         {"tau_s", m.gauss_markov.tau_c},
                         {"sigma_n", m.gauss_markov.sigma_n},
                         {"residual_rms_log", m.gauss_markov_residual.rms_log},
                         {"residual_chi2", m.gauss_markov_residual.chi2}};
  } else {
    j["gauss_markov"] = nullptr;
    j["gauss_markov_error"] = m.gm_error;
  }
  if (m.ok && m.gm_ok)
    j["better_fit"] = m.gauss_markov_residual.rms_log < m.random_walk_residual.rms_log ? "gauss_markov" : "random_walk";
  // The curve the models were fitted to, when it is not the record's.
  if (m.samples != record_samples) j["adev"] = curve_json(m.adev);
  return j;
}

// The coefficients of a temperature fit: offset c_0, coeff c_1.., their
// sigmas and covariance, and how well the polynomial fits.
void temperature_fit_json(json& tj, const TemperatureFit& f) {
  tj["t_ref"] = f.t_ref;
  tj["offset"] = f.coeff.empty() ? 0.0 : f.coeff[0];
  tj["offset_sigma"] = f.coeff_sigma.empty() ? 0.0 : f.coeff_sigma[0];
  std::vector<double> coeff, sig;
  if (!f.coeff.empty()) coeff.assign(f.coeff.begin() + 1, f.coeff.end());
  if (!f.coeff_sigma.empty()) sig.assign(f.coeff_sigma.begin() + 1, f.coeff_sigma.end());
  tj["coeff"] = coeff;
  tj["coeff_sigma"] = sig;
  tj["coeff_cov"] = detail::to_json(f.cov);
  tj["r2"] = f.r2;
  tj["residual_rms"] = f.residual_rms;
}

json temperature_json(const TemperatureAnalysis& t, const Unit& u, const std::string& sensor,
                      std::size_t record_samples, double rate_hz) {
  json tj;
  tj["sensor"] = sensor;
  temperature_fit_json(tj, t.fit);
  tj["order"] = t.fit.order;
  tj["unit"] = u.name + "/degC";
  std::vector<std::string> units;
  for (std::size_t p = 1; p < t.fit.coeff.size(); ++p)
    units.push_back(u.name + (p == 1 ? "/degC" : "/degC^" + std::to_string(p)));
  tj["coeff_units"] = units;
  if (t.joint) {
    tj["method"] = "random_walk_gls";
    tj["method_text"] =
        "generalized least squares with white noise and a random-walk bias (Kalman filter), noise model fitted "
        "to the compensated record";
    tj["noise_model"] = {{"sigma_n", t.noise.sigma_n}, {"sigma_mu", t.noise.sigma_mu}, {"sigma_mu_unit", u.name + "/s"},
                         {"lsb", t.noise.lsb},         {"iterations", t.iterations},   {"converged", t.converged}};
  } else {
    tj["method"] = "ols";
    tj["method_text"] = "ordinary least squares, batch-means sandwich covariance";
    if (!t.joint_error.empty()) tj["joint_error"] = t.joint_error;
  }
  json ols;
  ols["method_text"] = "ordinary least squares, batch-means sandwich covariance";
  temperature_fit_json(ols, t.ols);
  tj["ols"] = ols;
  tj["compensated"] = noise_json(t.compensated, u);
  tj["compensated"]["adev"] = curve_json(t.compensated.adev);
  tj["compensated_model"] = model_json(t.compensated_model, u, record_samples);
  if (t.compensated_model.composite) {
    // The twin of the compensated series: the record's refitted (what
    // `simulate` adds the temperature term to).
    json& cj = tj["compensated_model"]["composite"];
    cj = to_json(*t.compensated_model.composite, rate_hz, false);
    cj["residual_rms_log"] = t.compensated_model.composite_residual.rms_log;
    cj["residual_chi2"] = t.compensated_model.composite_residual.chi2;
  }
  return tj;
}

// The spectral view (analyze --psd): the Welch plan, the spectrum in log
// bands, the power-law fit, and each IEEE 952 term of the fit beside the
// Allan curve's five-term fit with their difference in combined sigmas (the
// terms are derived from the fit and the Allan fit: not read back).
json spectral_json(const SpectralAnalysis& s, const NoiseFit& allan, const Unit& u) {
  const Psd& p = s.spectrum;
  json j;
  j["method"] =
      "Welch power spectral density with the defaults of cubecal psd, one-sided; the power-law fit S(f) = sum "
      "h_alpha f^alpha and the IEEE 952 terms its coefficients stand for (docs/formulas/spectral.md); beside each "
      "term the five-term fit of the Allan curve (noise.fit) and (spectrum - allan) / sqrt(sigma_spectrum^2 + "
      "sigma_allan^2)";
  j["welch"] = welch_json(p, s.overlap);
  j["welch"]["pieces"] = s.pieces;
  j["welch"]["pieces_used"] = s.pieces_used;
  j["spectrum"] = {{"bins_per_decade", p.bins_per_decade},
                   {"density_unit", density_unit(u).name},
                   {"frequency_hz", p.frequency},
                   {"density", p.density},
                   {"edf", p.edf},
                   {"bins", p.bins},
                   {"first_bin", p.first_bin}};
  const bool fitted = s.fit_error.empty() && !s.fit.terms.empty();
  j["fit"] = fitted ? power_law_fit_json(s.fit, u) : json(nullptr);
  if (!s.fit_error.empty()) j["fit_error"] = s.fit_error;
  json terms = json::array();
  for (const TermViews& v : compare_views(allan, s)) {
    json t = quantity(display(v.spectrum, v.term, u), v.spectrum.valid);
    t["term"] = std::string(to_string(v.term));
    t["alpha"] = power_law_exponent(v.term);
    t["allan_fit"] = quantity(display(v.allan, v.term, u), v.allan.valid);
    t["difference_sigmas"] = v.difference_sigmas ? json(*v.difference_sigmas) : json(nullptr);
    terms.push_back(std::move(t));
  }
  j["terms"] = std::move(terms);
  return j;
}

std::string_view edf_name(EdfMethod m) { return m == EdfMethod::simple ? "simple" : "greenhall"; }

// ---------------------------------------------------------------------------
// Reading: every access names its place in the document.

using Node = detail::JsonNode;

// Listed taus left out of a curve ("excluded_taus": tau_s, af, needs_samples,
// samples, reason) and merged with an earlier one ("merged_taus": tau_s,
// merged_with_tau_s, af).
json whole(double v) {  // an integer where a double holds it exactly
  return v < 9.0e15 ? json(static_cast<std::uint64_t>(v)) : json(v);
}

json excluded_json(const std::vector<ExcludedTau>& ex) {
  json a = json::array();
  for (const auto& e : ex)
    a.push_back({{"tau_s", e.tau},
                 {"af", whole(e.m)},
                 {"needs_samples", whole(e.needs)},
                 {"samples", e.has},
                 {"reason", e.reason}});
  return a;
}

void write_tau_list(json& j, const TauListOutcome& t) {
  j["excluded_taus"] = excluded_json(t.excluded);
  json merged = json::array();
  for (const auto& m : t.merged) merged.push_back({{"tau_s", m.tau}, {"merged_with_tau_s", m.kept_tau}, {"af", m.m}});
  j["merged_taus"] = std::move(merged);
}

// Absent in documents written before the keys existed: nothing excluded.
std::vector<ExcludedTau> read_excluded(const Node& root, const char* key) {
  std::vector<ExcludedTau> out;
  if (!root.has(key)) return out;
  const Node a = root.at(key);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Node e = a.at(i);
    out.push_back({e.num("tau_s"), e.num("af"), e.num("needs_samples"), e.at("samples").count(), e.at("reason").str()});
  }
  return out;
}

TauListOutcome read_tau_list(const Node& root) {
  TauListOutcome t;
  t.excluded = read_excluded(root, "excluded_taus");
  if (root.has("merged_taus")) {
    const Node a = root.at("merged_taus");
    for (std::size_t i = 0; i < a.size(); ++i) {
      const Node m = a.at(i);
      t.merged.push_back({m.num("tau_s"), m.num("merged_with_tau_s"), m.at("af").count()});
    }
  }
  return t;
}

std::vector<StabilityPoint> read_curve(const Node& a) {
  const auto tau = a.at("tau").nums(), dev = a.at("dev").nums();
  const Node af = a.at("af"), n = a.at("n");
  const std::size_t k = tau.size();
  if (dev.size() != k || af.size() != k || n.size() != k) a.fail("af, tau, dev and n differ in length");
  std::vector<StabilityPoint> pts(k);
  for (std::size_t i = 0; i < k; ++i) {
    pts[i].m = af.at(i).count();
    pts[i].tau = tau[i];
    pts[i].dev = dev[i];
    pts[i].n = n.at(i).count();
  }
  if (a.has("lo")) {
    const auto lo = a.at("lo").nums(), hi = a.at("hi").nums(), edf = a.at("edf").nums();
    const Node alpha = a.at("alpha");
    if (lo.size() != k || hi.size() != k || edf.size() != k || alpha.size() != k)
      a.fail("the interval arrays differ in length from tau");
    for (std::size_t i = 0; i < k; ++i) {
      pts[i].interval = {lo[i], hi[i]};
      pts[i].edf = edf[i];
      pts[i].alpha = alpha.at(i).integer(-4, 2);  // the power-law noise exponents, +2 WPM .. -4 RRFM
    }
  }
  return pts;
}

// The inverse of term(): the display value back in the data unit.
TermEstimate read_term(const Node& q, Term which, const Unit& u) {
  TermEstimate t;
  const Node v = q.at("value");
  if (v.raw().is_null()) return t;
  TermEstimate one;
  one.valid = true;
  one.value = 1.0;
  const double f = display(one, which, u).value;
  t.valid = true;
  t.value = v.num() / f;
  t.sigma = q.num("sigma") / f;
  if (q.has("tau_range_s")) {
    const auto r = q.at("tau_range_s").nums();
    if (r.size() != 2) q.fail("tau_range_s is not a pair");
    t.tau_lo = r[0];
    t.tau_hi = r[1];
  }
  return t;
}

NoiseAnalysis read_noise(const Node& j, const Unit& u) {
  NoiseAnalysis n;
  SlopeReadOffs& r = n.readoffs;
  r.N = read_term(j.at("arw"), Term::N, u);
  r.B = read_term(j.at("bias_instability"), Term::B, u);
  r.K = read_term(j.at("rate_random_walk"), Term::K, u);
  r.Q = read_term(j.at("quantization"), Term::Q, u);
  r.R = read_term(j.at("rate_ramp"), Term::R, u);
  r.sigma_min = j.at("sigma_min").num("value");
  if (j.has("curve_minimum")) {
    const Node m = j.at("curve_minimum");
    r.tau_min = m.num("tau_s");
    const auto range = m.at("tau_range_s").nums();
    if (range.size() != 2) m.fail("tau_range_s is not a pair");
    r.tau_min_lo = range[0];
    r.tau_min_hi = range[1];
  } else if (j.has("time_constant_s")) {
    r.tau_min = j.num("time_constant_s");
    const auto range = j.at("time_constant_range_s").nums();
    if (range.size() != 2) j.fail("time_constant_range_s is not a pair");
    r.tau_min_lo = range[0];
    r.tau_min_hi = range[1];
  }
  const Node f = j.at("fit");
  NoiseFit& fit = n.fit;
  fit.Q = read_term(f.at("quantization"), Term::Q, u);
  fit.N = read_term(f.at("arw"), Term::N, u);
  fit.B = read_term(f.at("bias_instability"), Term::B, u);
  fit.K = read_term(f.at("rate_random_walk"), Term::K, u);
  fit.R = read_term(f.at("rate_ramp"), Term::R, u);
  const auto c = f.at("coefficients").nums(), cs = f.at("coefficients_sigma").nums();
  if (c.size() != 5 || cs.size() != 5) f.fail("coefficients are not five numbers (C_-2 .. C_2)");
  std::copy(c.begin(), c.end(), fit.c.begin());
  std::copy(cs.begin(), cs.end(), fit.c_sigma.begin());
  fit.chi2 = f.num("chi2");
  fit.dof = f.at("dof").count();
  fit.rms_rel_residual = f.num("rms_rel_residual");
  return n;
}

ModelAnalysis read_model(const Node& m, const ChannelAnalysis& ch, double dt) {
  ModelAnalysis a;
  a.samples = m.at("samples").count();
  a.adev = m.has("adev") ? read_curve(m.at("adev")) : ch.noise.adev;
  const double lsb = m.num_or("lsb", 0.0);
  if (m.has("sigma_n")) {
    a.ok = true;
    a.random_walk = RandomWalkModel{m.num("sigma_n"), m.num("sigma_mu"), dt, lsb};
    a.random_walk_residual.rms_log = m.num("residual_rms_log");
    a.random_walk_residual.chi2 = m.num_or("residual_chi2", 0.0);
  } else {
    a.error = m.str_or("error", "");
    a.random_walk.dt = dt;
    a.random_walk.lsb = lsb;
  }
  if (m.has("gauss_markov")) {
    const Node g = m.at("gauss_markov");
    a.gm_ok = true;
    a.gauss_markov = GaussMarkovModel{g.num("sigma_n"), g.num("sigma"), g.num("tau_s"), dt, lsb};
    a.gauss_markov_residual.rms_log = g.num("residual_rms_log");
    a.gauss_markov_residual.chi2 = g.num_or("residual_chi2", 0.0);
  } else {
    a.gm_error = m.str_or("gauss_markov_error", "");
    a.gauss_markov.dt = dt;
    a.gauss_markov.lsb = lsb;
  }
  return a;
}

// The inverse of temperature_fit_json.
TemperatureFit read_temperature_fit(const Node& t, std::size_t order) {
  TemperatureFit f;
  f.t_ref = t.num("t_ref");
  const auto coeff = t.at("coeff").nums(), sig = t.at("coeff_sigma").nums();
  if (sig.size() != coeff.size()) t.fail("coeff and coeff_sigma differ in length");
  f.coeff.push_back(t.num("offset"));
  f.coeff.insert(f.coeff.end(), coeff.begin(), coeff.end());
  f.coeff_sigma.push_back(t.num_or("offset_sigma", 0.0));
  f.coeff_sigma.insert(f.coeff_sigma.end(), sig.begin(), sig.end());
  if (t.has("coeff_cov")) {
    const Node cov = t.at("coeff_cov");
    for (std::size_t i = 0; i < cov.size(); ++i) {
      const std::vector<double> row = cov.at(i).nums();
      if (i == 0) f.cov = Matrix(cov.size(), row.size());
      for (std::size_t k = 0; k < row.size() && k < f.cov.cols(); ++k) f.cov(i, k) = row[k];
    }
  }
  f.order = order > 0 ? order : coeff.size();
  f.r2 = t.num("r2");
  f.residual_rms = t.num("residual_rms");
  return f;
}

TemperatureAnalysis read_temperature(const Node& t, const ChannelAnalysis& ch, std::size_t record_samples, double dt) {
  TemperatureAnalysis a;
  const std::size_t order = t.has("order") ? t.at("order").count() : 0;
  a.fit = read_temperature_fit(t, order);
  // Before the joint estimate, the one fit was the least-squares one.
  const std::string method = t.str_or("method", "ols");
  if (method != "ols" && method != "random_walk_gls") t.at("method").fail("neither 'ols' nor 'random_walk_gls'");
  a.joint = method == "random_walk_gls";
  a.joint_error = t.str_or("joint_error", "");
  a.ols = t.has("ols") ? read_temperature_fit(t.at("ols"), a.fit.order) : a.fit;
  if (a.joint) {
    const Node m = t.at("noise_model");
    a.noise = RandomWalkModel{m.num("sigma_n"), m.num("sigma_mu"), dt, m.num_or("lsb", 0.0)};
    a.iterations = m.at("iterations").count();
    a.converged = m.has("converged") && m.at("converged").raw().is_boolean() && m.at("converged").raw().get<bool>();
  }
  const Node comp = t.at("compensated");
  a.compensated = read_noise(comp, ch.unit);
  a.compensated.adev = read_curve(comp.at("adev"));
  if (t.has("compensated_model")) {
    // The curve the models were fitted to: its own when written, else the
    // compensated record's.
    ChannelAnalysis on = ch;
    on.noise.adev = a.compensated.adev;
    a.compensated_model = read_model(t.at("compensated_model"), on, dt);
    if (t.at("compensated_model").has("composite")) {
      const Node m = t.at("compensated_model").at("composite");
      a.compensated_model.composite =
          model_channel_from_json(m.raw(), "analysis.json", "channels[].temperature.compensated_model.composite");
      a.compensated_model.composite_residual.rms_log = m.num("residual_rms_log");
      a.compensated_model.composite_residual.chi2 = m.num("residual_chi2");
    }
  } else {
    a.compensated_model.error = a.compensated_model.gm_error =
        "not in this analysis.json (written before the compensated series' model was reported)";
    a.compensated_model.samples = record_samples;
    a.compensated_model.adev = a.compensated.adev;
    a.compensated_model.random_walk.dt = a.compensated_model.gauss_markov.dt = dt;
  }
  return a;
}

std::vector<std::size_t> counts(const Node& a) {
  std::vector<std::size_t> v(a.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = a.at(i).count();
  return v;
}

// The inverse of power_law_fit_json.
PowerLawFit read_power_law_fit(const Node& f) {
  PowerLawFit fit;
  fit.f_lo = f.num("f_lo_hz");
  fit.f_hi = f.num("f_hi_hz");
  fit.bands = f.at("bands").count();
  fit.chi2 = f.num("chi2");
  fit.dof = f.at("dof").count();
  fit.scale = f.num("scale");
  const Node terms = f.at("terms");
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const Node t = terms.at(i);
    PowerLawTerm term;
    term.alpha = t.at("alpha").integer(-4, 4);
    term.h = t.num("h");
    term.sigma = t.num("sigma");
    term.valid = t.at("valid").boolean();
    term.f_lo = t.num("f_lo_hz");
    term.f_hi = t.num("f_hi_hz");
    fit.terms.push_back(term);
  }
  const Node cov = f.at("covariance");
  const std::size_t p = fit.terms.size();
  if (cov.size() != p) cov.fail("not one row per term");
  fit.covariance = Matrix(p, p);
  for (std::size_t i = 0; i < p; ++i) {
    const auto row = cov.at(i).nums();
    if (row.size() != p) cov.at(i).fail("not one column per term");
    std::copy(row.begin(), row.end(), fit.covariance.row(i).begin());
  }
  return fit;
}

// The inverse of spectral_json (its terms are derived: made again from the fit).
SpectralAnalysis read_spectral(const Node& j, const Unit& u, double rate_hz) {
  SpectralAnalysis s;
  const Node w = j.at("welch");
  Psd& p = s.spectrum;
  p.rate_hz = rate_hz;
  const std::string window = w.at("window").str(), detrend = w.at("detrend").str();
  const auto win = parse_window(window);
  const auto det = parse_detrend(detrend);
  if (!win) w.at("window").fail("unknown window '" + window + "'");
  if (!det) w.at("detrend").fail("unknown detrending '" + detrend + "'");
  p.window = *win;
  p.detrend = *det;
  p.segment_length = w.at("segment_length").count();
  s.overlap = w.num("overlap");
  p.overlap = w.at("overlap_samples").count();
  p.segments = w.at("segments").count();
  p.samples_used = w.at("samples_used").count();
  p.enbw_hz = w.num("enbw_hz");
  s.pieces = w.at("pieces").count();
  s.pieces_used = w.at("pieces_used").count();
  const Node sp = j.at("spectrum");
  p.bins_per_decade = sp.at("bins_per_decade").count();
  p.frequency = sp.at("frequency_hz").nums();
  p.density = sp.at("density").nums();
  p.edf = sp.at("edf").nums();
  p.bins = counts(sp.at("bins"));
  p.first_bin = counts(sp.at("first_bin"));
  const std::size_t k = p.frequency.size();
  if (p.density.size() != k || p.edf.size() != k || p.bins.size() != k || p.first_bin.size() != k)
    sp.fail("frequency_hz, density, edf, bins and first_bin differ in length");
  if (j.has("fit")) {
    s.fit = read_power_law_fit(j.at("fit"));
    s.allan_terms = psd_allan_terms(s.fit, u, rate_hz);
  } else {
    s.fit_error = j.str_or("fit_error", "");
  }
  return s;
}

// Files before format_version 2 carry in noise.arw the white-noise line
// tangent to the whole -1/2 region, not the line read at tau = 1 s: N is
// read again from the stored curve, so that a report of an old file gives
// the N a new analysis would.
void reread_white_noise(NoiseAnalysis& n) {
  if (n.adev.empty()) return;
  n.readoffs.N = read_off_noise_terms(to_allan_curve(n.adev)).N;
}

// Channel c of the document (r: the record so far, its samples, rate and
// temperature sensor; the sensor is set from the first channel that names it).
ChannelAnalysis read_channel(const Node& chans, std::size_t c, AnalysisResult& r, double version,
                             const std::string& label) {
  const double dt = 1.0 / r.rate_hz;
  const Node cj = chans.at(c);
  ChannelAnalysis ch;
  ch.name = cj.at("name").str();
  const std::string unit = cj.at("unit").str();
  const auto u = parse_unit(unit);
  if (!u) cj.at("unit").fail("unknown unit '" + unit + "' (known: " + known_units() + ")");
  ch.unit = *u;
  ch.mean = cj.num("mean");
  ch.stddev = cj.num("stddev");
  ch.noise = read_noise(cj.at("noise"), ch.unit);
  ch.noise.adev = read_curve(cj.at("adev"));
  if (cj.has("adev_stride")) {
    const Node st = cj.at("adev_stride");
    if (st.size() != ch.noise.adev.size()) st.fail("not one stride per point of adev");
    for (std::size_t k = 0; k < st.size(); ++k) ch.adev_strides.push_back(st.at(k).count());
  }
  if (version < 2) reread_white_noise(ch.noise);
  ch.model = read_model(cj.at("model"), ch, dt);
  if (cj.at("model").has("composite")) {
    const Node m = cj.at("model").at("composite");
    ch.model.composite = model_channel_from_json(m.raw(), label, "channels[" + std::to_string(c) + "].model.composite");
    ch.model.composite_residual.rms_log = m.num("residual_rms_log");
    ch.model.composite_residual.chi2 = m.num("residual_chi2");
    if (m.has("twin_error")) {
      const Node e = m.at("twin_error");
      ch.model.twin_error = {e.at("taus").count(),   e.at("inside").count(),   e.num("share_inside"),
                             e.num("max_error"),     e.num("max_error_tau_s"), e.num("max_error_10s"),
                             e.num("max_error_100s")};
    }
  }
  const Node d = cj.at("drift");
  const double window = d.num("window_s") * r.rate_hz;  // samples
  if (!(window >= 0.0 && window <= 1e15)) d.at("window_s").fail("not a window length in seconds");
  ch.drift.window = static_cast<std::size_t>(std::llround(window));
  ch.drift.mean = d.num("fixed_bias");
  if (cj.has("temperature")) {
    const Node t = cj.at("temperature");
    ch.temperature = read_temperature(t, ch, r.samples, dt);
    if (version < 2) reread_white_noise(ch.temperature->compensated);
    if (r.temp_name.empty()) r.temp_name = t.str_or("sensor", "");
  }
  // Written by analyze --psd only (and not before it existed).
  if (cj.has("spectral")) ch.spectral = read_spectral(cj.at("spectral"), ch.unit, r.rate_hz);
  return ch;
}

// analyze --twin-check's curves.
TwinCheck read_twin_check(const Node& t) {
  TwinCheck tc;
  tc.twins = t.at("twins").count();
  tc.seed = t.at("seed").count();
  tc.samples = t.at("samples").count();
  const Node cs = t.at("channels");
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const Node c = cs.at(i);
    TwinCheckChannel ch;
    ch.name = c.at("name").str();
    ch.tau = c.at("tau").nums();
    ch.measured = c.at("measured").nums();
    ch.twins = c.at("twins").nums();
    ch.twins_lo = c.at("twins_lo").nums();
    ch.twins_hi = c.at("twins_hi").nums();
    const std::size_t n = ch.tau.size();
    if (ch.measured.size() != n || ch.twins.size() != n || ch.twins_lo.size() != n || ch.twins_hi.size() != n)
      c.fail("tau, measured, twins, twins_lo and twins_hi differ in length");
    ch.max_error_10s = c.num("max_error_10s");
    ch.max_error_100s = c.num("max_error_100s");
    ch.max_error = c.num("max_error");
    ch.max_error_tau_s = c.num("max_error_tau_s");
    tc.channels.push_back(std::move(ch));
  }
  return tc;
}

AnalysisResult read_result(const json& doc, const std::string& label) {
  const Node root(doc, "", label);
  if (!doc.is_object() || !doc.contains("input") || !doc.contains("channels")) root.fail("no 'input' and 'channels'");
  AnalysisResult r;
  const Node in = root.at("input");
  r.file = in.at("file").str();
  r.samples = in.at("samples").count();
  r.rate_hz = in.num("rate_hz");
  if (!(r.rate_hz > 0)) in.fail("rate_hz is not positive");
  r.duration_s = in.num("duration_s");
  r.segments = in.at("segments").count();
  const std::string gaps = in.str_or("gaps", "error");
  if (gaps != "error" && gaps != "split" && gaps != "skip") in.at("gaps").fail("not 'error', 'split' or 'skip'");
  r.gaps = gaps == "split" ? io::GapPolicy::split : gaps == "skip" ? io::GapPolicy::skip : io::GapPolicy::error;
  r.ci = root.num_or("ci", 0.683);
  const double version = root.num_or("format_version", 1.0);
  const Node chans = root.at("channels");
  for (std::size_t c = 0; c < chans.size(); ++c) r.channels.push_back(read_channel(chans, c, r, version, label));
  const Node cov = root.at("covariance");
  const Node names = cov.at("channels");
  for (std::size_t i = 0; i < names.size(); ++i) r.cov_names.push_back(names.at(i).str());
  const Node m = cov.at("matrix");
  for (std::size_t i = 0; i < m.size(); ++i) {
    const std::vector<double> row = m.at(i).nums();
    if (i == 0) r.covariance = Matrix(m.size(), row.size());
    for (std::size_t k = 0; k < row.size() && k < r.covariance.cols(); ++k) r.covariance(i, k) = row[k];
  }
  r.cov_samples = cov.at("samples").count();
  r.tau_list = read_tau_list(root);
  r.model_excluded_taus = read_excluded(root, "model_excluded_taus");
  if (root.has("stream")) r.window_bound = root.at("stream").at("window_bound").count();
  if (root.has("composite")) {
    const Node c = root.at("composite");
    r.composite = CompositeSettings{c.at("model").str(), c.at("selection_replicates").count(),
                                    c.at("bootstrap").count(), c.at("seed").count()};
    r.composite->robust = c.has("robust") && c.at("robust").boolean();
    if (r.composite->robust) r.composite->robust_efficiency = c.num("robust_efficiency");
  }
  if (root.has("composite_skipped")) r.composite_skipped = root.at("composite_skipped").str();
  if (root.has("drift_skipped")) r.drift_skipped = root.at("drift_skipped").str();
  if (root.has("twin_check")) r.twin_check = read_twin_check(root.at("twin_check"));
  return r;
}

// The twin check of a result (AnalyzeRequest::twin_check).
json twin_check_json(const AnalysisResult& r) {
  json checked = json::array();
  for (const TwinCheckChannel& c : r.twin_check->channels)
    checked.push_back({{"name", c.name},
                       {"tau", c.tau},
                       {"measured", c.measured},
                       {"twins", c.twins},
                       {"twins_lo", c.twins_lo},
                       {"twins_hi", c.twins_hi},
                       {"max_error_10s", c.max_error_10s},
                       {"max_error_100s", c.max_error_100s},
                       {"max_error", c.max_error},
                       {"max_error_tau_s", c.max_error_tau_s}});
  return {{"twins", r.twin_check->twins},
          {"seed", r.twin_check->seed},
          {"samples", r.twin_check->samples},
          {"note",
           "each channel's twin simulated at the record's length, seeds seed .. seed + twins - 1; "
           "twins: sqrt of the mean of their Allan variances, twins_lo/hi the smallest and largest "
           "twin's deviation; max_error: the largest |twins / measured - 1|"},
          {"channels", checked}};
}

}  // namespace

json to_json(const AnalysisResult& r) {
  json j = json::object();
  j["format_version"] = kAnalysisFormatVersion;
  j["input"] = {{"file", r.file},
                {"samples", r.samples},
                {"rate_hz", r.rate_hz},
                {"duration_s", r.duration_s},
                {"segments", r.segments},
                {"gaps", r.gaps == io::GapPolicy::split  ? "split"
                         : r.gaps == io::GapPolicy::skip ? "skip"
                                                         : "error"}};
  j["ci"] = r.ci;
  json chans = json::array();
  for (const auto& c : r.channels) {
    json ch;
    ch["name"] = c.name;
    ch["unit"] = c.unit.name;
    ch["kind"] = to_string(c.unit.kind);
    ch["mean"] = c.mean;
    ch["stddev"] = c.stddev;
    ch["adev"] = curve_json(c.noise.adev);
    if (!c.adev_strides.empty()) ch["adev_stride"] = c.adev_strides;
    ch["noise"] = noise_json(c.noise, c.unit);
    ch["model"] = model_json(c.model, c.unit, r.samples);
    if (c.model.composite) {
      json& cj = ch["model"]["composite"];
      cj = to_json(*c.model.composite, r.rate_hz, r.composite && r.composite->bootstrap > 0);
      // As the two models': its Allan variance on the curve.
      cj["residual_rms_log"] = c.model.composite_residual.rms_log;
      cj["residual_chi2"] = c.model.composite_residual.chi2;
      const TwinError& e = c.model.twin_error;
      cj["twin_error"] = {{"taus", e.taus},
                          {"inside", e.inside},
                          {"share_inside", e.share_inside},
                          {"max_error", e.max_error},
                          {"max_error_tau_s", e.max_error_tau_s},
                          {"max_error_10s", e.max_error_10s},
                          {"max_error_100s", e.max_error_100s},
                          {"note",
                           "on adev: the largest |sigma_model / sigma_measured - 1| and the share of taus whose model "
                           "deviation lies inside the curve's intervals at ci"}};
    }
    ch["drift"] = {{"window_s", static_cast<double>(c.drift.window) / r.rate_hz},
                   {"fixed_bias", c.drift.mean},
                   {"points", c.drift.t.size()},
                   {"file", "drift.csv"}};
    if (c.temperature) ch["temperature"] = temperature_json(*c.temperature, c.unit, r.temp_name, r.samples, r.rate_hz);
    if (c.spectral) ch["spectral"] = spectral_json(*c.spectral, c.noise.fit, c.unit);
    chans.push_back(std::move(ch));
  }
  j["channels"] = std::move(chans);
  std::string cov_unit;
  if (!r.channels.empty()) cov_unit = "(" + r.channels[0].unit.name + ")^2";
  j["covariance"] = {{"channels", r.cov_names},
                     {"matrix", detail::to_json(r.covariance)},
                     {"samples", r.cov_samples},
                     {"unit", cov_unit}};
  write_tau_list(j, r.tau_list);
  j["model_excluded_taus"] = excluded_json(r.model_excluded_taus);
  // A streamed run: overlapping terms exact up to the window bound, at the
  // stride of adev_stride above it.
  if (r.window_bound > 0)
    j["stream"] = {
        {"window_bound", r.window_bound}};  // analyze --composite: how each channel's model.composite was fitted.
  if (r.composite)
    j["composite"] = {{"method",
                       "GMWM fit of a composite noise model to the Haar wavelet variance of the samples the sensor "
                       "models are fitted on, as cubecal model (docs/formulas/noise-terms.md §8a-8c); each "
                       "channel's in channels[].model.composite, with the intervals at ci"},
                      {"model", r.composite->model},
                      {"selection_replicates", r.composite->selection_replicates},
                      {"bootstrap", r.composite->bootstrap},
                      {"seed", r.composite->seed},
                      {"robust", r.composite->robust}};
  if (r.composite && r.composite->robust) j["composite"]["robust_efficiency"] = r.composite->robust_efficiency;
  if (!r.composite_skipped.empty()) j["composite_skipped"] = r.composite_skipped;
  if (!r.drift_skipped.empty()) j["drift_skipped"] = r.drift_skipped;
  if (r.twin_check) j["twin_check"] = twin_check_json(r);
  return j;
}

AnalysisResult analysis_result_from_json(const json& j, const std::string& where) { return read_result(j, where); }

json to_json(const AnalysisDocument& d) {
  json j = to_json(d.result);
  j["command"] = d.command;
  return j;
}

AnalysisDocument parse_analysis_json(const std::string& text, const std::string& label) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) throw UsageError(label + ": not an analysis.json written by cubecal analyze (not valid JSON)");
  AnalysisDocument d;
  d.result = read_result(j, label);
  if (j.contains("command") && j["command"].is_string()) d.command = j["command"].get<std::string>();
  for (const auto& c : j["channels"]) {
    const json& n = c["drift"].contains("points") ? c["drift"]["points"] : json();
    d.drift_points.push_back(n.is_number_unsigned() ? n.get<std::size_t>() : 0);
  }
  return d;
}

json to_json(const DevResult& r) {
  json j = json::object();
  j["stat"] = to_string(r.stat);
  j["type"] = to_string(r.type);
  j["rate_hz"] = r.rate_hz;
  j["file"] = r.file;
  j["samples"] = r.samples;
  j["segments"] = r.segments;
  j["ci"] = r.options.intervals ? json(r.options.ci) : json(nullptr);
  j["edf_method"] = edf_name(r.options.edf);
  json cols = json::array();
  for (const auto& ch : r.channels) {
    json c = curve_json(ch.points, r.options.intervals);
    c["name"] = ch.name;
    if (!ch.strides.empty()) c["stride"] = ch.strides;
    cols.push_back(std::move(c));
  }
  j["columns"] = std::move(cols);
  if (r.window_bound > 0) j["stream"] = {{"window_bound", r.window_bound}};
  write_tau_list(j, r.tau_list);
  return j;
}

DevResult dev_result_from_json(const json& j, const std::string& where) {
  const Node root(j, "", where);
  DevResult r;
  const std::string stat = root.at("stat").str(), type = root.at("type").str();
  const auto s = parse_stat(stat);
  const auto t = parse_data_type(type);
  if (!s) root.at("stat").fail("unknown statistic '" + stat + "'");
  if (!t) root.at("type").fail("unknown data type '" + type + "'");
  r.stat = *s;
  r.type = *t;
  r.rate_hz = root.num("rate_hz");
  if (!(r.rate_hz > 0)) root.at("rate_hz").fail("not positive");
  r.tau0 = 1.0 / r.rate_hz;
  r.file = root.at("file").str();
  r.samples = root.at("samples").count();
  r.segments = root.at("segments").count();
  r.options.intervals = root.has("ci");
  if (r.options.intervals) r.options.ci = root.num("ci");
  const std::string edf = root.str_or("edf_method", "greenhall");
  if (edf != "greenhall" && edf != "simple") root.at("edf_method").fail("neither 'greenhall' nor 'simple'");
  r.options.edf = edf == "simple" ? EdfMethod::simple : EdfMethod::greenhall;
  const Node cols = root.at("columns");
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const Node cj = cols.at(c);
    r.channels.push_back({cj.at("name").str(), read_curve(cj), {}});
    if (cj.has("stride")) {
      const Node st = cj.at("stride");
      for (std::size_t k = 0; k < st.size(); ++k) r.channels.back().strides.push_back(st.at(k).count());
    }
  }
  if (root.has("stream")) r.window_bound = root.at("stream").at("window_bound").count();
  r.tau_list = read_tau_list(root);
  return r;
}

}  // namespace cubecal::pipeline
