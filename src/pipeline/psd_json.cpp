#include "cubecal/pipeline/psd_json.hpp"

#include <string>

#include "cubecal/spectral/density_unit.hpp"

namespace cubecal::pipeline {

namespace {

// The unit of a term's value in the data unit and seconds (noise_terms.hpp).
std::string raw_term_unit(Term t, const std::string& u) {
  switch (t) {
    case Term::Q: return u + "*s";
    case Term::N: return u + "*sqrt(s)";
    case Term::B: return u;
    case Term::K: return u + "/sqrt(s)";
    case Term::R: return u + "/s";
  }
  return u;
}

nlohmann::json channel_json(const PsdChannel& c, bool fitted) {
  nlohmann::json j;
  j["name"] = c.name;
  j["unit"] = c.unit.name.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.unit.name);
  j["density_unit"] = density_unit(c.unit).name;
  j["frequency_hz"] = c.spectrum.frequency;
  j["density"] = c.spectrum.density;
  j["edf"] = c.spectrum.edf;
  j["bins"] = c.spectrum.bins;
  if (const auto rate = rate_density_unit(c.unit)) {
    std::vector<double> v(c.spectrum.density.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = c.spectrum.density[i] * rate->factor;
    j["density_rate"] = {{"unit", rate->name}, {"values", v}};
  }
  if (fitted && !c.fit_error.empty()) {
    j["fit"] = nullptr;
    j["fit_error"] = c.fit_error;
    j["allan_terms"] = nlohmann::json::array();
  } else if (fitted) {
    j["fit"] = power_law_fit_json(c.fit, c.unit);
    const std::string u = c.unit.name.empty() ? "u" : c.unit.name;
    nlohmann::json terms = nlohmann::json::array();
    for (const auto& a : c.allan_terms)
      terms.push_back(
          {{"term", std::string(to_string(a.term))},
           {"alpha", a.alpha},
           {"valid", a.estimate.valid},
           {"value", a.estimate.value},
           {"sigma", a.estimate.sigma},
           {"unit", raw_term_unit(a.term, u)},
           {"display", {{"value", a.display.value}, {"sigma", a.display.sigma}, {"unit", a.display.unit}}}});
    j["allan_terms"] = terms;
  }
  return j;
}

}  // namespace

nlohmann::json to_json(const PsdResult& r) {
  nlohmann::json j;
  j["command"] = "psd";
  j["file"] = r.file;
  j["rate_hz"] = r.rate_hz;
  j["samples"] = r.samples;
  j["pieces"] = r.pieces;
  j["pieces_used"] = r.pieces_used;
  j["one_sided"] = true;
  if (!r.channels.empty()) {
    j["welch"] = welch_json(r.channels.front().spectrum, r.overlap);
    j["welch"]["bins_per_decade"] = r.bins_per_decade;
  }
  nlohmann::json channels = nlohmann::json::array();
  for (const auto& c : r.channels) channels.push_back(channel_json(c, r.fitted));
  j["channels"] = channels;
  return j;
}

nlohmann::json power_law_fit_json(const PowerLawFit& f, const Unit& unit) {
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& t : f.terms)
    terms.push_back({{"alpha", t.alpha},
                     {"h", t.h},
                     {"sigma", t.sigma},
                     {"valid", t.valid},
                     {"unit", power_law_unit(unit, t.alpha)},
                     {"f_lo_hz", t.f_lo},
                     {"f_hi_hz", t.f_hi}});
  nlohmann::json cov = nlohmann::json::array();
  const std::size_t p = f.terms.size();
  for (std::size_t i = 0; i < p; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (std::size_t j = 0; j < p && i < f.covariance.rows() && j < f.covariance.cols(); ++j)
      row.push_back(f.covariance(i, j));
    cov.push_back(std::move(row));
  }
  return {{"f_lo_hz", f.f_lo}, {"f_hi_hz", f.f_hi}, {"bands", f.bands}, {"chi2", f.chi2},
          {"dof", f.dof},      {"scale", f.scale},  {"terms", terms},   {"covariance", cov}};
}

nlohmann::json welch_json(const Psd& s, double overlap) {
  return {{"window", std::string(to_string(s.window))},
          {"segment_length", s.segment_length},
          {"overlap", overlap},
          {"overlap_samples", s.overlap},
          {"detrend", std::string(to_string(s.detrend))},
          {"segments", s.segments},
          {"samples_used", s.samples_used},
          {"resolution_hz", s.resolution_hz()},
          {"enbw_hz", s.enbw_hz}};
}

}  // namespace cubecal::pipeline
