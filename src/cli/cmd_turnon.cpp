// cubecal turnon: turn-on bias over power-cycled runs; cubecal compare: Allan
// curves and N, B, T of several runs side by side (sampling rates, units).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "common_options.hpp"
#include "file_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/noise/unit_from_name.hpp"
#include "cubecal/pipeline/turnon.hpp"
#include "cubecal/pipeline/turnon_json.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "cubecal/report/command_reports.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct RunsOptions {
  InputOptions input;
  std::string unit;  // empty: from the column names (units_for)
  std::string taus = "log:10";
  double ci = 0.683;
  std::string format = "table";
  std::string out;
  bool force = false;
  ReportTarget report;  // --report DIR, --gnuplot PATH
};

pipeline::AnalyzeRequest request_of(const RunsOptions& o) {
  pipeline::AnalyzeRequest req;
  if (!o.unit.empty()) req.units = parse_units(o.unit);  // else from the column names: runs_units()
  req.grid = parse_taus(o.taus);
  if (!(o.ci > 0.0 && o.ci < 1.0)) throw UsageError("--ci must be between 0 and 1");
  req.ci = o.ci;
  req.threads = o.input.threads;
  return req;
}

// The record arguments with their own options (FILE:key=value,...), all
// checked before any file is read.
std::vector<FileSpec> file_specs(const RunsOptions& o, bool per_file_unit, const char* command) {
  std::vector<FileSpec> specs;
  for (const auto& f : o.input.files) {
    specs.push_back(parse_file_spec(f, o.input, o.unit));
    if (specs.back().own_unit && !per_file_unit)
      throw UsageError(f + ": " + command +
                       " averages the runs' biases, so every run is in the same unit: give "
                       "--unit (or scale a run with lsb=), not unit= per file");
  }
  return specs;
}

std::vector<io::Series> read_runs(const std::vector<FileSpec>& specs) {
  std::vector<io::Series> runs;
  for (const auto& f : specs) runs.push_back(io::read_series(f.path, to_series_options(f.input)));
  return runs;
}

// The request of each run with its units: its own unit=, else --unit, else
// those the column names of the first such run announce, which every other
// such run's names must announce too.
std::vector<pipeline::AnalyzeRequest> requests_for(const RunsOptions& o, const std::vector<FileSpec>& specs,
                                                   const std::vector<io::Series>& runs) {
  std::vector<pipeline::AnalyzeRequest> reqs(runs.size(), request_of(o));
  const io::Series* reference = nullptr;
  std::vector<Unit> inferred;
  std::string note;  // said once every run is checked
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (specs[k].own_unit || !o.unit.empty()) {
      reqs[k].units = parse_units(specs[k].unit);
      continue;
    }
    if (!reference) {
      ChannelUnits first = units_for({}, runs[k]);
      inferred = std::move(first.units);
      reference = &runs[k];
      note = std::move(first.note);
    } else {
      // As the first such run's: from the names, or from the format (ROS bags).
      std::vector<Unit> other;
      try {
        other = units_for({}, runs[k]).units;
      } catch (const UsageError&) {
      }
      bool same = other.size() == inferred.size();
      for (std::size_t c = 0; same && c < inferred.size(); ++c) same = other[c].name == inferred[c].name;
      if (!same)
        throw UsageError(runs[k].file + ": its column names do not announce the units of " + reference->file +
                         "'s: give --unit, or unit= after the file (FILE:unit=...)");
    }
    reqs[k].units = inferred;
  }
  if (!note.empty()) std::cerr << note << '\n';
  return reqs;
}

// "value ± sigma unit" in the term's display unit (N in deg/sqrt(h), B in
// deg/h for a gyro), "—" when the term is not read.
std::string term(const TermEstimate& t, Term which, const Unit& u) {
  if (!t.valid) return "—";
  const Quantity q = display(t, which, u);
  return fmt::format("{:.4g} ± {:.2g} {}", q.value, q.sigma, q.unit);
}

report::RunsReportContext report_context(const RunsOptions& o) { return {invocation(), o.ci, o.taus}; }

std::string turnon_text(const RunsOptions& o, const pipeline::TurnOnResult& t) {
  if (o.format == "json") return pipeline::json_text(pipeline::to_json(t), 1) + "\n";
  std::string s = fmt::format("Turn-on bias over {} runs ({:.1f} % interval of the standard deviation, {} dof)\n\n",
                              t.runs.size(), 100 * t.ci, t.runs.size() - 1);
  s += fmt::format("{:<28}", "run");
  for (const auto& n : t.names) s += fmt::format(" {:>16} {:>24}", n + " bias", "B");
  s += '\n';
  for (const auto& r : t.runs) {
    s += fmt::format("{:<28}", r.file.size() > 28 ? "…" + r.file.substr(r.file.size() - 27) : r.file);
    for (const auto& c : r.channels) s += fmt::format(" {:>16.6g} {:>24}", c.mean, term(c.readoffs.B, Term::B, c.unit));
    s += '\n';
  }
  s += fmt::format("\n{:<10} {:>14} {:>14} {:>26}\n", "channel", "mean bias", "turn-on (std)", "interval");
  for (std::size_t c = 0; c < t.names.size(); ++c)
    s += fmt::format("{:<10} {:>14.6g} {:>14.4g} {:>12.4g} – {:<11.4g} {}\n", t.names[c], t.mean_bias[c], t.turn_on[c],
                     t.turn_on_interval[c].lo, t.turn_on_interval[c].hi, t.units[c].name);
  return s;
}

std::string compare_text(const RunsOptions& o, const std::vector<pipeline::RunSummary>& runs) {
  if (o.format == "json") return pipeline::json_text(pipeline::to_json(runs), 1) + "\n";
  std::string s = fmt::format("{:<28} {:>8} {:>10} {:<8} {:>28} {:>24} {:>10}\n", "run", "rate Hz", "samples", "axis",
                              "N", "B", "T [s]");
  for (const auto& r : runs)
    for (const auto& c : r.channels) {
      const auto& ro = c.readoffs;
      s += fmt::format("{:<28} {:>8.4g} {:>10} {:<8} {:>28} {:>24} {:>10}\n",
                       r.file.size() > 28 ? "…" + r.file.substr(r.file.size() - 27) : r.file, r.rate_hz, r.samples,
                       c.name, term(ro.N, Term::N, c.unit), term(ro.B, Term::B, c.unit),
                       ro.B.valid ? fmt::format("{:.3g}", ro.tau_min) : "—");
    }
  return s;
}

// turnon with one recording directory (cubecal record): its segments, one
// per run of the recorder, are the power-cycled runs.
std::vector<io::Series> read_turnon_runs(std::vector<FileSpec>& specs) {
  if (specs.size() != 1 || !io::looks_like_recording(specs.front().path)) return read_runs(specs);
  auto runs = io::read_recording_segments(specs.front().path, to_series_options(specs.front().input));
  if (runs.size() < 2)
    throw UsageError(specs.front().path + ": the recording has " + std::to_string(runs.size()) +
                     " segment with samples; turn-on bias needs at least 2 (record each power cycle with the same "
                     "--out, or give several records)");
  specs.assign(runs.size(), specs.front());
  return runs;
}

int run_turnon_command(const RunsOptions& o) {
  check_report_option(o.report, o.force);
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  auto specs = file_specs(o, false, "turnon");
  const auto runs = read_turnon_runs(specs);
  const auto t = pipeline::run_turnon(runs, requests_for(o, specs, runs).front());
  result.stream() << turnon_text(o, t);
  result.finish();
  if (!o.report.dir.empty()) write_report_option(report::turnon_report(t, report_context(o)), o.report);
  return 0;
}

int run_compare_command(const RunsOptions& o) {
  check_report_option(o.report, o.force);
  ResultOutput result(o.out, o.force);
  const auto specs = file_specs(o, true, "compare");
  const auto records = read_runs(specs);
  const auto runs = pipeline::run_compare(records, requests_for(o, specs, records));
  result.stream() << compare_text(o, runs);
  result.finish();
  if (!o.report.dir.empty()) write_report_option(report::compare_report(runs, report_context(o)), o.report);
  return 0;
}

void add_runs_options(CLI::App& cmd, RunsOptions& o) {
  add_input_options(cmd, o.input, true);
  cmd.get_option("files")->description(
      "Input files (one record each): delimited text, optionally gzip, NumPy .npy, HDF5, raw binary (--binary), "
      "ROS bags (ROS 1 .bag, MCAP, .db3 or a ROS 2 bag directory), PX4 ULog or a recording directory of cubecal "
      "record. FILE:key=value,... reads one file with its "
      "own options in place of the command's (keys " +
      file_option_keys() +
      "; a list value such as "
      "columns=gx,gy,lsb=131,131 runs on to the next key=), for runs of different layouts, rates or scales. Only the "
      "text after the last ':' is taken as options, and only when it starts with key=; a FILE that exists as "
      "named is always a file");
  cmd.add_option("--unit", o.unit, unit_option_help());
  cmd.add_option("--taus", o.taus, "Tau grid")->capture_default_str();
  cmd.add_option("--ci", o.ci, "Confidence factor")->capture_default_str();
  cmd.add_option("--format", o.format, "table or json")->check(CLI::IsMember({"table", "json"}))->capture_default_str();
  cmd.add_option("--out", o.out, "Write the result to this file");
  cmd.add_flag("--force", o.force, "Replace --out and the --report files if they exist");
  add_report_option(cmd, o.report);
}

}  // namespace

CLI::App* add_turnon_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<RunsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "turnon",
      "Turn-on bias: per-run bias, mean over runs, standard deviation of the run biases with its "
      "interval, and each run's bias instability; a recording directory of cubecal record given alone: "
      "its segments (one per power cycle) are the runs");
  add_runs_options(*cmd, *opt);
  cmd->callback([opt, &run] { run = [opt] { return run_turnon_command(*opt); }; });
  return cmd;
}

CLI::App* add_compare_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<RunsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "Allan curves of several runs (sampling rates, units) side by side, with N, B, T per run");
  add_runs_options(*cmd, *opt);
  cmd->callback([opt, &run] { run = [opt] { return run_compare_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
