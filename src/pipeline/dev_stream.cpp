#include "cubecal/pipeline/dev_stream.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/stats/streaming_deviation.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

std::size_t window_bound_for(std::size_t memory_bytes, std::size_t channels) {
  const std::size_t share = memory_bytes / 4 / std::max<std::size_t>(channels, 1);
  std::size_t bound = std::size_t{1} << 12;
  while (bound < (std::size_t{1} << 16) && streaming_bytes(bound * 2) <= share) bound *= 2;
  return bound;
}

void check_streamable(const DevRequest& req) {
  if (!streams(req.stat))
    throw UsageError(Field::stat, std::string(to_string(req.stat)) +
                                      " needs the whole record in memory (its terms average over every window): "
                                      "use adev, oadev, hdev or ohdev with {stream}, or leave out {stream}");
  if (req.type != DataType::freq)
    throw UsageError(Field::type, "a stream takes frequency (rate) data: leave out {type} phase, or {stream}");
  if (req.grid.kind == TauGrid::Kind::all)
    throw UsageError(Field::taus,
                     "{taus} all is not streamed (every factor would be a pass over each sample): use "
                     "octave, decade or log:K with {stream}");
}

DevResult run_dev_stream(io::SampleStream& in, const DevRequest& req, std::size_t window_bound) {
  check_streamable(req);
  DevResult res;
  res.stat = req.stat;
  res.type = req.type;
  res.rate_hz = in.rate_hz();
  res.tau0 = 1.0 / in.rate_hz();
  res.file = in.file();
  res.options = req.options;
  res.window_bound = window_bound;
  // The grid up to any length the record may turn out to have.
  const std::vector<std::size_t> ms = averaging_factors(req.grid, std::size_t{1} << 50, res.tau0);
  std::vector<StreamingDeviation> acc;
  for (std::size_t c = 0; c < in.names().size(); ++c) acc.emplace_back(req.stat, ms, window_bound);
  io::SampleChunk chunk;
  while (in.next(chunk)) {
    cubecal::detail::for_channels(acc.size(), req.threads, [&](std::size_t c) {
      try {
        acc[c].push(chunk.channels[c]);
      } catch (const std::invalid_argument& e) {
        throw UsageError("column " + in.names()[c] + ": " + e.what() + " (remove or repair it before the analysis)");
      }
    });
    if (req.progress)
      req.progress(in.total_bytes() > 0
                       ? std::min(1.0, static_cast<double>(in.bytes_read()) / static_cast<double>(in.total_bytes()))
                       : 0.0);
  }
  res.samples = acc.empty() ? 0 : acc[0].samples();
  if (res.samples < 3)
    throw InputError(in.file(), 0, 0,
                     "series too short: " + std::to_string(res.samples) + " samples, at least 3 needed",
                     "a longer record is needed");
  res.tau_list = tau_list_outcome(req.grid, req.stat, req.type, res.samples, res.tau0, "the record");
  for (std::size_t c = 0; c < acc.size(); ++c) {
    auto r = acc[c].finish(res.tau0, req.options);
    DevChannel ch{in.names()[c], std::move(r.points), std::move(r.strides)};
    res.channels.push_back(std::move(ch));
  }
  if (res.channels.empty() || res.channels[0].points.empty())
    throw UsageError("series too short for " + std::string(to_string(req.stat)) + ": " + std::to_string(res.samples) +
                     " samples, and no averaging factor of the tau grid fits (record longer data or choose "
                     "smaller taus)");
  if (req.progress) req.progress(1.0);
  return res;
}

}  // namespace cubecal::pipeline
