// The reported noise terms on the six real ADIS16405 runs
// (../shared/data/imu/adis16405, 1e6 samples each at 100 Hz) against an
// independent read-off: N_ind = sigma_OADEV(tau = 1 s) * sqrt(1 s), computed
// here from the samples at m = 100 with its own code (second differences of
// the phase), and its 68.3 % interval from the EDF of white FM noise
// (NIST SP 1065 eq. 61) and chi-squared quantiles (Wilson-Hilferty).
//
// Where the curve is white at 1 s (its log-log slopes over 0.5..1 s and over
// 1..2 s, also computed here, both within 0.15 of -1/2: the tolerance that
// defines a -1/2 region), cubecal's N must lie inside that interval and be read over
// a tau range that contains 1 s. Where it is not white at 1 s (the
// accelerometers: a bump at 0.3-0.6 s, then a steep fall at 1 s, slope
// -0.9 to -1.2, the mark of a periodic disturbance), N comes from the
// white arm at shorter taus and its range must say so (not contain 1 s).
//
// Prints the table of docs/validation.md ("One N on the ADIS16405 runs"):
//   ./build/tests/test_adis16405_n --gtest_filter='*Table*'
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {
namespace {

// Overlapping Allan deviation of frequency samples y at averaging factor m,
// tau = m tau0: sigma^2 = sum (x[i+2m] - 2 x[i+m] + x[i])^2 / (2 tau^2 (N - 2m)),
// x the phase (running sum of y tau0), N + 1 phase points for N samples.
double oadev(const std::vector<double>& y, std::size_t m, double tau0) {
  const std::size_t n = y.size();
  std::vector<long double> x(n + 1, 0.0L);
  for (std::size_t i = 0; i < n; ++i) x[i + 1] = x[i] + static_cast<long double>(y[i]);
  long double s = 0.0L;
  const std::size_t terms = n + 1 - 2 * m;
  for (std::size_t i = 0; i < terms; ++i) {
    const long double d = (x[i + 2 * m] - 2.0L * x[i + m] + x[i]) * tau0;
    s += d * d;
  }
  const double tau = static_cast<double>(m) * tau0;
  return std::sqrt(static_cast<double>(s / terms) / (2.0 * tau * tau));
}

// EDF of the overlapping Allan variance for white FM noise (NIST SP 1065,
// Table 5 / eq. 61), N phase points.
double edf_white_fm(double n_phase, double m) {
  return (3.0 * (n_phase - 1.0) / (2.0 * m) - 2.0 * (n_phase - 2.0) / n_phase) * 4.0 * m * m / (4.0 * m * m + 5.0);
}

// Chi-squared quantile with nu degrees of freedom at the normal quantile z
// (Wilson-Hilferty; relative error < 1e-6 at nu ~ 1e4).
double chi2_quantile(double nu, double z) {
  const double a = 2.0 / (9.0 * nu);
  const double c = 1.0 - a + z * std::sqrt(a);
  return nu * c * c * c;
}

struct Row {
  std::string run, axis;
  bool white_at_1s = false;
  double slope_below = 0.0;  // log-log slope of the curve over 0.5..1 s and 1..2 s
  double slope_above = 0.0;
  TermEstimate n;  // cubecal's N (read-off, data unit * sqrt(s))
  double n_ind = 0.0, lo = 0.0, hi = 0.0;
  ReportedTerms rep;
  double sigma_min = 0.0, tau_min = 0.0;
};

std::string data_file(int run) {
  return std::string(CUBECAL_SHARED_DATA) + "/imu/adis16405/run" + std::to_string(run) + ".csv.gz";
}

const std::vector<Row>& rows() {
  static const std::vector<Row> all = [] {
    std::vector<Row> out;
    for (int run = 1; run <= 6; ++run) {
      const std::string path = data_file(run);
      if (!std::filesystem::exists(path)) continue;
      const io::Series s = io::read_series(path, io::SeriesOptions{});
      pipeline::DevRequest req;  // as analyze asks for it (pipeline/analyze.cpp)
      req.stat = Stat::oadev;
      req.type = DataType::freq;
      req.grid = parse_tau_grid("log:10");
      req.options.ci = 0.683;
      const pipeline::DevResult d = pipeline::run_dev(s, req);
      for (std::size_t c = 0; c < s.channels.size(); ++c) {
        Row r;
        r.run = "run" + std::to_string(run);
        r.axis = s.names[c];
        const AllanCurve curve = to_allan_curve(d.channels[c].points);
        const SlopeReadOffs ro = read_off_noise_terms(curve);
        r.n = ro.N;
        r.rep = reported_terms(ro, fit_noise_terms(curve), curve);
        r.sigma_min = ro.sigma_min;
        r.tau_min = ro.tau_min;

        const std::vector<double>& y = s.channels[c];
        const double tau0 = s.tau0;
        EXPECT_NEAR(tau0, 0.01, 1e-12);
        const double dev1 = oadev(y, 100, tau0);
        const double below = std::log(dev1 / oadev(y, 50, tau0)) / std::log(2.0);
        const double above = std::log(oadev(y, 200, tau0) / dev1) / std::log(2.0);
        r.slope_below = below;
        r.slope_above = above;
        r.white_at_1s = std::abs(below + 0.5) <= 0.15 && std::abs(above + 0.5) <= 0.15;
        const double nu = edf_white_fm(static_cast<double>(y.size() + 1), 100.0);
        r.n_ind = dev1 * std::sqrt(1.0);
        r.lo = r.n_ind * std::sqrt(nu / chi2_quantile(nu, 1.0));
        r.hi = r.n_ind * std::sqrt(nu / chi2_quantile(nu, -1.0));
        out.push_back(r);
      }
    }
    return out;
  }();
  return all;
}

TEST(Adis16405, NIsSigmaAtOneSecondWhereTheCurveIsWhite) {
  if (rows().empty()) GTEST_SKIP() << "no ADIS16405 data at " << data_file(1);
  ASSERT_EQ(rows().size(), 36u);
  std::size_t white = 0;
  for (const Row& r : rows()) {
    SCOPED_TRACE(r.run + " " + r.axis);
    ASSERT_TRUE(r.n.valid);
    // One N: the reported N is the read-off.
    EXPECT_EQ(r.rep.N.source, TermSource::read_off);
    EXPECT_EQ(r.rep.N.value(), r.n.value);
    const bool range_has_1s = r.n.tau_lo <= 1.0 && 1.0 <= r.n.tau_hi;
    if (r.white_at_1s) {
      ++white;
      EXPECT_TRUE(range_has_1s) << r.n.tau_lo << ".." << r.n.tau_hi;
      EXPECT_GE(r.n.value, r.lo);
      EXPECT_LE(r.n.value, r.hi);
    } else {
      // Not white at 1 s: N is the white arm's line, read where the arm is.
      EXPECT_FALSE(range_has_1s) << r.n.tau_lo << ".." << r.n.tau_hi << " slopes " << r.slope_below << ", "
                                 << r.slope_above;
    }
  }
  // Every gyroscope axis is white at 1 s on these runs.
  EXPECT_GE(white, 18u);
}

TEST(Adis16405, Table) {
  if (rows().empty()) GTEST_SKIP() << "no ADIS16405 data";
  std::printf(
      "| run | axis | N cubecal [u*sqrt(s)] | read over [s] | N_ind = sigma(1 s) | 68.3 %% interval | ratio | "
      "white at 1 s | K estimate [u/sqrt(s)] | K sigma | K significant | K reported | B [u] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows()) {
    char k[64] = "—", ks[64] = "—";
    if (r.rep.K_candidate.valid) {
      std::snprintf(k, sizeof k, "%.3g (%s)", r.rep.K_candidate.value,
                    r.rep.K_candidate_source == TermSource::fit ? "fit" : "read-off");
      std::snprintf(ks, sizeof ks, "%.2g", r.rep.K_candidate.sigma);
    }
    char kr[64];
    std::snprintf(kr, sizeof kr, "%s%.3g", r.rep.K.bound() ? "< " : "", r.rep.K.value());
    char b[96];
    if (r.rep.no_minimum)
      std::snprintf(b, sizeof b, "no minimum within the record (< %.3g)", r.rep.B.value());
    else
      std::snprintf(b, sizeof b, "%.3g ± %.2g (T %.3g s)", r.rep.B.value(), r.rep.B.estimate.sigma, r.tau_min);
    std::printf(
        "| %s | %s | %.5g ± %.2g | %.3g–%.3g | %.5g | %.5g–%.5g | %.4f | %s (%.2f, %.2f) | %s | %s | %s | %s | %s |\n",
        r.run.c_str(), r.axis.c_str(), r.n.value, r.n.sigma, r.n.tau_lo, r.n.tau_hi, r.n_ind, r.lo, r.hi,
        r.n.value / r.n_ind, r.white_at_1s ? "yes" : "no", r.slope_below, r.slope_above, k, ks,
        r.rep.K.bound() ? "no" : "yes", kr, b);
  }
}

}  // namespace
}  // namespace cubecal
