// cubecal dev: the Allan family of deviations with confidence intervals.
#include <fmt/format.h>

#include <algorithm>

#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "field_flags.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"
#include "cubecal/pipeline/dev_stream.hpp"
#include "cubecal/pipeline/dev_missing.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "cubecal/printable_text.hpp"
#include "cubecal/stats/statistic.hpp"
#include "memory_budget.hpp"
#include "output.hpp"
#include "progress.hpp"
#include "timings.hpp"

namespace cubecal::cli {

namespace {

struct DevOptions {
  InputOptions input;
  std::string stat = "oadev";
  std::string type;  // empty: what the file says (a Stable32 .DAT header), else freq
  std::string taus = "octave";
  double ci = 0.683;
  std::string edf = "greenhall";
  std::optional<int> alpha;
  bool no_ci = false;
  bool bias_correction = false;
  bool no_bias_correction = false;
  std::string short_ci = "stable32";
  std::string format = "table";
  std::string out;
  bool force = false;
  MemoryOptions memory;
  Timings timings;
};

std::size_t samples_of(const io::Series& s) { return s.channels.empty() ? 0 : s.channels[0].size(); }

void write_dev(const DevOptions& o, const pipeline::DevResult& res, ResultOutput& result) {
  for (const std::string& line : {excluded_taus_warning(res.tau_list), merged_taus_note(res.tau_list)})
    if (!line.empty()) std::cerr << line << '\n';
  DevContext ctx{o.input.file, o.ci, o.edf, !o.no_ci};
  std::ostream& out = result.stream();
  if (o.format == "json")
    out << pipeline::json_text(pipeline::to_json(res), 1) << '\n';
  else if (o.format == "csv")
    write_dev_csv(out, res, ctx);
  else
    write_dev_table(out, res, ctx);
  result.finish();
}

int run_dev_stream_command(const DevOptions& o, pipeline::DevRequest req, const io::SeriesOptions& series_opt,
                           std::size_t budget, ResultOutput& result) {
  pipeline::check_streamable(req);  // before the input is opened
  const auto input = io::SampleStream::open(o.input.file, series_opt);
  const std::size_t bound =
      stream_window(o.memory, budget, input->names().size(), estimated_samples(o.input.file, series_opt));
  // On a terminal: the share of a file read with the time left, or the
  // samples of a pipe so far.
  Progress progress(true);
  progress.stage(fmt::format("{} of {} channel(s), streamed", to_string(req.stat), input->names().size()));
  req.progress = [&](double f) {
    if (input->total_bytes() > 0)
      progress.fraction(f);
    else
      progress.count(static_cast<double>(input->rows_read()), "samples");
  };
  const pipeline::DevResult res = pipeline::run_dev_stream(*input, req, bound);
  progress.done();
  write_dev(o, res, result);
  return 0;
}

// The request of the command line (TIE rms and MTIE: --no-ci set, as
// they have no noise type or interval).
pipeline::DevRequest dev_request(DevOptions& o) {
  pipeline::DevRequest req;
  req.stat = *parse_stat(o.stat);
  req.type = *parse_data_type(o.type.empty() ? "freq" : o.type);
  req.grid = parse_taus(o.taus);
  if (!(o.ci > 0.0 && o.ci < 1.0)) throw UsageError("--ci must be between 0 and 1 (e.g. 0.683 or 0.95)");
  req.options.ci = o.ci;
  req.options.edf = o.edf == "simple" ? EdfMethod::simple : EdfMethod::greenhall;
  req.options.alpha = o.alpha;
  req.options.intervals = !o.no_ci;
  req.options.conservative_short = o.short_ci == "widest";
  req.options.bias_correction = o.bias_correction      ? BiasCorrection::on
                                : o.no_bias_correction ? BiasCorrection::off
                                                       : BiasCorrection::stable32;
  if (!has_intervals(req.stat)) o.no_ci = true;  // TIE rms and MTIE have no noise type or interval
  req.threads = o.input.threads;

  return req;
}

// Whether to stream a record that was not asked to be: when reading it
// whole would exceed the budget and the request can be streamed (a
// pipe's size is not known: --stream).
bool stream_beyond_budget(const DevOptions& o, const pipeline::DevRequest& req, const io::SeriesOptions& series_opt,
                          std::size_t budget) {
  // Streamed by itself when reading the file whole would exceed the budget
  // and the request can be streamed (a pipe's size is not known: --stream).
  const std::size_t need = in_memory_bytes(o.input.file, series_opt);
  const std::string recording_warning = recording_beyond_budget(o.input.file, need, budget);
  if (!recording_warning.empty()) {
    std::cerr << recording_warning;
  } else if (need > budget) {
    try {
      pipeline::check_streamable(req);
      std::cerr << fmt::format(
          "cubecal: note: reading {} whole would take about {:.0f} MB, more than the "
          "memory budget ({:.0f} MB, --memory): streaming it in one pass\n",
          o.input.file, static_cast<double>(need) / 1e6, static_cast<double>(budget) / 1e6);
      return true;
    } catch (const UsageError& e) {
      std::cerr << "cubecal: warning: " << o.input.file << " may not fit the memory budget (--memory), and it "
                << "cannot be streamed: " << flag_words(e.text()) << '\n';
    }
  }
  return false;
}

// The record read whole, with a note on its missing samples (--gaps skip).
io::Series read_dev_series(DevOptions& o) {
  const std::size_t bytes = file_size_or_zero(o.input.file);
  StageTimer reading_time(o.timings.sink(), Stage::read);
  const io::Series series = [&] {
    Progress reading(bytes > 50'000'000);
    reading.stage(fmt::format("reading {} ({:.0f} MB)", o.input.file, static_cast<double>(bytes) / 1e6));
    io::SeriesOptions so = to_series_options(o.input);
    so.max_inflated_bytes = memory_budget(o.memory);  // a gzip file's text within --memory
    so.keep_time = false;                             // the deviations need the rate and the segments, not the stamps
    return io::read_series(o.input.file, so);
  }();
  reading_time.stop();
  note_default_columns(series);
  if (series.gaps == io::GapPolicy::skip) {
    const auto missing = pipeline::missing_per_channel(series);
    std::size_t total = 0;
    for (const std::size_t m : missing) total += m;
    std::cerr << fmt::format(
        "cubecal: note: {}: {} missing sample(s) in {} channel(s) of {} samples: the OADEV "
        "terms that need one are left out (--gaps skip)\n",
        series.file, total, series.channels.size(), samples_of(series));
  }

  return series;
}

// The data type a Stable32 .DAT header gives, unless --type says otherwise
// (then the header is contradicted: refused).
void take_file_type(const DevOptions& o, const io::Series& series, pipeline::DevRequest& req) {
  if (!series.data_type) return;
  const DataType file_type = *series.data_type;
  if (o.type.empty()) {
    req.type = file_type;
    return;
  }
  if (req.type != file_type)
    throw UsageError(series.file + ": --type " + o.type + " contradicts the Stable32 header's Type: " +
                     (file_type == DataType::phase ? "Phase" : "Frequency") +
                     " (leave out --type, or correct the header)");
}

// The work estimated and, when long, announced before it starts with what
// a sparser grid costs.
pipeline::DevWorkEstimate announce_dev_work(const io::Series& series, const pipeline::DevRequest& req) {
  // Announce long work before it starts, with what a sparser grid costs.
  const pipeline::DevWorkEstimate work = pipeline::estimate_dev(series, req);
  const bool long_work = work.seconds > long_work_seconds();
  if (long_work) {
    pipeline::DevRequest sparse = req;
    sparse.grid = parse_taus("log:20");
    const pipeline::DevWorkEstimate quick = pipeline::estimate_dev(series, sparse);
    std::cerr << fmt::format(
        "cubecal: warning: {} at {} taus on {} channel(s) of {} samples is about {:.2g} terms: "
        "estimated {} on {} thread(s); --taus log:20 ({} taus) would take {}, --taus octave less\n",
        to_string(req.stat), work.taus, series.channels.size(), samples_of(series), work.terms,
        format_duration(work.seconds), work.threads, quick.taus, format_duration(quick.seconds));
  }
  return work;
}

// --gaps split: each tau pools the segments long enough for it, so when the
// segments differ in length the short taus and the long ones average
// different parts of the record (jittery stamps cut a bag into thousands of
// pieces of a few samples). Said on stderr, with the cause.
void warn_pooled_segments(const pipeline::DevResult& res, const io::Series& series) {
  if (series.segments.size() < 2 || res.channels.empty() || res.channels[0].points.empty()) return;
  const auto pooled = [&](std::size_t m) {
    std::size_t k = 0;
    for (const IndexRange& seg : series.segments) {
      const std::size_t n_phase = res.type == DataType::freq ? seg.size() + 1 : seg.size();
      k += max_averaging_factor(res.stat, n_phase) >= m;
    }
    return k;
  };
  const StabilityPoint& first = res.channels[0].points.front();
  const StabilityPoint& last = res.channels[0].points.back();
  const std::size_t a = pooled(first.m), b = pooled(last.m);
  if (a == b) return;
  std::size_t shortest = series.samples(), longest = 0;
  for (const IndexRange& seg : series.segments) {
    shortest = std::min(shortest, seg.size());
    longest = std::max(longest, seg.size());
  }
  std::cerr << fmt::format(
      "cubecal: warning: {}: {} irregular intervals cut the record into {} segments of {} to {} samples: tau {:.6g} s "
      "pools {} of them, tau {:.6g} s only {}, so each tau averages a different part of the record{}\n",
      printable_text(series.file), series.irregular_intervals, series.segments.size(), shortest, longest, first.tau, a,
      last.tau, b, series.rate_from_time ? " (jittery time stamps? --rate HZ takes the samples as evenly spaced)" : "");
}

// The result in the format asked for.
void write_dev_result(DevOptions& o, const pipeline::DevResult& res, const io::Series& series, ResultOutput& result) {
  StageTimer writing(o.timings.sink(), Stage::output);
  DevContext ctx{o.input.file, o.ci, o.edf, !o.no_ci};
  std::ostream& out = result.stream();
  if (res.segments > 1)
    std::cerr << fmt::format(
        "cubecal: note: {} gaps/jitter found; statistics computed per "
        "contiguous segment ({} segments) and combined\n",
        series.irregular_intervals, res.segments);
  warn_pooled_segments(res, series);
  if (o.format == "json")
    out << pipeline::json_text(pipeline::to_json(res), 1)
        << '\n';  // run_dev recorded the file and the interval options
  else if (o.format == "csv")
    write_dev_csv(out, res, ctx);
  else
    write_dev_table(out, res, ctx);
  result.finish();
  writing.stop();
}

int run_dev_command(DevOptions& o) {
  pipeline::DevRequest req = dev_request(o);
  if (o.input.gaps == "skip" && req.stat != Stat::oadev)
    throw UsageError(
        "--gaps skip: missing samples are skipped for OADEV only (as AllanTools' gradev): give "
        "--stat oadev, or --gaps split to analyze the contiguous pieces with " +
        std::string(to_string(req.stat)));
  ResultOutput result(o.out, o.force);  // refuses an unusable --out before the work
  const std::size_t budget = memory_budget(o.memory);
  const io::SeriesOptions series_opt = to_series_options(o.input);
  const bool stream = o.memory.stream || stream_beyond_budget(o, req, series_opt, budget);
  if (stream) {
    const int rc = run_dev_stream_command(o, req, series_opt, budget, result);
    print_timings(o.timings, req.threads);  // a stream's stages are one pass: the wall clock only
    return rc;
  }
  const io::Series series = read_dev_series(o);
  take_file_type(o, series, req);
  const pipeline::DevWorkEstimate work = announce_dev_work(series, req);
  const bool long_work = work.seconds > long_work_seconds();
  Progress progress(work.seconds > 2.0, long_work);
  progress.stage(fmt::format("{} at {} taus on {} channel(s)", to_string(req.stat), work.taus, series.channels.size()));
  req.progress = [&](double f) { progress.fraction(f); };
  req.times = o.timings.sink();
  const pipeline::DevResult res = pipeline::run_dev(series, req);
  progress.done();

  for (const std::string& line : {excluded_taus_warning(res.tau_list), merged_taus_note(res.tau_list)})
    if (!line.empty()) std::cerr << line << '\n';

  write_dev_result(o, res, series, result);
  print_timings(o.timings, req.threads);
  return 0;
}

}  // namespace

CLI::App* add_dev_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<DevOptions>();
  CLI::App* cmd = app.add_subcommand(
      "dev",
      "Stability statistics with Stable32-compatible confidence intervals: the Allan family (adev, "
      "oadev, mdev, tdev, hdev, ohdev, totdev), the total variances (mtotdev, ttotdev, htotdev), "
      "Theo1 and the bias-removed TheoBR (theo1, theobr: even averaging factors, tau = 0.75 m tau0), "
      "TheoH (theoh: OADEV below 20 % of the record, TheoBR beyond), "
      "and the time-interval errors (tierms, mtie: no intervals)");
  add_input_options(*cmd, opt->input);
  opt->input.missing_samples = true;  // --gaps skip
  cmd->add_option("--stat", opt->stat, "Statistic")
      ->check(CLI::IsMember(std::vector<std::string>(stat_names().begin(), stat_names().end())))
      ->capture_default_str();
  cmd->add_option("--type", opt->type,
                  "freq: rate-like samples (deg/s, fractional frequency); phase: their "
                  "integral (angle, time error in s). Default: the type a Stable32 .DAT header gives "
                  "(Type: Phase or Frequency), else freq")
      ->check(CLI::IsMember({"freq", "phase"}));
  cmd->add_option("--taus", opt->taus,
                  "Tau grid: octave, decade, all, log:K (K per decade) or a list of seconds "
                  "(1,10,100)")
      ->capture_default_str();
  cmd->add_option("--ci", opt->ci, "Confidence factor of the intervals")
      ->check(number_between(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--edf", opt->edf, "EDF: greenhall (as Stable32) or simple (SP 1065 Table 5)")
      ->check(CLI::IsMember({"greenhall", "simple"}))
      ->capture_default_str();
  cmd->add_option("--alpha", opt->alpha,
                  "Use this noise type (+2 WPM, +1 FPM, 0 WFM, -1 FFM, -2 RWFM; -3 FWFM and -4 RRFM "
                  "for the Hadamard family only: hdev, ohdev, htotdev) instead of identifying it")
      ->check(CLI::Range(-4, 2));
  cmd->add_flag("--no-ci", opt->no_ci, "Deviations only: skip noise identification and intervals");
  auto* bias = cmd->add_flag("--bias-correction", opt->bias_correction,
                             "totdev, mtotdev, ttotdev, htotdev: divide the variance by its bias for the noise type "
                             "(identified, or --alpha). Default: as Stable32, totdev and htotdev corrected where "
                             "the noise type is identified (not with --no-ci), mtotdev and ttotdev not");
  cmd->add_flag("--no-bias-correction", opt->no_bias_correction,
                "No bias correction: the plain totdev and htotdev estimators (as AllanTools)")
      ->excludes(bias);
  cmd->add_option("--short-ci", opt->short_ci,
                  "Intervals where fewer than 30 averages remain (the noise type comes from the B1 "
                  "ratio): stable32 (the identified type's EDF, as Stable32) or widest (the smallest "
                  "EDF of the identified type and its neighbours: never falsely narrow)")
      ->check(CLI::IsMember({"stable32", "widest"}))
      ->capture_default_str();
  cmd->add_option("--format", opt->format, "Output format")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file if it exists");
  add_memory_options(*cmd, opt->memory);
  add_timings_option(*cmd, opt->timings);
  cmd->callback([opt, &run] { run = [opt] { return run_dev_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
