// Simulated twins against the measured curve (pipeline/twin_check.hpp).
#include "cubecal/pipeline/twin_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cubecal/error.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/deviation.hpp"
#include "../detail/for_channels.hpp"

namespace cubecal::pipeline {

TwinCheck twin_check(const AnalysisResult& r, std::size_t twins, std::uint64_t seed, unsigned threads) {
  if (twins == 0 || twins > 10000)
    throw UsageError(Field::twin_check, "give 1 to 10000 twins, not " + std::to_string(twins));
  std::vector<std::size_t> with;
  for (std::size_t c = 0; c < r.channels.size(); ++c)
    if (r.channels[c].model.composite && !r.channels[c].model.adev.empty()) with.push_back(c);
  if (with.empty())
    throw UsageError(Field::twin_check, "no channel has a twin to simulate" + (r.composite_skipped.empty()
                                                                                   ? std::string(" ({composite} none)")
                                                                                   : " (" + r.composite_skipped + ")"));
  TwinCheck out;
  out.twins = twins;
  out.seed = seed;
  out.samples = r.channels[with.front()].model.samples;
  const std::size_t nc = with.size();
  // [channel][twin][point]: each twin's Allan variance at the curve's taus.
  std::vector<std::vector<std::vector<double>>> avar(nc, std::vector<std::vector<double>>(twins));
  // Every (channel, twin) on the threads, each from its own seed.
  cubecal::detail::for_channels(nc * twins, threads, [&](std::size_t k) {
    const std::size_t i = k / twins, b = k % twins;
    const ModelAnalysis& m = r.channels[with[i]].model;
    const std::vector<double> y = simulate_composite(m.composite->fit.model, m.samples, seed + b);
    TauGrid grid;
    grid.kind = TauGrid::Kind::list;
    for (const StabilityPoint& p : m.adev) grid.taus.push_back(p.tau);
    StabilityOptions o;
    o.intervals = false;
    const std::vector<StabilityPoint> dev = oadev(y, r.rate_hz, DataType::freq, grid, o);
    std::vector<double>& v = avar[i][b];
    v.assign(m.adev.size(), std::numeric_limits<double>::quiet_NaN());
    for (const StabilityPoint& p : dev)
      for (std::size_t j = 0; j < m.adev.size(); ++j)
        if (m.adev[j].m == p.m) v[j] = p.dev * p.dev;
  });

  for (std::size_t i = 0; i < nc; ++i) {
    const ChannelAnalysis& ch = r.channels[with[i]];
    TwinCheckChannel t;
    t.name = ch.name;
    for (std::size_t j = 0; j < ch.model.adev.size(); ++j) {
      const StabilityPoint& p = ch.model.adev[j];
      double sum = 0.0, lo = std::numeric_limits<double>::infinity(), hi = 0.0;
      std::size_t n = 0;
      for (std::size_t b = 0; b < twins; ++b) {
        const double v = avar[i][b][j];
        if (!std::isfinite(v)) continue;
        sum += v;
        lo = std::min(lo, std::sqrt(v));
        hi = std::max(hi, std::sqrt(v));
        ++n;
      }
      if (n == 0 || !(p.dev > 0.0)) continue;
      t.tau.push_back(p.tau);
      t.measured.push_back(p.dev);
      t.twins.push_back(std::sqrt(sum / static_cast<double>(n)));
      t.twins_lo.push_back(lo);
      t.twins_hi.push_back(hi);
      const double e = std::abs(t.twins.back() / p.dev - 1.0);
      if (p.tau <= 10.0 * (1.0 + 1e-12)) t.max_error_10s = std::max(t.max_error_10s, e);
      if (p.tau <= 100.0 * (1.0 + 1e-12)) t.max_error_100s = std::max(t.max_error_100s, e);
      if (e >= t.max_error) {
        t.max_error = e;
        t.max_error_tau_s = p.tau;
      }
    }
    out.channels.push_back(std::move(t));
  }
  return out;
}

}  // namespace cubecal::pipeline
