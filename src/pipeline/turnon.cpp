#include "cubecal/pipeline/turnon.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>

#include "cubecal/error.hpp"

namespace cubecal::pipeline {

namespace {

RunSummary summarize(const io::Series& s, const AnalyzeRequest& req) {
  AnalysisResult r = run_analyze(s, req);
  RunSummary rs;
  rs.file = s.file;
  rs.samples = r.samples;
  rs.rate_hz = r.rate_hz;
  for (auto& c : r.channels)
    rs.channels.push_back(
        {std::move(c.name), std::move(c.unit), c.mean, c.stddev, std::move(c.noise.adev), c.noise.readoffs});
  return rs;
}

}  // namespace

std::vector<RunSummary> run_compare(const std::vector<io::Series>& runs, const AnalyzeRequest& req) {
  std::vector<RunSummary> out;
  for (const auto& s : runs) out.push_back(summarize(s, req));
  return out;
}

std::vector<RunSummary> run_compare(const std::vector<io::Series>& runs, const std::vector<AnalyzeRequest>& requests) {
  if (requests.size() != runs.size())
    throw UsageError(std::to_string(requests.size()) + " requests for " + std::to_string(runs.size()) + " runs");
  std::vector<RunSummary> out;
  for (std::size_t k = 0; k < runs.size(); ++k) out.push_back(summarize(runs[k], requests[k]));
  return out;
}

TurnOnResult run_turnon(const std::vector<io::Series>& runs, const AnalyzeRequest& req) {
  if (runs.size() < 2)
    throw UsageError("turn-on bias needs at least 2 runs (power cycles), got " + std::to_string(runs.size()));
  for (const auto& s : runs)
    if (s.names != runs.front().names)
      throw UsageError(Field::columns, s.file + ": columns differ from " + runs.front().file +
                                           " (choose the same columns in every run)");
  TurnOnResult t;
  t.ci = req.ci;
  t.runs = run_compare(runs, req);
  const std::size_t nch = runs.front().names.size();
  t.names = runs.front().names;
  for (const auto& c : t.runs.front().channels) t.units.push_back(c.unit);
  const double k = static_cast<double>(t.runs.size());
  const boost::math::chi_squared chi(k - 1.0);
  const double tail = (1.0 - req.ci) / 2.0;
  const double q_lo = boost::math::quantile(chi, tail), q_hi = boost::math::quantile(chi, 1.0 - tail);
  for (std::size_t c = 0; c < nch; ++c) {
    double mean = 0.0;
    for (const auto& r : t.runs) mean += r.channels[c].mean;
    mean /= k;
    double ss = 0.0;
    for (const auto& r : t.runs) ss += (r.channels[c].mean - mean) * (r.channels[c].mean - mean);
    const double sd = std::sqrt(ss / (k - 1.0));
    t.mean_bias.push_back(mean);
    t.turn_on.push_back(sd);
    // (k-1) s^2 / sigma^2 ~ chi^2(k-1): the interval of sigma.
    t.turn_on_interval.push_back({sd * std::sqrt((k - 1.0) / q_hi), sd * std::sqrt((k - 1.0) / q_lo)});
  }
  return t;
}

}  // namespace cubecal::pipeline
