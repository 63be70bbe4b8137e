// cubecal demo: a self-contained tour. Generates a static gyro record with
// the noise model of the paper's MPU-3300 fit (white noise sigma_n, bias
// random walk sigma_mu, fixed bias, 145.6 LSB/(deg/s) quantization), writes
// it as CSV, reads it back through the normal reader and runs `dev` on it.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>

#include "commands.hpp"
#include "cubecal/io/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "output.hpp"

namespace cubecal::cli {

namespace {

struct DemoOptions {
  std::string out = "demo-out";
  double hours = 24.0;
  double rate_hz = 10.0;
  std::uint64_t seed = 1;
  bool force = false;
};

// The paper's adjusted gyro model (PRODUCT.md): deg/s and deg/s^2.
constexpr std::array<double, 3> kSigmaN{13.9e-3, 14.5e-3, 13.0e-3};
constexpr std::array<double, 3> kSigmaMu{3.50e-3, 0.87e-3, 0.66e-3};
constexpr std::array<double, 3> kFixedBias{182.3e-3, 1509.3e-3, -1501.5e-3};
constexpr double kLsb = 145.6;  // LSB per deg/s
constexpr std::array<double, 3> kPaperN{0.2683, 0.2723, 0.2469};   // deg/sqrt(h)
constexpr std::array<double, 3> kPaperB{12.649, 6.853, 5.3007};    // deg/h
constexpr std::array<double, 3> kPaperT{7.4, 34.9, 39.2};          // s

void write_record(const std::string& path, const DemoOptions& o, std::size_t n) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw io::UsageError("cannot write " + path + " (check the --out directory)");
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double dt = 1.0 / o.rate_hz;
  std::array<double, 3> bias{0.0, 0.0, 0.0};
  fmt::memory_buffer buf;
  buf.reserve(1 << 20);
  fmt::format_to(std::back_inserter(buf), "t,gx,gy,gz\n");
  for (std::size_t i = 0; i < n; ++i) {
    fmt::format_to(std::back_inserter(buf), "{:.1f}", static_cast<double>(i) * dt);
    for (int a = 0; a < 3; ++a) {
      const double w = kFixedBias[a] + bias[a] + kSigmaN[a] * gauss(rng);
      // Eq. (3): int() truncates toward zero.
      const double q = std::trunc(w * kLsb) / kLsb;
      fmt::format_to(std::back_inserter(buf), ",{:.7g}", q);
      bias[a] += kSigmaMu[a] * dt * gauss(rng);
    }
    buf.push_back('\n');
    if (buf.size() > (1 << 20) - 256) {
      f.write(buf.data(), static_cast<std::streamsize>(buf.size()));
      buf.clear();
    }
  }
  f.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  if (!f) throw io::UsageError("could not finish writing " + path + " (disk full?)");
}

int run_demo(const DemoOptions& o) {
  namespace fs = std::filesystem;
  const auto t0 = std::chrono::steady_clock::now();
  fs::create_directories(o.out);
  const std::string csv = (fs::path(o.out) / "gyro_static.csv").string();
  const std::string json = (fs::path(o.out) / "gyro_oadev.json").string();
  const std::string table = (fs::path(o.out) / "gyro_oadev.txt").string();
  // A marker tells a directory of earlier demo output (replaced freely) from
  // one holding the user's own files of the same names (never replaced unasked).
  const fs::path marker = fs::path(o.out) / ".cubecal-demo";
  if (!fs::exists(marker) && !o.force)
    for (const auto& p : {csv, json, table})
      if (fs::exists(p))
        throw io::UsageError(p + " already exists (use another --out, or --force to replace)");
  std::ofstream(marker) << "written by cubecal demo; files here are replaced by the next run\n";

  const auto n = static_cast<std::size_t>(std::llround(o.hours * 3600.0 * o.rate_hz));
  std::cout << fmt::format("cubecal demo: simulating a {:.0f} h static gyro record at {} Hz "
                           "({} samples, seed {})\n",
                           o.hours, o.rate_hz, n, o.seed);
  write_record(csv, o, n);

  io::SeriesOptions so;  // time column "t" is found by name, rate inferred
  const io::Series s = io::read_series(csv, so);
  pipeline::DevRequest req;
  req.stat = Stat::oadev;
  req.type = DataType::freq;
  req.grid = parse_tau_grid("log:10");
  const pipeline::DevResult r = pipeline::run_dev(s, req);

  DevContext ctx{csv, req.options.ci, "greenhall", true};
  {
    OutputFile f(json, true);
    f.stream() << dev_to_json(r, ctx).dump(1) << '\n';
    f.commit();
    OutputFile t(table, true);
    write_dev_table(t.stream(), r, ctx);
    t.commit();
  }

  // Read-offs as the paper makes them: N = sigma(1 s) * 60 deg/sqrt(h),
  // B = sigma_min / 0.664 in deg/h, T = tau at the minimum.
  std::cout << fmt::format("\n{:<4} {:>22} {:>24} {:>18}\n", "axis", "ARW N [deg/sqrt(h)]",
                           "bias instab. B [deg/h]", "T at minimum [s]");
  std::cout << fmt::format("{:<4} {:>11} {:>10} {:>12} {:>11} {:>9} {:>8}\n", "", "measured",
                           "paper", "measured", "paper", "measured", "paper");
  for (std::size_t a = 0; a < r.channels.size() && a < 3; ++a) {
    const auto& pts = r.channels[a].points;
    double sigma1 = 0.0;
    for (const auto& p : pts)
      if (std::abs(p.tau - 1.0) < 1e-9) sigma1 = p.dev;
    const auto mn = std::min_element(pts.begin(), pts.end(),
                                     [](const auto& x, const auto& y) { return x.dev < y.dev; });
    std::cout << fmt::format("{:<4} {:>11.4f} {:>10.4f} {:>12.3f} {:>11.3f} {:>9.1f} {:>8.1f}\n",
                             r.channels[a].name, sigma1 * 60.0, kPaperN[a],
                             mn->dev / 0.664 * 3600.0, kPaperB[a], mn->tau, kPaperT[a]);
  }
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << fmt::format("\n(T is read on a log:10 grid, so it is coarse.)\n"
                           "Done in {:.1f} s. Output in {}/:\n  {}  simulated record\n  {}  "
                           "OADEV with 68.3 % intervals (JSON)\n  {}  the same as a table\n"
                           "Try: build/bin/cubecal dev {} --columns gx,gy,gz --taus log:20\n",
                           secs, o.out, csv, json, table, csv);
  return 0;
}

}  // namespace

CLI::App* add_demo_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<DemoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Simulate a static gyro record with the paper's noise model and analyse it");
  cmd->add_option("--out", opt->out, "Output directory")->capture_default_str();
  cmd->add_option("--hours", opt->hours, "Record length in hours")
      ->check(CLI::Range(0.01, 1000.0))
      ->capture_default_str();
  cmd->add_option("--rate", opt->rate_hz, "Sampling rate in Hz")
      ->check(CLI::Range(0.001, 1e6))
      ->capture_default_str();
  cmd->add_option("--seed", opt->seed, "Random seed")->capture_default_str();
  cmd->add_flag("--force", opt->force, "Replace files from an earlier demo run");
  cmd->callback([opt, &run] { run = [opt] { return run_demo(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
