// cubecal model: the fit the command prints is the library's on the same
// samples, a seeded composite record's terms come back in the units people
// quote, the bootstrap is reproducible and does not depend on the threads,
// candidates are ranked by the WIC and the selected one fitted, and bad
// input is one error line with exit 2.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

namespace cubecal::test {
namespace {

constexpr double kRate = 10.0;

// WN + GM in deg/s at 10 Hz: N = 0.3 deg/sqrt(h), a Gauss-Markov bias of
// 20 deg/h with T_c = 60 s.
CompositeModel gyro() {
  CompositeModel m = parse_composite_model("WN+GM");
  const double dt = 1.0 / kRate;
  const double n_deg_per_sqrt_s = 0.3 / 60.0;  // deg/sqrt(h) -> deg/sqrt(s)
  m.processes[0].value = n_deg_per_sqrt_s * n_deg_per_sqrt_s / dt;
  m.processes[1] = gm_process(60.0, 20.0 / 3600.0, dt);
  return m;
}

class ModelCli : public TempDirTest {
 protected:
  std::string record(std::size_t n, std::vector<double>* out = nullptr) {
    const std::vector<double> y = simulate_composite(gyro(), n, 7);
    if (out) *out = y;
    std::ostringstream text;
    text.precision(17);
    text << "t,gx\n";
    for (std::size_t i = 0; i < n; ++i) text << static_cast<double>(i) / kRate << ',' << y[i] << '\n';
    return write("gyro.csv", text.str());
  }
};

const nlohmann::json& quantity(const nlohmann::json& channel, const std::string& term, const std::string& name) {
  for (const auto& t : channel.at("terms"))
    if (t.at("term") == term)
      for (const auto& q : t.at("quantities"))
        if (q.at("name") == name) return q;
  throw std::runtime_error("no " + term + " " + name);
}

TEST_F(ModelCli, JsonIsTheLibraryFitInQuotedUnits) {
  std::vector<double> y;
  const std::string file = record(200000, &y);
  const CliRun r = run_cubecal("model " + file + " --model wn+gm --unit deg/s --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("command"), "model");
  EXPECT_EQ(j.at("model"), "WN+GM");
  const auto& c = j.at("channels").at(0);
  // The library on the same doubles (the CSV holds them exactly).
  const WaveletVariance wv = wavelet_variance(y);
  const GmwmFit fit = fit_gmwm(wv, parse_composite_model("WN+GM"));
  EXPECT_EQ(c.at("wavelet_variance").at("nu2").get<std::vector<double>>(), wv.nu2);
  EXPECT_EQ(c.at("wavelet_variance").at("model").get<std::vector<double>>(), fit.nu2_model);
  EXPECT_EQ(c.at("terms").at(0).at("parameters").at("value").get<double>(), fit.model.processes[0].value);
  // N in deg/sqrt(h), sigma_b in deg/h, T_c in s: near the truth (one
  // record; 200000 samples hold N to ~0.2 %, the bias's terms to ~10 %).
  const auto& n = quantity(c, "WN", "N");
  EXPECT_EQ(n.at("display").at("unit"), "deg/sqrt(h)");
  EXPECT_NEAR(n.at("display").at("value").get<double>(), 0.3, 0.3 * 0.01);
  EXPECT_NEAR(n.at("value").get<double>() * 60.0, n.at("display").at("value").get<double>(), 1e-12);
  const auto& sb = quantity(c, "GM", "sigma_b");
  EXPECT_EQ(sb.at("display").at("unit"), "deg/h");
  EXPECT_NEAR(sb.at("display").at("value").get<double>(), 20.0, 20.0 * 0.25);
  EXPECT_NEAR(quantity(c, "GM", "T_c").at("value").get<double>(), 60.0, 60.0 * 0.4);
  EXPECT_TRUE(n.at("sd").is_null());  // no bootstrap asked for
  // The table says the same.
  const CliRun t = run_cubecal("model " + file + " --model WN+GM --unit deg/s");
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("deg/sqrt(h)"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("GM  Gauss-Markov"), std::string::npos) << t.out;
}

// MA1+GM (a sensor's averaging filter, N = 0.3 deg/sqrt(h), theta = 0.25):
// N in deg/sqrt(h) and theta come back within 4 of their sandwich standard
// deviations, the JSON reads back to the same terms, the table names the
// term, and WN beside MA1 is refused.
TEST_F(ModelCli, MovingAverageTermInQuotedUnitsAndJsonRoundTrip) {
  const double dt = 1.0 / kRate;
  CompositeModel m = parse_composite_model("MA1+GM");
  m.processes[0] = ma1_process(0.3 / 60.0, 0.25, dt);
  m.processes[1] = gyro().processes[1];
  const std::vector<double> y = simulate_composite(m, 200000, 11);
  std::ostringstream text;
  text.precision(17);
  text << "t,gx\n";
  for (std::size_t i = 0; i < y.size(); ++i) text << static_cast<double>(i) * dt << ',' << y[i] << '\n';
  const std::string file = write("ma.csv", text.str());
  const CliRun r = run_cubecal("model " + file + " --model ma1+gm --unit deg/s --format json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& c = j.at("channels").at(0);
  const auto& n = quantity(c, "MA1", "N");
  EXPECT_EQ(n.at("display").at("unit"), "deg/sqrt(h)");
  EXPECT_NEAR(n.at("display").at("value").get<double>(), 0.3, 4.0 * n.at("display").at("asymptotic_sd").get<double>());
  const auto& th = quantity(c, "MA1", "theta");
  EXPECT_EQ(th.at("unit"), "");
  EXPECT_NEAR(th.at("value").get<double>(), 0.25, 4.0 * th.at("asymptotic_sd").get<double>());
  EXPECT_GT(th.at("asymptotic_sd").get<double>(), 0.0);
  EXPECT_EQ(c.at("terms").at(0).at("parameters").at("theta").get<double>(), th.at("value").get<double>());
  const pipeline::ModelResult back = pipeline::model_result_from_json(j, "model.json");
  EXPECT_EQ(back.channels.at(0).terms.at(0).process.theta, th.at("value").get<double>());
  EXPECT_EQ(pipeline::to_json(back).at("channels").at(0).at("terms"), c.at("terms"));
  const CliRun t = run_cubecal("model " + file + " --model MA1+GM --unit deg/s");
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("MA1 moving average"), std::string::npos) << t.out;
  const CliRun bad = run_cubecal("model " + file + " --model WN+MA1");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("MA1 with WN"), std::string::npos) << bad.err;
}

TEST_F(ModelCli, BootstrapIsReproducibleOnAnyThreadsAndHoldsTheTruth) {
  const std::string file = record(100000);
  const std::string args = "model " + file + " --model WN+GM --unit deg/s --format json --bootstrap 40 --seed 5";
  const CliRun one = run_cubecal(args + " --threads 1");
  const CliRun two = run_cubecal(args + " --threads 2");
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(one.out, two.out);
  const auto c = nlohmann::json::parse(one.out).at("channels").at(0);
  EXPECT_GE(c.at("replicates").get<int>(), 38);
  const auto& n = quantity(c, "WN", "N");
  const double lo = n.at("display").at("lo").get<double>(), hi = n.at("display").at("hi").get<double>();
  const double v = n.at("display").at("value").get<double>(), sd = n.at("display").at("sigma").get<double>();
  EXPECT_LT(lo, v);
  EXPECT_GT(hi, v);
  EXPECT_GT(sd, 0.0);
  // The truth within four bootstrap standard deviations of the estimate.
  EXPECT_LT(std::abs(v - 0.3), 4.0 * sd) << v << " ± " << sd;
  const auto& tc = quantity(c, "GM", "T_c");
  EXPECT_LT(std::abs(tc.at("value").get<double>() - 60.0), 4.0 * tc.at("sd").get<double>());
}

TEST_F(ModelCli, CandidatesAreRankedByTheWicAndTheSelectedOneIsFitted) {
  std::vector<double> y;
  const std::string file = record(100000, &y);
  const std::string args = "model " + file +
                           " --model WN,WN+RW,WN+GM,WN+2*GM --unit deg/s --format json "
                           "--wic-replicates 20 --seed 3";
  const CliRun one = run_cubecal(args + " --threads 1");
  const CliRun two = run_cubecal(args + " --threads 2");
  ASSERT_EQ(one.code, 0) << one.err;
  EXPECT_EQ(one.out, two.out);  // the bootstrap's draws do not depend on the threads
  const auto j = nlohmann::json::parse(one.out);
  EXPECT_EQ(j.at("model"), "WN,WN+RW,WN+GM,WN+2*GM");
  EXPECT_EQ(j.at("selection_replicates"), 20);
  const auto& c = j.at("channels").at(0);
  // The record is WN+GM with T_c = 60 s, 1700 correlation times long: the
  // white noise alone and the random walk fit it far worse.
  EXPECT_EQ(c.at("model"), "WN+GM");
  const auto& cand = c.at("candidates");
  ASSERT_EQ(cand.size(), 4u);
  EXPECT_EQ(cand.at(0).at("model"), "WN+GM");
  for (const auto& m : cand) {
    EXPECT_NEAR(m.at("wic").get<double>(), m.at("loss").get<double>() + m.at("optimism").get<double>(), 1e-9);
    EXPECT_EQ(m.at("replicates"), 20);
    if (m.at("model") == "WN" || m.at("model") == "WN+RW") {
      EXPECT_GT(m.at("wic").get<double>(), cand.at(0).at("wic").get<double>() + 10.0) << m.at("model");
    }
  }
  // The reported fit is the lone fit's (reweighted) of the selected model,
  // started from its common-weight fit: the same minimum a lone fit finds.
  const GmwmFit lone = fit_gmwm(wavelet_variance(y), parse_composite_model("WN+GM"));
  EXPECT_NEAR(c.at("objective").get<double>(), lone.objective, 1e-6 * lone.objective + 1e-9);
  const CliRun t = run_cubecal("model " + file + " --model WN,WN+GM --unit deg/s --wic-replicates 10");
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("selected WN+GM of 2 candidates by the WIC"), std::string::npos) << t.out;
}

TEST_F(ModelCli, BadInputIsOneLine) {
  const std::string file = record(2000);
  CliRun r = run_cubecal("model " + file + " --model WN+XX");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--model: model 'WN+XX': unknown term 'XX'"), std::string::npos) << r.err;
  r = run_cubecal("model " + file + " --model WN+4*GM+RW");  // 10 parameters, 9 scales
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("more than the"), std::string::npos) << r.err;
  r = run_cubecal("model " + file + " --model WN --bootstrap 1");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--bootstrap"), std::string::npos) << r.err;
  r = run_cubecal("model " + file + " --model WN+RW,RW+WN");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("named twice"), std::string::npos) << r.err;
  r = run_cubecal("model " + file + " --model WN,WN+RW --wic-replicates 1");
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_NE(r.err.find("--wic-replicates"), std::string::npos) << r.err;
  r = run_cubecal("model " + file);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--model"), std::string::npos) << r.err;
}

// A fit the data cannot give is a calibration error on the file, with the
// command's hint and exit 2 (it used to end as an internal error).
TEST_F(ModelCli, NoCandidateThatFitsIsOneLineWithAHint) {
  const std::string file = record(2000);
  // 10 and 11 parameters, 9 scales: no candidate gives a fit.
  const CliRun r = run_cubecal("model " + file + " --model WN+4*GM+RW,WN+QN+4*GM+RW");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(one_error_line(r)) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ": GMWM: no candidate model gave a fit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(give a model with fewer terms (--model) or more starting points (--starts))"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace cubecal::test
