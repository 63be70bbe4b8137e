// cubecal calibrate multiposition: accelerometer (and gyroscope) calibration
// from a sequence of static poses, without a turntable (Tedaldi, Pretto &
// Menegatti 2014; formulas.md 3.2). X' = T K (X - B) for each triad.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/calib/multiposition.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/error.hpp"
#include "output.hpp"

namespace cubecal::cli {

namespace {

namespace mp = cubecal::multipos;

struct MultiposCliOptions {
  std::string acc_file;
  std::string gyro_file;
  std::string acc_columns;
  std::string gyro_columns;
  std::string time_col;
  double rate_hz = 0.0;
  std::size_t skip_rows = 0;
  double g = 9.80665;
  double init_static = 50.0;
  std::size_t window = mp::kDefaultWindow;
  std::size_t interval_samples = mp::kIntervalSamples;
  std::size_t min_intervals = mp::kMinIntervals;
  std::vector<double> acc_bias{0.0};
  double acc_scale = 0.0;
  double gyro_scale = 1.0;
  bool refine_gyro_bias = false;
  bool use_means = false;
  std::string format = "table";
  std::string out;
  bool force = false;
  unsigned threads = 0;
};

struct Triads {
  std::vector<double> t;
  std::vector<Vec3> x;
  std::vector<std::string> names;
};

// Reads one file: the given columns (3 or 6), split into triads, and the time
// column when asked. Time stamps must increase (FILE:LINE:COL otherwise).
std::vector<Triads> read_triads(const std::string& path, const std::vector<std::string>& columns,
                                const MultiposCliOptions& o, const char* what_columns) {
  io::TableOptions to;
  to.columns = columns;
  if (!o.time_col.empty()) to.extra_columns = {o.time_col};
  to.skip_rows = o.skip_rows;
  to.threads = o.threads;
  const io::Table tab = io::read_table(path, to);
  const std::size_t want = columns.empty() ? 3 : columns.size();
  if (tab.data.size() != want || want % 3 != 0)
    throw UsageError(fmt::format("{}: {} data columns{}: choose three with {}", path, tab.data.size(),
                                     o.time_col.empty() ? "" : " besides the time column", what_columns));
  if (!o.time_col.empty()) {
    const auto& t = tab.extra[0];
    for (std::size_t i = 1; i < t.size(); ++i)
      if (!(t[i] > t[i - 1])) {
        const io::Location at = io::locate(tab, i, tab.extra_indices[0]);
        throw InputError(path, at.line, at.column,
                             fmt::format("time stamps not increasing ({} s after {} s)", t[i], t[i - 1]),
                             "check --time-col");
      }
  }
  std::vector<Triads> out(want / 3);
  for (std::size_t k = 0; k < out.size(); ++k) {
    Triads& tr = out[k];
    if (!o.time_col.empty()) tr.t = tab.extra[0];
    tr.x.resize(tab.rows());
    for (std::size_t i = 0; i < tab.rows(); ++i)
      tr.x[i] = {tab.data[3 * k][i], tab.data[3 * k + 1][i], tab.data[3 * k + 2][i]};
    tr.names = {tab.names[3 * k], tab.names[3 * k + 1], tab.names[3 * k + 2]};
  }
  return out;
}

double mean_rate(const Triads& t, double rate) {
  if (t.t.size() < 2) return rate;
  return static_cast<double>(t.t.size() - 1) / (t.t.back() - t.t.front());
}

nlohmann::json residuals_json(const mp::Residuals& r) {
  return {{"count", r.count}, {"cost", r.cost}, {"rms", r.rms}, {"max", r.max}};
}

nlohmann::json params_json(const std::vector<std::string>& names, const std::vector<double>& v,
                           const std::vector<double>& s, const std::vector<std::string>& units) {
  nlohmann::json a = nlohmann::json::array();
  for (std::size_t i = 0; i < names.size(); ++i)
    a.push_back({{"name", names[i]}, {"value", v[i]}, {"sigma", s[i]}, {"unit", units[i]}});
  return a;
}

nlohmann::json model_json(const mp::TriadCalibration& m) {
  return {{"T", m.misalignment()}, {"K", m.scale}, {"B", m.bias}, {"TK", m.matrix()}};
}

std::vector<std::string> acc_units() {
  return {"rad", "rad", "rad", "g-unit/raw", "g-unit/raw", "g-unit/raw", "raw", "raw", "raw"};
}
std::vector<std::string> gyro_units(std::size_t n) {
  std::vector<std::string> u{"rad", "rad", "rad", "rad", "rad", "rad", "rad/s/raw", "rad/s/raw", "rad/s/raw"};
  if (n == 12) u.insert(u.end(), {"raw", "raw", "raw"});
  return u;
}

struct Context {
  std::string acc_file, gyro_file;
  std::size_t samples = 0;
  double rate = 0.0;
  bool gyro = false;
};

nlohmann::json result_json(const mp::AccResult& a, const std::optional<mp::GyroResult>& g, const Context& ctx,
                           const mp::Options& opt, const std::vector<double>& ta) {
  nlohmann::json j;
  j["method"] = "multi-position calibration without a turntable (Tedaldi, Pretto & Menegatti 2014)";
  j["invocation"] = invocation();
  j["acc_file"] = ctx.acc_file;
  j["gyro_file"] = ctx.gyro ? nlohmann::json(ctx.gyro_file) : nlohmann::json(nullptr);
  j["model"] = "X' = T K (X - B); T = [[1, -mis_yz, mis_zy], [mis_xz, 1, -mis_zx], [-mis_xy, mis_yx, 1]]";
  j["samples"] = ctx.samples;
  j["rate_hz"] = ctx.rate;
  j["g"] = opt.g;
  j["init_static_s"] = opt.init_static_s;
  j["window"] = mp::normalised_window(opt.window);
  j["interval_samples"] = opt.interval_samples;
  j["min_intervals"] = opt.min_intervals;
  j["th_mult"] = a.th_mult;
  j["threshold"] = a.threshold;
  j["init_variance_norm"] = a.init_variance_norm;
  j["static_intervals"] = a.intervals.size();
  nlohmann::json iv = nlohmann::json::array();
  for (const IndexRange& i : a.intervals)
    iv.push_back({{"begin", i.begin}, {"end", i.end}, {"t_begin", ta[i.begin]}, {"t_end", ta[i.end]}});
  j["intervals"] = iv;
  nlohmann::json trials = nlohmann::json::array();
  for (const mp::Trial& t : a.trials)
    trials.push_back({{"th_mult", t.th_mult},
                      {"threshold", t.threshold},
                      {"intervals", t.intervals},
                      {"fitted", t.fitted},
                      {"cost", t.fitted ? nlohmann::json(t.cost) : nlohmann::json(nullptr)}});
  j["trials"] = trials;
  nlohmann::json ja;
  ja["parameters"] = params_json(a.names, a.values, a.sigma, acc_units());
  ja["covariance"] = {{"names", a.names}, {"matrix", a.covariance}};
  ja["model"] = model_json(a.model);
  ja["initial"] = model_json(a.initial);
  ja["residual"] = "g - |T K (a - B)|";
  ja["before"] = residuals_json(a.before);
  ja["after"] = residuals_json(a.after);
  ja["sigma0"] = a.sigma0;
  ja["iterations"] = a.iterations;
  ja["converged"] = a.converged;
  j["accelerometer"] = ja;
  if (g) {
    nlohmann::json jg;
    jg["parameters"] = params_json(g->names, g->values, g->sigma, gyro_units(g->names.size()));
    jg["sigma_fit"] = g->sigma_fit;
    jg["covariance"] = {{"names", g->names}, {"matrix", g->covariance}};
    jg["model"] = model_json(g->model);
    jg["initial"] = model_json(g->initial);
    jg["init_bias"] = g->init_bias;
    jg["init_bias_sigma"] = g->init_bias_sigma;
    jg["bias_sigma"] = g->bias_sigma;
    jg["init_samples"] = g->init_samples;
    jg["residual"] = "R^-1 u_{k-1} - u_k";
    jg["pairs"] = g->pairs;
    jg["before"] = residuals_json(g->before);
    jg["after"] = residuals_json(g->after);
    jg["angle_rms_before_deg"] = g->angle_rms_before_deg;
    jg["angle_rms_after_deg"] = g->angle_rms_after_deg;
    jg["angle_max_after_deg"] = g->angle_max_after_deg;
    jg["sigma0"] = g->sigma0;
    jg["iterations"] = g->iterations;
    jg["converged"] = g->converged;
    j["gyroscope"] = jg;
  } else {
    j["gyroscope"] = nullptr;
  }
  return j;
}

void print_params(std::ostream& out, const std::vector<std::string>& names, const std::vector<double>& v,
                  const std::vector<double>& s, const std::vector<std::string>& units) {
  for (std::size_t i = 0; i < names.size(); ++i)
    fmt::print(out, "  {:<7} {:>15.8g} ± {:<10.3g} {}\n", names[i], v[i], s[i], units[i]);
}

void print_matrix(std::ostream& out, const char* label, const Mat3& m) {
  for (std::size_t i = 0; i < 3; ++i)
    fmt::print(out, "  {:<4} [{:>13.6g} {:>13.6g} {:>13.6g}]\n", i == 1 ? label : "", m[i][0], m[i][1], m[i][2]);
}

void print_table(std::ostream& out, const mp::AccResult& a, const std::optional<mp::GyroResult>& g, const Context& ctx,
                 const mp::Options& opt) {
  fmt::print(out, "Multi-position calibration without a turntable (Tedaldi, Pretto & Menegatti 2014)\n");
  fmt::print(out, "accelerometer {}{}\n", ctx.acc_file,
             ctx.gyro ? fmt::format(", gyroscope {}", ctx.gyro_file == ctx.acc_file ? "(same file)" : ctx.gyro_file)
                      : std::string());
  fmt::print(out, "{} samples at {:.6g} Hz; g = {:.6g}; initial static period {:.6g} s ({} samples, |var| {:.4g})\n",
             ctx.samples, ctx.rate, opt.g, opt.init_static_s, a.init_samples, a.init_variance_norm);
  fmt::print(out, "static intervals: {} (th_mult {} of {}..{}, threshold {:.4g}; window {}, {} {} per interval)\n",
             a.intervals.size(), a.th_mult, opt.th_mult_min, opt.th_mult_max, a.threshold,
             mp::normalised_window(opt.window), opt.acc_use_means ? "mean of" : "first", opt.interval_samples);
  fmt::print(out, "  th_mult  ");
  for (const mp::Trial& t : a.trials) fmt::print(out, " {:>9}", t.th_mult);
  fmt::print(out, "\n  intervals");
  for (const mp::Trial& t : a.trials) fmt::print(out, " {:>9}", t.intervals);
  fmt::print(out, "\n  cost     ");
  for (const mp::Trial& t : a.trials)
    fmt::print(out, " {:>9}", t.fitted ? fmt::format("{:.4g}", t.cost) : std::string("-"));
  fmt::print(out, "\n\nAccelerometer  a' = T K (a - B), 1 sigma\n");
  print_params(out, a.names, a.values, a.sigma, acc_units());
  print_matrix(out, "T", a.model.misalignment());
  fmt::print(out, "  |g| - |a'| over {} residuals: rms {:.5g} -> {:.5g}, max {:.5g} -> {:.5g} (g units)\n",
             a.after.count, a.before.rms, a.after.rms, a.before.max, a.after.max);
  fmt::print(out, "  cost sum r^2 {:.6g} -> {:.6g}; {} iterations{}\n", a.before.cost, a.after.cost, a.iterations,
             a.converged ? "" : " (not converged)");
  if (opt.acc_scale_guess == 0.0)
    fmt::print(out, "  (before: bias guess and the isotropic scale g / mean|a - B| of the initial period)\n");
  if (!g) return;
  fmt::print(out, "\nGyroscope  w' = T K (w - B), w' in rad/s, 1 sigma (incl. accelerometer and bias errors)\n");
  print_params(out, g->names, g->values, g->sigma, gyro_units(g->names.size()));
  print_matrix(out, "T", g->model.misalignment());
  fmt::print(out, "  B {:>13.6g} {:>13.6g} {:>13.6g} raw ± {:.3g} {:.3g} {:.3g} ({})\n", g->model.bias[0],
             g->model.bias[1], g->model.bias[2], g->bias_sigma[0], g->bias_sigma[1], g->bias_sigma[2],
             g->names.size() == 12 ? "initial-period mean, refined" : "initial-period mean");
  fmt::print(out,
             "  gravity direction after integration between {} pose pairs: rms {:.4g} -> {:.4g} deg, max {:.4g} deg\n",
             g->pairs, g->angle_rms_before_deg, g->angle_rms_after_deg, g->angle_max_after_deg);
  fmt::print(out, "  cost sum |R^-1 u_(k-1) - u_k|^2 {:.6g} -> {:.6g}; {} iterations{}\n", g->before.cost,
             g->after.cost, g->iterations, g->converged ? "" : " (not converged)");
  fmt::print(out, "  (before: scale guess {:.6g} rad/s/raw, no misalignment)\n", opt.gyro_scale_guess);
}

int run_calibrate_multiposition(const MultiposCliOptions& o) {
  if (!o.time_col.empty() && o.rate_hz > 0.0) throw UsageError("give --time-col or --rate, not both");
  if (o.time_col.empty() && !(o.rate_hz > 0.0))
    throw UsageError("give the time column (--time-col) or the sampling rate (--rate)");
  if (o.acc_bias.size() != 1 && o.acc_bias.size() != 3)
    throw UsageError("--acc-bias takes one value or three (x,y,z)");
  const std::vector<std::string> acc_cols = split_list(o.acc_columns);
  const std::vector<std::string> gyro_cols = split_list(o.gyro_columns);
  if (!acc_cols.empty() && acc_cols.size() != 3) throw UsageError("--acc-columns takes three columns");
  if (!gyro_cols.empty() && gyro_cols.size() != 3) throw UsageError("--gyro-columns takes three columns");

  Context ctx;
  ctx.acc_file = o.acc_file;
  ctx.gyro_file = o.gyro_file;
  Triads acc, gyro;
  if (o.gyro_file.empty() && !gyro_cols.empty()) {
    // One file with both triads.
    if (acc_cols.empty()) throw UsageError("give --acc-columns with --gyro-columns for a single file");
    std::vector<std::string> cols = acc_cols;
    cols.insert(cols.end(), gyro_cols.begin(), gyro_cols.end());
    auto both = read_triads(o.acc_file, cols, o, "--acc-columns and --gyro-columns");
    acc = std::move(both[0]);
    gyro = std::move(both[1]);
    ctx.gyro = true;
    ctx.gyro_file = o.acc_file;
  } else {
    acc = std::move(read_triads(o.acc_file, acc_cols, o, "--acc-columns")[0]);
    if (!o.gyro_file.empty()) {
      gyro = std::move(read_triads(o.gyro_file, gyro_cols.empty() ? acc_cols : gyro_cols, o, "--gyro-columns")[0]);
      ctx.gyro = true;
    }
  }
  ctx.samples = acc.x.size();
  ctx.rate = mean_rate(acc, o.rate_hz);

  mp::Options opt;
  opt.g = o.g;
  opt.init_static_s = o.init_static;
  opt.window = o.window;
  opt.interval_samples = o.interval_samples;
  opt.min_intervals = o.min_intervals;
  opt.acc_use_means = o.use_means;
  opt.acc_bias_guess = o.acc_bias.size() == 3 ? Vec3{o.acc_bias[0], o.acc_bias[1], o.acc_bias[2]}
                                              : Vec3{o.acc_bias[0], o.acc_bias[0], o.acc_bias[0]};
  opt.acc_scale_guess = o.acc_scale;
  opt.gyro_scale_guess = o.gyro_scale;
  opt.refine_gyro_bias = o.refine_gyro_bias;

  const mp::TriadSeries sa{acc.x, acc.t, o.rate_hz};
  const mp::TriadSeries sg{gyro.x, gyro.t, o.rate_hz};
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  mp::AccResult a;
  std::optional<mp::GyroResult> g;
  try {
    a = mp::calibrate_accelerometer(sa, opt);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    throw InputError(o.acc_file, 0, 0, what,
                         what.find("static intervals") != std::string::npos
                             ? "check --init-static (the sensor must be still then) and --rate/--time-col"
                             : std::string());
  }
  if (ctx.gyro) {
    try {
      g = mp::calibrate_gyroscope(sa, a, sg, opt);
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      throw InputError(
          ctx.gyro_file, 0, 0, what,
          what.find("scale") != std::string::npos ? "give --gyro-scale in rad/s per count" : std::string());
    }
  }
  std::vector<double> ta = acc.t;
  if (ta.empty())
    for (std::size_t i = 0; i < acc.x.size(); ++i) ta.push_back(static_cast<double>(i) / o.rate_hz);

  std::ostream& out = result.stream();
  if (o.format == "json")
    out << result_json(a, g, ctx, opt, ta).dump(2) << '\n';
  else
    print_table(out, a, g, ctx, opt);
  result.finish();
  return 0;
}

}  // namespace

CLI::App* add_calibrate_multiposition_command(CLI::App& calibrate, Command& run) {
  auto opt = std::make_shared<MultiposCliOptions>();
  CLI::App* cmd = calibrate.add_subcommand(
      "multiposition",
      "Accelerometer (and gyroscope) calibration from static poses without a turntable (Tedaldi et al. 2014): "
      "X' = T K (X - B); the accelerometer from |a'| = g over >= 12 static poses, the gyroscope by integrating "
      "between them");
  cmd->add_option("acc_file", opt->acc_file, "Accelerometer record: delimited text, optionally gzip")->required();
  cmd->add_option("gyro_file", opt->gyro_file,
                  "Gyroscope record (same layout and clock); omit for the accelerometer alone, or give "
                  "--gyro-columns for a file holding both");
  cmd->add_option("--acc-columns", opt->acc_columns,
                  "The 3 accelerometer columns, by header name or 1-based index (ax,ay,az or 2,3,4); default: "
                  "every column but the time column, which must then be 3");
  cmd->add_option("--gyro-columns", opt->gyro_columns,
                  "The 3 gyroscope columns (default with GYRO_FILE: those of --acc-columns); without GYRO_FILE, "
                  "read from ACC_FILE");
  cmd->add_option("--time-col", opt->time_col, "Time column (s), by name or index");
  cmd->add_option("--rate", opt->rate_hz, "Sampling rate in Hz (when there is no time column)");
  cmd->add_option("--skip-rows", opt->skip_rows, "Lines to skip before the header/data (preamble), in each file");
  cmd->add_option("--g", opt->g, "Local gravity magnitude: |a'| after calibration (sets the unit of a')")
      ->capture_default_str();
  cmd->add_option("--init-static", opt->init_static,
                  "Initial static period (s): sets the static threshold and the gyroscope bias")
      ->capture_default_str();
  cmd->add_option("--window", opt->window, "Centred variance window (samples, odd, >= 11)")->capture_default_str();
  cmd->add_option("--interval-samples", opt->interval_samples,
                  "Samples taken from each static interval (and its minimum length)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->capture_default_str();
  cmd->add_option("--min-intervals", opt->min_intervals,
                  "Static intervals required (the paper's rule is 12; fewer weakens the calibration)")
      ->check(CLI::Range(std::size_t{4}, std::size_t{100000}))
      ->capture_default_str();
  cmd->add_option("--acc-bias", opt->acc_bias,
                  "Initial accelerometer bias guess (raw), one value or x,y,z (e.g. 32768 for offset-binary)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--acc-scale", opt->acc_scale,
                  "Initial accelerometer scale guess (g units per raw); 0: g / mean|a - bias| of the initial period")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--gyro-scale", opt->gyro_scale,
                  "Initial gyroscope scale guess (rad/s per raw count), e.g. 1.3323e-4 for an MPU-6050 at 250 deg/s")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--refine-gyro-bias", opt->refine_gyro_bias,
                "Fit 3 gyroscope bias corrections besides the 9 parameters");
  cmd->add_flag("--use-means", opt->use_means, "One accelerometer residual per interval (its mean)");
  cmd->add_option("--format", opt->format, "table or json")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file");
  cmd->add_flag("--force", opt->force, "Replace --out if it exists");
  cmd->add_option("--threads", opt->threads, "Reader threads (default: all cores)");
  cmd->callback([opt, &run] { run = [opt] { return run_calibrate_multiposition(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
