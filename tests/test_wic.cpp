// Model selection by the Wavelet Information Criterion (noise/wic.hpp,
// pipeline/model_selection.hpp):
// - the candidate list: "auto", commas, the same model twice refused;
// - the optimism of white noise alone is Akaike's 2 (one parameter, scales
//   nearly independent for white noise, Omega close to the inverse
//   covariance): a check of the bootstrap covariance penalty; its
//   asymptotic form agrees with the bootstrap on a composite model;
// - seeded records of WN+RW and WN+GM: the true model ranked first in most
//   seeds, the larger nested models not preferred for their lower loss.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cubecal/error.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/pipeline/model_selection.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal {
namespace {

using pipeline::ModelSelection;
using pipeline::select_composite_model;
using pipeline::WicOptions;

TEST(Wic, CandidateLists) {
  const std::vector<CompositeModel> all = parse_candidate_models("auto");
  EXPECT_EQ(all.size(), default_candidate_models().size());
  EXPECT_GE(all.size(), 8u);
  const std::vector<CompositeModel> two = parse_candidate_models(" WN+RW ,wn+2*gm+rw");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(model_name(two[0]), "WN+RW");
  EXPECT_EQ(model_name(two[1]), "WN+2*GM+RW");
  EXPECT_EQ(parse_candidate_models("WN+GM").size(), 1u);
  EXPECT_THROW(parse_candidate_models("WN+RW,rw + wn"), UsageError);  // one model twice
  EXPECT_THROW(parse_candidate_models("WN+RW,,WN"), UsageError);
  EXPECT_THROW(parse_candidate_models("WN+RW,WN+XX"), UsageError);
}

TEST(Wic, RefusesWhatCannotBeScored) {
  const std::vector<double> y = simulate_composite(parse_composite_model("WN"), 1 << 10, 1);
  const WaveletVariance wv = wavelet_variance(y);
  WicOptions o;
  o.replicates = 1;
  EXPECT_THROW(select_composite_model(wv, y.size(), {parse_composite_model("WN")}, o), UsageError);
  EXPECT_THROW(select_composite_model(wv, y.size(), {}, {}), UsageError);
}

TEST(Wic, WhiteNoiseAloneHasAkaikesOptimism) {
  CompositeModel wn = parse_composite_model("WN");
  wn.processes[0].value = 4.0;
  const std::size_t n = 1 << 15;
  const std::vector<double> y = simulate_composite(wn, n, 11);
  const WaveletVariance wv = wavelet_variance(y);
  WicOptions o;
  o.replicates = 400;
  o.seed = 5;
  const ModelSelection sel = select_composite_model(wv, n, {parse_composite_model("WN")}, o);
  ASSERT_EQ(sel.ranked.size(), 1u);
  const WicScore& s = sel.ranked[0].score;
  EXPECT_EQ(s.replicates, 400u);
  // 2 p = 2 for one parameter; the bootstrap's own error with 400
  // replicates is about 2 sqrt(2 / 400) ~ 0.14, Omega's departure from the
  // inverse covariance (eta3 is approximate) a few tenths.
  EXPECT_NEAR(s.optimism, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(s.wic, s.loss + s.optimism);
}

TEST(Wic, TheAsymptoticOptimismAgreesWithTheBootstrap) {
  // WN + GM + RW at 2^16 samples: the covariance penalty 2 tr(Omega V P')
  // from the model's own wavelet-variance covariance against the
  // bootstrap's, 300 replicates (their own error ~ 2 sqrt(2 / 300) ~ 16 %).
  CompositeModel m = parse_composite_model("WN+GM+RW");
  m.processes[0].value = 1.0;
  m.processes[1] = gm_process(300.0, 0.3, 1.0);
  m.processes[2].value = 1e-6;
  const std::size_t n = 1 << 16;
  const WaveletVariance wv = wavelet_variance(simulate_composite(m, n, 21));
  const std::vector<CompositeModel> cands = parse_candidate_models("WN+GM, WN+GM+RW");
  WicOptions boot;
  boot.replicates = 300;
  WicOptions asym;
  asym.replicates = 0;
  const ModelSelection b = select_composite_model(wv, n, cands, boot);
  const ModelSelection a = select_composite_model(wv, n, cands, asym);
  ASSERT_EQ(a.ranked.size(), 2u);
  ASSERT_EQ(b.ranked.size(), 2u);
  for (const CandidateFit& x : a.ranked)
    for (const CandidateFit& y : b.ranked)
      if (model_name(x.structure) == model_name(y.structure)) {
        EXPECT_EQ(x.score.replicates, 0u);
        EXPECT_DOUBLE_EQ(x.score.loss, y.score.loss);  // the same fit
        EXPECT_NEAR(x.score.optimism, y.score.optimism, 0.3 * y.score.optimism) << model_name(x.structure);
      }
}

// One selection per seed among nested and aliased candidates.
std::size_t true_model_first(const CompositeModel& truth, std::size_t n, int seeds) {
  const std::vector<CompositeModel> candidates = parse_candidate_models("WN, WN+RW, WN+GM, WN+GM+RW, WN+2*GM");
  const std::string want = model_name(truth);
  std::size_t hits = 0;
  for (int s = 0; s < seeds; ++s) {
    const std::vector<double> y = simulate_composite(truth, n, 1000 + static_cast<std::uint64_t>(s));
    const WaveletVariance wv = wavelet_variance(y);
    WicOptions o;
    o.replicates = 20;
    o.seed = 77 + static_cast<std::uint64_t>(s);
    o.gmwm.starts = 8;
    const ModelSelection sel = select_composite_model(wv, n, candidates, o);
    if (model_name(sel.ranked.front().structure) == want) ++hits;
  }
  return hits;
}

TEST(Wic, SelectsTheTrueModelInMostSeeds) {
  CompositeModel wn_rw = parse_composite_model("WN+RW");
  wn_rw.processes[0].value = 1.0;
  wn_rw.processes[1].value = 1e-6;
  CompositeModel wn_gm = parse_composite_model("WN+GM");
  wn_gm.processes[0].value = 1.0;
  wn_gm.processes[1] = gm_process(300.0, 0.3, 1.0);
  const int seeds = 20;
  // The larger nested models fit every record at least as well; a
  // criterion that only counted the loss would pick WN+GM+RW or WN+2*GM
  // nearly always. The WIC is AIC-like, so it overfits in a few seeds.
  EXPECT_GE(true_model_first(wn_rw, 1 << 16, seeds), 15u);
  EXPECT_GE(true_model_first(wn_gm, 1 << 16, seeds), 15u);
}

}  // namespace
}  // namespace cubecal
