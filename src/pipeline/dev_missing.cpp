#include "cubecal/pipeline/dev_missing.hpp"

#include <omp.h>

#include <exception>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/stats/gap_deviation.hpp"
#include "cubecal/stats/tau_exclusions.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

std::vector<std::size_t> missing_per_channel(const io::Series& series) {
  std::vector<std::size_t> out;
  for (const auto& c : series.channels) out.push_back(missing_samples(c));
  return out;
}

DevResult run_dev_skipping_missing(const io::Series& series, const DevRequest& request) {
  if (request.stat != Stat::oadev)
    throw UsageError(Field::stat,
                     "missing samples are skipped for OADEV only (as AllanTools' gradev): give {stat} "
                     "oadev, or {gaps} split to analyze the contiguous pieces with " +
                         std::string(to_string(request.stat)));
  DevResult r;
  r.stat = request.stat;
  r.type = request.type;
  r.rate_hz = series.rate_hz;
  r.tau0 = series.tau0;
  r.samples = series.samples();
  r.segments = 1;
  r.segments_used = 1;
  r.file = series.file;
  r.options = request.options;
  const std::size_t n_phase = request.type == DataType::freq ? r.samples + 1 : r.samples;
  const std::vector<std::size_t> ms =
      averaging_factors(request.grid, max_averaging_factor(request.stat, n_phase), r.tau0);
  r.tau_list = tau_list_outcome(request.grid, request.stat, request.type, r.samples, r.tau0);
  if (ms.empty())
    throw UsageError("the record (" + std::to_string(r.samples) + " samples) is too short for any tau of the grid");
  r.channels.resize(series.channels.size());
  const int threads = request.threads > 0 ? static_cast<int>(request.threads) : omp_get_max_threads();
  cubecal::detail::for_channels(series.channels.size(), cubecal::detail::Team{threads}, [&](std::size_t k) {
    r.channels[k].name = series.names[k];
    // A factor without a whole term has no point, as run_dev leaves out
    // a factor no segment holds.
    for (const StabilityPoint& p :
         oadev_skipping_missing(series.channels[k], request.type, r.tau0, ms, request.options))
      if (p.n > 0) r.channels[k].points.push_back(p);
  });
  for (std::size_t k = 0; k < r.channels.size(); ++k)
    if (r.channels[k].points.empty())
      throw UsageError("column " + r.channels[k].name +
                       ": no OADEV term without a missing sample at any tau of "
                       "the grid (" +
                       std::to_string(missing_samples(series.channels[k])) + " of " + std::to_string(r.samples) +
                       " samples missing)");
  return r;
}

}  // namespace cubecal::pipeline
