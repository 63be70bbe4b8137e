// cubecal model: a composite noise model fitted to each channel's Haar
// wavelet variance by the GMWM, with parametric-bootstrap uncertainties.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>

#include "calibration_hints.hpp"
#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/model_fit.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "output.hpp"
#include "progress.hpp"

namespace cubecal::cli {

namespace {

struct ModelOptions {
  InputOptions input;
  std::string model;
  std::string unit;
  std::size_t bootstrap = 0;
  std::size_t wic_replicates = 50;
  std::uint64_t seed = 1;
  double ci = 0.95;
  std::size_t starts = 32;
  bool robust = false;
  double efficiency = 0.6;
  std::string format = "table";
  std::string out;
  bool force = false;
};

std::string term_title(ProcessKind k) {
  switch (k) {
    case ProcessKind::wn: return "WN  white noise";
    case ProcessKind::qn: return "QN  quantization";
    case ProcessKind::rw: return "RW  random walk";
    case ProcessKind::dr: return "DR  drift";
    case ProcessKind::gm: return "GM  Gauss-Markov";
    case ProcessKind::ma1: return "MA1 moving average";
    case ProcessKind::sin: return "SIN periodic line";
  }
  return "";
}

void write_table(std::ostream& out, const pipeline::ModelResult& r) {
  fmt::print(out, "model {} of {}: {} channel(s), {} samples at {} Hz, GMWM on the {}Haar wavelet variance{}\n",
             r.model, r.file.empty() ? "-" : r.file, r.channels.size(), r.samples, rate_text(r.rate_hz),
             r.robust ? "robust " : "",
             r.robust ? fmt::format(" (biweight, Gaussian efficiency {:g})", r.robust_efficiency) : std::string());
  if (r.bootstrap > 0)
    fmt::print(out, "uncertainties: parametric bootstrap, {} replicates (seed {}): sd and {:g} % percentile interval\n",
               r.bootstrap, r.seed, 100.0 * r.ci);
  for (const auto& c : r.channels) {
    fmt::print(out, "\n{} [{}]: objective {:.4g} over {} scales{}{}\n", c.name,
               c.unit.name.empty() ? "no unit given" : c.unit.name, c.fit.objective, c.wv.size(),
               c.fit.converged ? "" : " (the optimiser stopped before its convergence tests held)",
               r.bootstrap > 0 ? fmt::format(", {} replicates fitted", c.replicates) : std::string());
    if (!c.candidates.empty()) {
      fmt::print(out, "  selected {} of {} candidates by the WIC (loss + optimism, {}):\n", c.model,
                 c.candidates.size() + c.failed.size(),
                 r.selection_replicates > 0 ? fmt::format("{} bootstrap replicates each", r.selection_replicates)
                                            : std::string("asymptotic optimism"));
      fmt::print(out, "    {:<16} {:>6} {:>12} {:>12} {:>12}\n", "candidate", "params", "WIC", "loss", "optimism");
      for (const auto& m : c.candidates)
        fmt::print(out, "    {:<16} {:>6} {:>12.5g} {:>12.5g} {:>12.5g}\n", m.model, m.parameters, m.score.wic,
                   m.score.loss, m.score.optimism);
      for (const auto& f : c.failed) fmt::print(out, "    left out: {}\n", f);
      fmt::print(out, "  {}:\n", c.model);
    }
    const bool boot = r.bootstrap > 0 && c.replicates >= 2;
    fmt::print(out, "  {:<18} {:<8} {:>12} {:>10}   {}\n", "term", "", "value", "asym. sd",
               boot ? "± bootstrap sd [interval] unit" : "unit");
    for (const auto& t : c.terms)
      for (std::size_t i = 0; i < t.quantities.size(); ++i) {
        const auto& q = t.quantities[i];
        const std::string title = i == 0 ? term_title(t.kind) : "";
        // The sandwich sd (noise/gmwm_asymptotics.hpp); "-" where the fit does not determine it.
        const std::string asym =
            std::isfinite(q.display_asymptotic_sd) ? fmt::format("{:.3g}", q.display_asymptotic_sd) : "-";
        if (boot)
          fmt::print(out, "  {:<18} {:<8} {:>12.5g} {:>10}   ± {:<10.3g} [{:.5g}, {:.5g}] {}\n", title, q.name,
                     q.display.value, asym, q.display.sigma, q.display_interval.lo, q.display_interval.hi,
                     q.display.unit);
        else
          fmt::print(out, "  {:<18} {:<8} {:>12.5g} {:>10}   {}\n", title, q.name, q.display.value, asym,
                     q.display.unit);
      }
    fmt::print(out, "  {:>12} {:>14} {:>14} {:>14} {:>14} {:>8}\n", "tau [s]", "WV", "lo", "hi", "model", "edf");
    for (std::size_t j = 0; j < c.wv.size(); ++j)
      fmt::print(out, "  {:>12.5g} {:>14.6e} {:>14.6e} {:>14.6e} {:>14.6e} {:>8.4g}\n", c.wv.tau[j] / r.rate_hz,
                 c.wv.nu2[j], c.wv.interval[j].lo, c.wv.interval[j].hi, c.fit.nu2_model[j], c.wv.edf[j]);
  }
}

// The bootstrap's progress on stderr, as dev's: once the first replicates
// give an estimate of the whole, a line rewritten on a terminal when it is
// more than 2 s, lines per tenth into a log when it is long work
// (long_work_seconds()); nothing otherwise.
class BootstrapProgress {
 public:
  explicit BootstrapProgress(std::size_t channels) : channels_(channels) {}
  void operator()(std::size_t done, std::size_t total) {
    const auto now = std::chrono::steady_clock::now();
    if (done == 0) {
      start_ = now;
      return;
    }
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (!progress_) {
      const double estimate = elapsed * static_cast<double>(total) / static_cast<double>(done);
      const bool long_work = estimate > long_work_seconds();
      if (!(estimate > 2.0) && !long_work) return;
      progress_.emplace(estimate > 2.0, long_work);
      progress_->stage(fmt::format("bootstrap: {} replicates on {} channel(s), estimated {}", total / channels_,
                                   channels_, format_duration(estimate)));
    }
    progress_->fraction(static_cast<double>(done) / static_cast<double>(total));
    if (done == total) progress_->done();
  }

 private:
  std::size_t channels_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::optional<Progress> progress_;
};

int run_model_command(const ModelOptions& o) {
  pipeline::ModelRequest req;
  req.model = o.model;
  req.selection_replicates = o.wic_replicates;
  if (!pipeline::is_twin(o.model)) (void)parse_candidate_models(o.model);  // a typo fails before the reading
  if (!o.unit.empty()) req.units = parse_units(o.unit);
  req.bootstrap = o.bootstrap;
  req.seed = o.seed;
  req.ci = o.ci;
  req.gmwm.starts = o.starts;
  req.robust = o.robust;
  req.robust_efficiency = o.efficiency;
  req.threads = o.input.threads;
  ResultOutput result(o.out, o.force);  // refuses an unusable --out before the work
  io::SeriesOptions so = to_series_options(o.input);
  so.keep_time = false;
  const io::Series series = io::read_series(o.input.file, so);
  std::string unit_note;
  if (o.unit.empty()) {
    try {
      ChannelUnits units = units_for({}, series);
      unit_note = units.note;
      req.units = std::move(units.units);
    } catch (const UsageError&) {
      unit_note = "cubecal: note: " + series.file +
                  ": no unit for the channels: terms in u, the unit of the values "
                  "(--unit names it)";
    }
  }
  BootstrapProgress progress(std::max<std::size_t>(series.channels.size(), 1));
  req.bootstrap_progress = [&](std::size_t done, std::size_t total) { progress(done, total); };
  const pipeline::ModelResult res = with_calibration_hints(o.input.file, {CalibrationCommand::model},
                                                           [&] { return pipeline::run_model(series, req); });
  note_default_columns(series);
  if (!unit_note.empty()) std::cerr << unit_note << '\n';
  std::ostream& out = result.stream();
  if (o.format == "json")
    out << pipeline::json_text(pipeline::to_json(res), 1) << '\n';
  else
    write_table(out, res);
  result.finish();
  return 0;
}

}  // namespace

CLI::App* add_model_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<ModelOptions>();
  CLI::App* cmd = app.add_subcommand(
      "model",
      "Fit a composite noise model (white noise, quantization, random walk, drift, Gauss-Markov terms) to "
      "each channel's Haar wavelet variance by the Generalized Method of Wavelet Moments (GMWM)");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--model", opt->model,
                  "The model's terms joined by +: WN, QN, RW, DR, GM (or AR1), MA1, SIN (a periodic line), k*GM or "
                  "k*SIN for k of them; e.g. WN+RW+2*GM. Several models joined by commas (WN+RW,WN+GM) are "
                  "candidates: each channel gets the one with the lowest Wavelet Information Criterion; auto: the "
                  "candidates WN, WN+RW, WN+GM, WN+QN+RW, WN+QN+GM, WN+GM+RW, WN+2*GM, WN+2*GM+RW, WN+QN+GM+RW; "
                  "twin: each channel's twin, searched among WN or MA1, QN, RW, DR, up to 4 GM and the lines of "
                  "its spectrum (docs/twins.md)")
      ->required();
  cmd->add_option("--wic-replicates", opt->wic_replicates,
                  "Bootstrap replicates of each candidate's WIC optimism, with several candidates (0: the "
                  "optimism's asymptotic form, no simulation)")
      ->check(whole_number(0, 100000))
      ->capture_default_str();
  cmd->add_option("--unit", opt->unit,
                  "Unit of the values (after --lsb): " + known_units() +
                      "; one for all columns or one per column. Default: from the column names' suffixes; rate "
                      "sensors get N in deg/sqrt(h), K in deg/h/sqrt(h), Gauss-Markov sigma in deg/h");
  cmd->add_option("--bootstrap", opt->bootstrap,
                  "Parametric bootstrap replicates for the uncertainties (the fitted model simulated at the "
                  "record's length and refitted); 0: none")
      ->check(whole_number(0, 100000))
      ->capture_default_str();
  cmd->add_option("--seed", opt->seed, "Seed of the bootstrap (same seed, same result)")
      ->check(whole_number(0, 1e18))
      ->capture_default_str();
  cmd->add_option("--ci", opt->ci, "Confidence of the wavelet variance's intervals and the bootstrap's")
      ->check(number_between(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--starts", opt->starts, "Starting points of the optimiser (the best fit is kept)")
      ->check(whole_number(1, 10000))
      ->capture_default_str();
  CLI::Option* robust =
      cmd->add_flag("--robust", opt->robust,
                    "Robust wavelet variance: a biweight M-estimate of each scale's Haar coefficients instead of their "
                    "mean square, so that spikes and bad samples do not dominate the fit (protects the scales where "
                    "the outlying share of samples times the scale stays small)");
  cmd->add_option("--efficiency", opt->efficiency,
                  "Gaussian efficiency of the robust wavelet variance (lower: more robust, wider intervals)")
      ->check(number_between(0.0, 1.0))
      ->needs(robust)
      ->capture_default_str();
  cmd->add_option("--format", opt->format, "Output format")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file if it exists");
  cmd->callback([opt, &run] { run = [opt] { return run_model_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
