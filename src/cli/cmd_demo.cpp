// cubecal demo: the paper's 72 h static experiment in one command. Simulates
// the SPORT gyro (MPU-3300 adjusted model) and magnetometer (HMC5843, with its
// temperature coefficient) at 10 Hz under a daily temperature swing into
// memory, writes the record for the user, analyzes the record held in memory
// as the paper did (model fitted on the first 42000 samples), writes every
// result file and the report, and prints the paper's numbers beside the
// recovered ones.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/io/atomic_file.hpp"
#include "cubecal/io/csv_writer.hpp"
#include "cubecal/io/output_path.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/report/report.hpp"
#include "cubecal/report/plot.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct DemoOptions {
  std::string out = "demo-out";
  double hours = 72.0;
  std::uint64_t seed = 1;
  bool force = false;
  std::string gnuplot;  // --gnuplot PATH; empty: gnuplot on PATH
};

// The paper's numbers (docs/paper.md §3.1): adjusted gyro model row and its model
// parameters; magnetometer measured row and model.
constexpr std::array<double, 3> kGyroN{0.2683, 0.2723, 0.2469};  // deg/sqrt(h)
constexpr std::array<double, 3> kGyroB{12.649, 6.853, 5.3007};   // deg/h
constexpr std::array<double, 3> kGyroT{7.4, 34.9, 39.2};         // s
constexpr std::array<double, 3> kGyroSn{13.9e-3, 14.5e-3, 13.0e-3};
constexpr std::array<double, 3> kGyroSmu{3.50e-3, 0.87e-3, 0.66e-3};
constexpr std::array<double, 3> kMagN{0.01568, 0.02587, 0.01588};  // mGauss*sqrt(h)
constexpr std::array<double, 3> kMagB{0.05376, 0.07180, 0.04988};  // mGauss
constexpr std::array<double, 3> kMagSn{3.0, 4.9, 2.96};
constexpr std::array<double, 3> kMagSmu{0.0034, 0.0042, 0.0036};

// The paper's record simulated (SPORT gyro and magnetometer, 10 Hz, a
// daily temperature swing) and written to `record`.
pipeline::SimulatedRecord simulate_demo_record(const DemoOptions& o, const std::string& record) {
  pipeline::SimulateRequest sim;
  sim.triads = {preset("sport-gyro"), preset("sport-mag")};
  sim.rate_hz = 10.0;
  sim.duration_s = o.hours * 3600.0;
  sim.seed = o.seed;
  sim.temperature.kind = TemperatureProfile::Kind::sinusoid;
  sim.temperature.mean = 25.0;
  sim.temperature.amplitude = 5.0;
  std::cout << fmt::format(
      "cubecal demo: the paper's static experiment, simulated: SPORT gyro + magnetometer, "
      "{:g} h at 10 Hz, 25 +- 5 degC daily, seed {}\n",
      o.hours, o.seed);
  pipeline::SimulatedRecord rec = pipeline::simulate(sim);
  {
    io::CsvWriter w(record, true);
    pipeline::write_record(rec, w);
    w.commit();
  }
  return rec;
}

// The record as the reader gets it back from the file.
io::Series demo_series(pipeline::SimulatedRecord& rec, const std::string& record) {
  // The record as the reader gets it back from the file (values to the nine
  // digits the file keeps), so the printed command reproduces these numbers.
  io::Series s;
  s.file = record;
  s.rate_hz = rec.rate_hz;
  s.tau0 = 1.0 / rec.rate_hz;
  s.rate_from_time = true;
  s.time_name = "t";
  const std::size_t n = rec.channels.empty() ? 0 : rec.channels[0].size();
  s.time.resize(n);
  for (std::size_t k = 0; k < n; ++k) s.time[k] = io::csv_round(static_cast<double>(k) * s.tau0);
  for (auto& c : rec.channels)
    for (double& v : c) v = io::csv_round(v);
  for (std::size_t c = 0; c < rec.names.size(); ++c) {
    if (rec.names[c] == "temp") {
      s.extra_names.push_back(rec.names[c]);
      s.extra.push_back(std::move(rec.channels[c]));
    } else {
      s.names.push_back(rec.names[c]);
      s.channels.push_back(std::move(rec.channels[c]));
    }
  }
  s.segments = {{0, n}};
  return s;
}

// The analysis as the paper made it (model fitted on the first 42000 samples).
pipeline::AnalyzeRequest demo_request() {
  pipeline::AnalyzeRequest req;
  for (int k = 0; k < 3; ++k) req.units.push_back(*parse_unit("deg/s"));
  for (int k = 0; k < 3; ++k) req.units.push_back(*parse_unit("mGauss"));
  req.grid = parse_tau_grid("log:20");
  req.temp_index = 0;
  req.max_samples = 42000;  // the paper's reduction for the model fit
  req.lsb = {145.6, 145.6, 145.6, 1.30, 1.30, 1.30};
  return req;
}

// The gyro rows: the paper's adjusted model row vs the recovered one.
void print_gyro_rows(const pipeline::AnalysisResult& r) {
  auto term = [](const TermEstimate& t, Term which, const Unit& u) { return display(t, which, u); };
  const auto& x = r.channels[0];
  std::cout << fmt::format(
      "\nGyro: the paper's adjusted model row vs the model fitted here on 42000 samples,\n"
      "and N, B, T read off the full record (OADEV, 68.3 % intervals);\n"
      "N in {}, B in {}, T in s, sigma_n (sn) in {}, sigma_mu (smu) in {}/s\n",
      term(x.noise.readoffs.N, Term::N, x.unit).unit, term(x.noise.readoffs.B, Term::B, x.unit).unit, x.unit.name,
      x.unit.name);
  std::cout << fmt::format("{:<4} {:>9} {:>17} {:>9} {:>16} {:>7} {:>12} {:>9} {:>10} {:>9} {:>10}\n", "axis",
                           "N paper", "N here", "B paper", "B here", "T paper", "T here", "sn paper", "sn fit",
                           "smu paper", "smu fit");
  for (std::size_t a = 0; a < 3; ++a) {
    const auto& c = r.channels[a];
    const auto N = term(c.noise.readoffs.N, Term::N, c.unit);
    const auto B = term(c.noise.readoffs.B, Term::B, c.unit);
    std::cout << fmt::format(
        "{:<4} {:>9.4f} {:>9.4f} ± {:<5.4f} {:>9.3f} {:>8.3f} ± {:<5.2f} {:>7.1f} {:>5.1f} s ({:.0f}–{:.0f}) {:>9.4f} "
        "{:>10.4f} {:>9.5f} "
        "{:>10.5f}\n",
        c.name, kGyroN[a], N.value, N.sigma, kGyroB[a], B.value, B.sigma, kGyroT[a], c.noise.readoffs.tau_min,
        c.noise.readoffs.tau_min_lo, c.noise.readoffs.tau_min_hi, kGyroSn[a],
        c.model.ok ? c.model.random_walk.sigma_n : NAN, kGyroSmu[a], c.model.ok ? c.model.random_walk.sigma_mu : NAN);
  }
}

// The magnetometer rows: the paper's measured row vs this record, before
// and after the temperature compensation.
void print_magnetometer_rows(const pipeline::AnalysisResult& r) {
  auto term = [](const TermEstimate& t, Term which, const Unit& u) { return display(t, which, u); };
  const auto& x = r.channels[3];
  std::cout << fmt::format(
      "\nMagnetometer: the paper's measured row vs this record, before and after the\n"
      "temperature compensation (the simulated field drifts 0.7 mGauss/degC);\n"
      "N in {}, B in {}, sigma_n (sn) in {}\n",
      term(x.noise.readoffs.N, Term::N, x.unit).unit, term(x.noise.readoffs.B, Term::B, x.unit).unit, x.unit.name);
  std::cout << fmt::format("{:<4} {:>9} {:>19} {:>9} {:>17} {:>17} {:>17} {:>8} {:>9}\n", "axis", "N paper", "N here",
                           "B paper", "B here", "B compensated", "coeff [mG/degC]", "sn paper", "sn fit");
  for (std::size_t a = 3; a < 6; ++a) {
    const auto& c = r.channels[a];
    const auto N = term(c.noise.readoffs.N, Term::N, c.unit);
    const auto B = term(c.noise.readoffs.B, Term::B, c.unit);
    const auto& t = *c.temperature;
    const auto Bc = term(t.compensated.readoffs.B, Term::B, c.unit);
    std::cout << fmt::format(
        "{:<4} {:>9.5f} {:>9.5f} ± {:<7.5f} {:>9.5f} {:>8.5f} ± {:<6.4f} {:>8.5f} ± {:<6.4f} "
        "{:>7.4f} ± {:<6.4f} {:>8.2f} {:>9.3f}\n",
        c.name, kMagN[a - 3], N.value, N.sigma, kMagB[a - 3], B.value, B.sigma, Bc.value, Bc.sigma, t.fit.coeff[1],
        t.fit.coeff_sigma[1], kMagSn[a - 3], c.model.ok ? c.model.random_walk.sigma_n : NAN);
  }
}

int run_demo(const DemoOptions& o) {
  namespace fs = std::filesystem;
  const auto t0 = std::chrono::steady_clock::now();
  // A gnuplot named explicitly must be there; none on PATH only leaves the plots out.
  if (!o.gnuplot.empty() && !report::find_gnuplot(o.gnuplot)) report::throw_gnuplot_missing(o.gnuplot);
  const fs::path dir(o.out);
  const std::string record = (dir / "sport_static.csv.gz").string();
  // A marker tells a directory of earlier demo output (replaced freely) from
  // one holding the user's own files of the same names (never replaced unasked).
  const fs::path marker = dir / ".cubecal-demo";
  std::vector<std::string> files(std::begin(pipeline::kAnalysisFiles), std::end(pipeline::kAnalysisFiles));
  files.insert(files.end(), {"sport_static.csv.gz", "report.html", "plots"});
  std::error_code ec;
  io::prepare_output_dir(o.out, o.force || fs::exists(marker, ec), files);
  io::write_file(marker.string(), "written by cubecal demo; files here are replaced by the next run\n", Field::out);

  pipeline::SimulatedRecord rec = simulate_demo_record(o, record);
  io::Series s = demo_series(rec, record);
  const pipeline::AnalyzeRequest req = demo_request();
  const pipeline::AnalysisResult r = pipeline::run_analyze(s, req);

  const std::string cmd = "cubecal analyze " + record +
                          " --unit deg/s,deg/s,deg/s,mGauss,mGauss,mGauss --temp-col temp --taus log:20"
                          " --max-samples 42000 --model-lsb 145.6,145.6,145.6,1.3,1.3,1.3";
  const pipeline::OutputContext ctx{cmd, "/imu0"};
  write_analysis_files(o.out, r, ctx);

  print_gyro_rows(r);
  print_magnetometer_rows(r);
  (void)kMagSmu;
  report::ReportOptions ro;
  ro.force = true;           // the marker makes the directory the demo's
  ro.require_plots = false;  // without gnuplot: the page without plots, and a warning
  ro.gnuplot = o.gnuplot;
  const report::ReportResult rep = report::write_report(r, {cmd, {}}, o.out, ro);
  if (!rep.note.empty()) std::cerr << "cubecal: warning: " << rep.note << '\n';
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << fmt::format(
      "\nDone in {:.1f} s. Output in {}:\n"
      "  sport_static.csv.gz  the simulated record (t, gx, gy, gz, mx, my, mz, temp)\n"
      "  analysis.json        every number above, with units and uncertainties\n"
      "  adev.csv, drift.csv  Allan curves with the fitted models, bias drift (300 s / 1000 s windows)\n"
      "  imu.yaml             Kalibr noise parameters of the gyro\n"
      "  report.html          all of it on one page, with the paper's figures (gnuplot files in plots/)\n"
      "Reproduce the analysis: {}\n",
      secs, (dir / "").string(), cmd);
  return 0;
}

}  // namespace

CLI::App* add_demo_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<DemoOptions>();
  CLI::App* cmd =
      app.add_subcommand("demo",
                         "The paper's 72 h static experiment, simulated and analyzed: prints the paper's numbers "
                         "beside the recovered ones");
  cmd->add_option("--out", opt->out, "Output directory")->capture_default_str();
  cmd->add_option("--hours", opt->hours, "Record length in hours")
      ->check(number_between(0.5, 1000.0))
      ->capture_default_str();
  cmd->add_option("--seed", opt->seed, "Random seed")->check(whole_number(0, 1e18))->capture_default_str();
  cmd->add_flag("--force", opt->force, "Replace files in --out that an earlier demo did not write");
  add_gnuplot_option(*cmd, opt->gnuplot);
  cmd->callback([opt, &run] { run = [opt] { return run_demo(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
