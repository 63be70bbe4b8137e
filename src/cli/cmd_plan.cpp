// cubecal plan: how long to record for the precision each noise term needs,
// or the precision a record of a given length gives (pipeline/plan.hpp).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <optional>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/sample_checks.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "cubecal/pipeline/plan.hpp"
#include "cubecal/pipeline/plan_json.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/report/plan_report.hpp"
#include "cubecal/sim/presets.hpp"
#include "field_flags.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct PlanCliOptions {
  std::string presets;
  std::string model_file;
  std::string datasheet;
  std::optional<double> rate_hz;
  std::string target;
  double ci = 0.683;
  std::string duration;
  std::string taus = "log:10";
  std::string format = "table";
  std::string out;
  bool force = false;
  ReportTarget report;
};

// The model source: exactly one of --preset, --model, --datasheet.
void set_source(pipeline::PlanRequest& req, const PlanCliOptions& o) {
  std::vector<std::string> given;
  if (!o.presets.empty()) given.emplace_back("--preset");
  if (!o.model_file.empty()) given.emplace_back("--model");
  if (!o.datasheet.empty()) given.emplace_back("--datasheet");
  if (given.empty())
    throw UsageError(
        "no sensor model: give --preset NAME, --model FILE (an analysis.json or the JSON of cubecal model) or "
        "--datasheet TERMS with --rate");
  if (given.size() > 1)
    throw UsageError(given[0] + " and " + given[1] + ": give one sensor model (--preset, --model or --datasheet)");
  if (!o.presets.empty()) {
    try {
      pipeline::set_plan_presets(req, split_list(o.presets), o.rate_hz);
    } catch (const UsageError& e) {
      if (e.field() != Field::model) throw;
      throw UsageError(std::string("--preset: ") + e.what());  // the library names the model source
    }
  } else if (!o.model_file.empty())
    pipeline::set_plan_model_file(req, o.model_file, o.rate_hz);
  else
    pipeline::set_plan_datasheet(req, o.datasheet, o.rate_hz);
}

// The targets of --target. The library's messages on Field::target do not
// name the flag (field_flags.cpp: Prefix::no, as record's own say it): here they do.
std::vector<PlanTarget> targets_of(const std::string& spec) {
  try {
    std::vector<PlanTarget> targets = parse_plan_targets(spec);
    pipeline::PlanRequest check;
    check.targets = targets;
    check.source = pipeline::PlanSource::preset;  // only the targets are checked here
    check.triads.emplace_back();
    check.rate_hz = 1.0;
    check.validate();
    return targets;
  } catch (const UsageError& e) {
    if (e.field() != Field::target || e.named() != UsageError::Named::in_front) throw;
    throw UsageError("--target: " + flag_words(e.text()));
  }
}

pipeline::PlanRequest request_of(const PlanCliOptions& o) {
  pipeline::PlanRequest req;
  // The options a user can get wrong without reading a file, first.
  if (!o.target.empty()) req.targets = targets_of(o.target);
  if (!o.duration.empty()) {
    try {
      req.duration_s = pipeline::parse_duration(o.duration);
    } catch (const UsageError& e) {
      throw UsageError(Field::duration, e.what());
    }
  }
  req.ci = o.ci;
  req.grid = parse_taus(o.taus);
  set_source(req, o);
  req.validate();
  return req;
}

// Rows of cells printed left-aligned in columns, the last one free.
void print_columns(std::ostream& out, const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const auto& r : rows)
    for (std::size_t c = 0; c + 1 < r.size(); ++c) {
      if (width.size() <= c) width.resize(c + 1, 0);
      width[c] = std::max(width[c], r[c].size());
    }
  for (const auto& r : rows) {
    std::string line;
    for (std::size_t c = 0; c < r.size(); ++c)
      line += c + 1 < r.size() ? fmt::format("{:<{}}  ", r[c], width[c]) : r[c];
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out << "  " << line << '\n';
  }
}

std::string value_text(const pipeline::PlanRow& row) {
  if (!std::isfinite(row.display.value)) return "-";
  return fmt::format("{:.4g} {}", row.display.value, row.display.unit);
}

// Why a row has no length or precision, in words.
std::string reason_text(const pipeline::PlanRow& row) {
  if (row.at.reason == PlanReason::none) return "";
  return row.at.why.empty() ? std::string(to_string(row.at.reason)) : row.at.why;
}

void write_table(std::ostream& out, const pipeline::PlanResult& r) {
  const bool datasheet = r.source == pipeline::PlanSource::datasheet;
  fmt::print(out, "plan for {} ({}) at {} Hz\n", datasheet ? "the datasheet " + r.source_name : r.source_name,
             datasheet ? r.source_note
                       : std::string(to_string(r.source)) + (r.source_note.empty() ? "" : ": " + r.source_note),
             rate_text(r.rate_hz));
  fmt::print(out, "precision: the half-width of a term's {:.3g} % interval, relative to the term\n", 100.0 * r.ci);
  if (r.defaults)
    out << "neither --target nor --duration: the length for B:10%,N:1%,K:20%,T:30% and the precision at 72 h\n";
  bool any_targets = false, any_duration = false;
  for (const auto& ch : r.channels) {
    any_targets = any_targets || !ch.targets.empty();
    any_duration = any_duration || !ch.at_duration.empty();
  }
  if (any_targets) {
    out << "\nrecord length each target needs\n";
    std::vector<std::vector<std::string>> rows{{"channel", "term", "value", "target", "record length", ""}};
    for (const auto& ch : r.channels)
      for (const auto& row : ch.targets)
        rows.push_back({ch.name, std::string(to_string(row.at.term)), value_text(row),
                        pipeline::percent_words(*row.target), pipeline::duration_words(row.duration_s),
                        reason_text(row)});
    print_columns(out, rows);
  }
  if (any_duration && r.duration_s) {
    fmt::print(out, "\nprecision from a record of {}\n", pipeline::duration_words(*r.duration_s));
    std::vector<std::vector<std::string>> rows{{"channel", "term", "value", "precision", ""}};
    for (const auto& ch : r.channels)
      for (const auto& row : ch.at_duration)
        rows.push_back(
            {ch.name, std::string(to_string(row.at.term)), value_text(row),
             pipeline::percent_words(row.at.reason == PlanReason::none ? row.at.precision
                                                                       : std::numeric_limits<double>::quiet_NaN()),
             reason_text(row)});
    print_columns(out, rows);
  }
}

int run_plan_command(const PlanCliOptions& o) {
  check_report_option(o.report, o.force);
  ResultOutput result(o.out, o.force);  // refuses an unusable --out before the work
  const pipeline::PlanRequest req = request_of(o);
  const pipeline::PlanResult res = pipeline::run_plan(req);
  if (!req.source_note.empty() && req.source == pipeline::PlanSource::random_walk)
    std::cerr << "cubecal: note: " << req.source_name << ": planning " << req.source_note << '\n';
  std::ostream& out = result.stream();
  if (o.format == "json")
    out << pipeline::json_text(pipeline::to_json(res), 1) << '\n';
  else
    write_table(out, res);
  result.finish();
  if (!o.report.dir.empty()) write_report_option(report::plan_report(res, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_plan_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<PlanCliOptions>();
  std::string presets;
  for (const auto& n : preset_names()) presets += (presets.empty() ? "" : ", ") + n;
  CLI::App* cmd = app.add_subcommand(
      "plan",
      "How long to record: from a sensor model (a preset, an analysis.json, a cubecal model result or datasheet "
      "terms) the static record length each noise term needs for a target precision (--target B:10%,N:1%), or "
      "the precision a record of --duration gives; without either, both for the defaults");
  cmd->add_option("--preset", opt->presets, "Comma-separated presets: " + presets);
  cmd->add_option("--model", opt->model_file,
                  "analysis.json of cubecal analyze (its twins, else its random-walk model) or the JSON of cubecal "
                  "model --format json (its composite models)");
  cmd->add_option("--datasheet", opt->datasheet,
                  "Datasheet terms, e.g. \"N=0.15deg/rth,B=6deg/h,K=0.02deg/h/rth\" (Q, N, B, K, R with their "
                  "units: deg/sqrt(h), deg/s/sqrt(Hz), deg/h, deg/h/sqrt(h), uT/rtHz, ug, ...); needs --rate");
  cmd->add_option("--rate", opt->rate_hz,
                  "Sampling rate of the record to plan, Hz (default: the model's; a preset's is 10 Hz); a model is "
                  "rescaled to it, keeping its N and K")
      ->check(number_between(io::kMinRateHz, io::kMaxRateHz));
  cmd->add_option("--target", opt->target,
                  "Targets TERM:PRECISION, e.g. B:10%,N:1%,K:20%,T:30% (TERM one of Q, N, B, K, R, T; the "
                  "half-width of the term's --ci interval relative to it)");
  cmd->add_option("--ci", opt->ci, "Confidence of the precisions (0.683: 1 sigma)")
      ->check(number_between(1e-6, 0.999999))
      ->capture_default_str();
  cmd->add_option("--duration", opt->duration, "A record length whose precision to plan: 72h, 30m, 3600s, 2d");
  cmd->add_option("--taus", opt->taus, "Tau grid of the analysis the plan stands for")->capture_default_str();
  cmd->add_option("--format", opt->format, "table or json (a list of {channel, term, precision, duration_s, ...})")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->callback([opt, &run] { run = [opt] { return run_plan_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
