// The Welch PSD equals scipy.signal.welch(scaling="density",
// return_onesided=True) to 1e-10 relative, bin by bin, for every window and
// detrend option (tests/psd_scipy.py, run with Debian's /usr/bin/python3).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "cubecal/pipeline/welch_psd.hpp"

namespace cubecal {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

struct Spec {
  Window window;
  const char* scipy_window;
  Detrend detrend;
  std::size_t nperseg;
  std::size_t noverlap;
};

std::string spec_text(const Spec& s) {
  return std::string(s.scipy_window) + ":" + std::string(to_string(s.detrend)) + ":" + std::to_string(s.nperseg) + ":" +
         std::to_string(s.noverlap);
}

std::vector<std::pair<double, double>> read_pairs(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::pair<double, double>> rows;
  double f = 0.0, p = 0.0;
  while (in >> f >> p) rows.emplace_back(f, p);
  return rows;
}

class ScipyWelch : public test::TempDirTest {};

TEST_F(ScipyWelch, EveryWindowAndDetrendAgreeTo1e10) {
  if (std::FILE* f = std::fopen(kPython, "r"))
    std::fclose(f);
  else
    GTEST_SKIP() << kPython << " is not installed: no scipy to compare with";

  // A record with everything the options act on: an offset and a ramp
  // (detrending), a tone (leakage, the windows), white noise and a walk.
  const double rate = 25.0;
  const std::size_t n = 20000;
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  double walk = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / rate;
    walk += 0.05 * g(rng);
    x[i] = 3.0 + 0.002 * t + 0.7 * std::sin(2.0 * 3.141592653589793 * 1.37 * t) + g(rng) + walk;
  }
  const std::string bin = path("x.bin");
  {
    std::ofstream out(bin, std::ios::binary);
    out.write(reinterpret_cast<const char*>(x.data()), static_cast<std::streamsize>(n * sizeof(double)));
  }

  std::vector<Spec> specs;
  const std::pair<Window, const char*> windows[] = {{Window::hann, "hann"},
                                                    {Window::hamming, "hamming"},
                                                    {Window::blackman, "blackman"},
                                                    {Window::rectangular, "boxcar"}};
  for (const auto& [w, name] : windows)
    for (Detrend d : {Detrend::none, Detrend::constant, Detrend::linear}) specs.push_back({w, name, d, 1000, 500});
  specs.push_back({Window::hann, "hann", Detrend::constant, 999, 333});          // odd length
  specs.push_back({Window::blackman, "blackman", Detrend::linear, 2048, 1536});  // 75 % overlap
  specs.push_back({Window::rectangular, "boxcar", Detrend::none, 1000, 0});      // no overlap

  std::ostringstream command;
  command << kPython << ' ' << CUBECAL_TEST_SOURCE_DIR << "/psd_scipy.py " << bin << " 25 " << path("scipy_");
  for (const Spec& s : specs) command << ' ' << spec_text(s);
  command << " 2>" << path("stderr.txt");
  const std::string cmd = command.str();
  const int status = std::system(cmd.c_str());
  if (WIFEXITED(status) && WEXITSTATUS(status) == 3) {
    std::ifstream err(path("stderr.txt"));
    std::stringstream why;
    why << err.rdbuf();
    GTEST_SKIP() << why.str();
  }
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd;

  double worst = 0.0;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const Spec& s = specs[i];
    WelchOptions o;
    o.window = s.window;
    o.detrend = s.detrend;
    o.segment_length = s.nperseg;
    o.overlap = static_cast<double>(s.noverlap) / static_cast<double>(s.nperseg);
    const Psd p = pipeline::welch_psd(x, rate, o);
    ASSERT_EQ(p.overlap, s.noverlap) << spec_text(s);
    const auto ref = read_pairs(path("scipy_" + std::to_string(i) + ".txt"));
    ASSERT_EQ(ref.size(), p.size()) << spec_text(s);
    double peak = 0.0;
    for (const auto& r : ref) peak = std::max(peak, r.second);
    for (std::size_t k = 0; k < ref.size(); ++k) {
      EXPECT_NEAR(p.frequency[k], ref[k].first, 1e-12 * rate) << spec_text(s) << " bin " << k;
      // The DC bin of a rectangular window after detrending is zero but for
      // rounding in both (the removed mean or line sums the segment to 0):
      // compared absolutely there, on the scale of the spectrum.
      if (k == 0 && s.window == Window::rectangular && s.detrend != Detrend::none) {
        EXPECT_LE(std::abs(p.density[k] - ref[k].second), 1e-10 * peak) << spec_text(s);
        continue;
      }
      const double rel = std::abs(p.density[k] - ref[k].second) / ref[k].second;
      worst = std::max(worst, rel);
      EXPECT_LE(rel, 1e-10) << spec_text(s) << " bin " << k << ": " << p.density[k] << " vs " << ref[k].second;
    }
  }
  std::printf("largest relative difference from scipy.signal.welch over %zu configurations: %.3g\n", specs.size(),
              worst);
  RecordProperty("max_relative_difference", std::to_string(worst));
}

}  // namespace
}  // namespace cubecal
