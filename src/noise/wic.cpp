// The Wavelet Information Criterion of a composite model's fit
// (noise/wic.hpp; docs/formulas/noise-terms.md §8c).
#include "cubecal/noise/wic.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "cubecal/error.hpp"
#include "cubecal/noise/gmwm_asymptotics.hpp"

namespace cubecal {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

}  // namespace

std::vector<CompositeModel> default_candidate_models() {
  return parse_candidate_models("WN, WN+RW, WN+GM, WN+QN+RW, WN+QN+GM, WN+GM+RW, WN+2*GM, WN+2*GM+RW, WN+QN+GM+RW");
}

std::vector<CompositeModel> parse_candidate_models(const std::string& text) {
  const std::string t = trim(text);
  if (t == "auto" || t == "AUTO") return default_candidate_models();
  std::vector<CompositeModel> out;
  std::vector<std::string> names;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = text.find(',', from);
    const std::string piece = trim(text.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
    if (piece.empty())
      throw UsageError(Field::model,
                       "model list '" + text + "': an empty model between commas (give e.g. WN+RW,WN+GM)");
    CompositeModel m = parse_composite_model(piece);
    // The same terms in another order are the same model.
    std::string key;
    for (const Process& p : m.processes) key += to_string(p.kind);
    std::sort(key.begin(), key.end());
    if (std::find(names.begin(), names.end(), key) != names.end())
      throw UsageError(Field::model, "model list '" + text + "': " + model_name(m) + " is named twice");
    names.push_back(std::move(key));
    out.push_back(std::move(m));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return out;
}

std::vector<double> wic_weights(const WaveletVariance& wv, const std::vector<double>& reference) {
  std::vector<double> sd(wv.size());
  for (std::size_t j = 0; j < wv.size(); ++j) sd[j] = reference[j] * std::sqrt(2.0 / wv.edf[j]);
  return sd;
}

WicScore wic_score(const WaveletVariance& wv, const std::vector<double>& sd, const GmwmFit& fit,
                   const std::vector<WicReplicate>& replicates) {
  const std::size_t J = wv.size();
  std::vector<double> omega(J);
  for (std::size_t j = 0; j < J; ++j) omega[j] = 1.0 / (sd[j] * sd[j]);
  WicScore s;
  for (std::size_t j = 0; j < J; ++j) {
    const double d = wv.nu2[j] - fit.nu2_model[j];
    s.loss += omega[j] * d * d;
  }
  std::vector<const WicReplicate*> ok;
  for (const WicReplicate& r : replicates)
    if (r.nu2.size() == J && r.model.size() == J) ok.push_back(&r);
  s.replicates = ok.size();
  if (ok.size() < 2)
    throw UsageError(Field::model, "the WIC's optimism needs at least 2 bootstrap replicates with a fit, not " +
                                       std::to_string(ok.size()));
  const double n = static_cast<double>(ok.size());
  double optimism = 0.0;
  for (std::size_t j = 0; j < J; ++j) {
    double mx = 0.0, my = 0.0;
    for (const WicReplicate* r : ok) {
      mx += r->nu2[j];
      my += r->model[j];
    }
    mx /= n;
    my /= n;
    double cov = 0.0;
    for (const WicReplicate* r : ok) cov += (r->nu2[j] - mx) * (r->model[j] - my);
    optimism += omega[j] * cov / (n - 1.0);
  }
  s.optimism = 2.0 * optimism;
  s.wic = s.loss + s.optimism;
  return s;
}

WicScore wic_score_asymptotic(const WaveletVariance& wv, const std::vector<double>& sd, const GmwmFit& fit,
                              std::size_t samples, double inflation, bool pseudo_inverse) {
  const std::size_t J = wv.size();
  WicScore s;
  for (std::size_t j = 0; j < J; ++j) {
    const double d = (wv.nu2[j] - fit.nu2_model[j]) / sd[j];
    s.loss += d * d;
  }
  const GmwmAsymptotics a = gmwm_asymptotics(fit, wv, samples, 1.0, pseudo_inverse);
  double tr = 0.0;  // tr(Omega V P') = sum_jk Omega_jj V_jk P_jk
  for (std::size_t j = 0; j < J; ++j)
    for (std::size_t k = 0; k < J; ++k) tr += a.nu2_covariance(j, k) * a.hat(j, k) / (sd[j] * sd[j]);
  s.optimism = 2.0 * inflation * tr;
  s.wic = s.loss + s.optimism;
  return s;
}

void rank_by_wic(std::vector<CandidateFit>& candidates) {
  std::stable_sort(candidates.begin(), candidates.end(), [](const CandidateFit& a, const CandidateFit& b) {
    if (a.score.wic != b.score.wic) return a.score.wic < b.score.wic;
    return parameter_count(a.structure) < parameter_count(b.structure);
  });
  if (candidates.empty()) return;
  // Within 2 of the lowest WIC, the fewest parameters.
  const double band = candidates.front().score.wic + 2.0;
  std::size_t pick = 0;
  for (std::size_t i = 1; i < candidates.size() && candidates[i].score.wic <= band; ++i)
    if (parameter_count(candidates[i].structure) < parameter_count(candidates[pick].structure)) pick = i;
  std::rotate(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(pick),
              candidates.begin() + static_cast<std::ptrdiff_t>(pick) + 1);
}

}  // namespace cubecal
