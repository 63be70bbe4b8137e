// The twin (noise/twin_selection.hpp through pipeline::run_model "twin"):
// the lines of a spectrum (spectral/spectral_lines.hpp), the selection's
// recovery of the true structure on seeded composite sensors with lines, its
// fidelity, the twin error on an Allan curve (noise/twin_error.hpp), and the
// SIN term's GMWM fit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/twin_error.hpp"
#include "cubecal/noise/twin_selection.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/welch_psd.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/spectral/spectral_lines.hpp"
#include "cubecal/stats/deviation.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {
namespace {

constexpr double kRate = 100.0;
constexpr double kDt = 1.0 / kRate;

io::Series series_of(std::vector<double> y) {
  io::Series s;
  s.file = "twin";
  s.rate_hz = kRate;
  s.tau0 = kDt;
  s.names = {"gyro"};
  const std::size_t n = y.size();
  s.channels.push_back(std::move(y));
  s.segments = {IndexRange{0, n}};
  return s;
}

// Sensors a MEMS record shows, each term dominant over a range of scales
// of a 2^18-sample (44 min) record at 100 Hz. (A quantized white noise,
// WN+QN, is an MA1 of negative theta: the same wavelet variance, so the
// last one stands for both.)
std::map<std::string, CompositeModel> true_models() {
  std::map<std::string, CompositeModel> m;
  m["WN+RW"] = {{Process{ProcessKind::wn, 1.0}, Process{ProcessKind::rw, 1e-6}}};
  m["MA1+RW+GM"] = {
      {Process{ProcessKind::ma1, 1.0, 0.0, 0.3}, Process{ProcessKind::rw, 4e-6}, gm_process(2.0, 0.25, kDt)}};
  m["WN+GM+SIN"] = {{Process{ProcessKind::wn, 1.0}, gm_process(20.0, 0.15, kDt), sin_process(0.8, 7.0, kDt)}};
  m["MA1+RW+GM+SIN"] = {{Process{ProcessKind::ma1, 1.0, 0.0, 0.2}, Process{ProcessKind::rw, 4e-6},
                         gm_process(1.0, 0.3, kDt), sin_process(1.0, 20.0, kDt)}};
  m["MA1+RW"] = {{Process{ProcessKind::ma1, 1.0, 0.0, -0.4}, Process{ProcessKind::rw, 1e-6}}};
  return m;
}

TEST(SpectralLines, FindsTheLinesOfAToneAndAResonanceAndNoneInWhiteNoise) {
  // White noise alone: no line (the false-alarm rate is 1e-3 per spectrum).
  std::size_t false_lines = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const std::vector<double> y = simulate_composite({{Process{ProcessKind::wn, 1.0}}}, 1 << 17, seed);
    false_lines += find_spectral_lines(pipeline::welch_psd(y, kRate)).size();
  }
  EXPECT_EQ(false_lines, 0u);
  // A tone of A = 0.3 at 12.5 Hz over white noise of unit variance: its
  // frequency to a bin, its power A^2 / 2 to 10 %.
  const CompositeModel tone{{Process{ProcessKind::wn, 1.0}, sin_process(0.3, 12.5, kDt)}};
  const std::vector<SpectralLine> lines =
      find_spectral_lines(pipeline::welch_psd(simulate_composite(tone, 1 << 18, 3), kRate));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NEAR(lines[0].frequency_hz, 12.5, 100.0 / 32768);
  EXPECT_NEAR(lines[0].power, 0.045, 0.0045);
  // Half the frequency of the tone: 2 lines, the stronger first.
  const CompositeModel two{{Process{ProcessKind::wn, 1.0}, sin_process(0.3, 12.5, kDt), sin_process(0.6, 3.0, kDt)}};
  const std::vector<SpectralLine> both =
      find_spectral_lines(pipeline::welch_psd(simulate_composite(two, 1 << 18, 4), kRate));
  ASSERT_EQ(both.size(), 2u);
  EXPECT_NEAR(both[0].frequency_hz, 3.0, 0.01);
  EXPECT_NEAR(both[1].frequency_hz, 12.5, 0.01);
}

TEST(Twin, SinTermFitBringsAmplitudeAndFrequencyBack) {
  // The exact wavelet variance of WN + SIN, the fit started at the line: the
  // parameters back to 1e-6.
  const CompositeModel truth{{Process{ProcessKind::wn, 1.0}, sin_process(0.8, 7.0, kDt)}};
  WaveletVariance wv;
  for (double tau = 2; tau <= 65536; tau *= 2) {
    wv.tau.push_back(tau);
    wv.nu2.push_back(haar_wavelet_variance(truth, tau));
    wv.edf.push_back(std::max(262144.0 / tau, 1.0));
    wv.n.push_back(262144 - static_cast<std::size_t>(tau) + 1);
    wv.interval.push_back({wv.nu2.back() * 0.9, wv.nu2.back() * 1.1});
  }
  CompositeModel structure = parse_composite_model("WN+SIN");
  structure.processes[1] = sin_process(0.7, 7.03, kDt);  // the start a spectrum gives
  const GmwmFit fit = fit_gmwm(wv, structure);
  EXPECT_NEAR(fit.model.processes[0].value, 1.0, 1e-6);
  EXPECT_NEAR(sine_term(fit.model.processes[1], kDt).amplitude, 0.8, 1e-6);
  EXPECT_NEAR(sine_term(fit.model.processes[1], kDt).frequency_hz, 7.0, 1e-6);
}

// The selection on seeded records of each true model: the structure comes
// back in at least 90 % of cases overall, and the selected twin lies inside
// the intervals at nearly every scale.
TEST(Twin, SelectionRecoversTheTrueStructureOfSeededSensors) {
  std::size_t right = 0, total = 0, faithful = 0;
  std::string misses;
  pipeline::ModelRequest req = pipeline::twin_request();
  req.threads = 1;
  for (const auto& [name, model] : true_models()) {
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      const pipeline::ModelResult r = pipeline::run_model(series_of(simulate_composite(model, 1 << 18, seed)), req);
      const pipeline::ModelChannel& ch = r.channels.front();
      ++total;
      faithful += ch.faithful ? 1 : 0;
      std::string got = ch.model;
      if (got.rfind("WN+QN", 0) == 0) got = "MA1" + got.substr(5);  // the same wavelet variance
      if (got == name)
        ++right;
      else
        misses += " " + name + "->" + ch.model;
    }
  }
  std::printf("twin selection: the true structure in %zu of %zu records, faithful %zu;%s\n", right, total, faithful,
              misses.c_str());
  EXPECT_GE(static_cast<double>(right), 0.9 * static_cast<double>(total)) << right << " of " << total << ":" << misses;
  EXPECT_GE(static_cast<double>(faithful), 0.9 * static_cast<double>(total)) << faithful << " of " << total;
}

TEST(Twin, TwinErrorOnTheAllanCurve) {
  const CompositeModel model{{Process{ProcessKind::wn, 1.0}, Process{ProcessKind::rw, 1e-7}}};
  const std::vector<double> y = simulate_composite(model, 1 << 18, 9);
  const std::vector<StabilityPoint> curve = oadev(y, kRate);
  const TwinError e = twin_error(model, curve);
  EXPECT_EQ(e.taus, curve.size());
  // The true model: inside most of the 68.3 % intervals, and near the curve
  // where many terms are averaged.
  EXPECT_GE(e.share_inside, 0.5);
  const TwinError short_taus = twin_error(model, curve, 1.0);
  EXPECT_LT(short_taus.max_error, 0.02);
  EXPECT_LE(short_taus.taus, 7u);
  // A model twice as noisy: 41 % off everywhere, inside nowhere.
  CompositeModel twice = model;
  for (Process& p : twice.processes) p.value *= 2.0;
  const TwinError bad = twin_error(twice, curve, 1.0);
  EXPECT_EQ(bad.inside, 0u);
  EXPECT_GT(bad.max_error, 0.38);
}

TEST(Twin, RefusesARecordTooShort) {
  pipeline::ModelRequest req = pipeline::twin_request();
  const std::vector<double> y = simulate_composite({{Process{ProcessKind::wn, 1.0}}}, 10, 1);
  EXPECT_THROW((void)pipeline::run_model(series_of(y), req), UsageError);
}

}  // namespace
}  // namespace cubecal
