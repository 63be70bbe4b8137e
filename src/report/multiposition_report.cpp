// The page of `cubecal calibrate multiposition`: the static poses found, the
// accelerometer and gyroscope parameters with 1σ, and the residuals before
// and after calibration.
#include "command_util.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

namespace mp = cubecal::multipos;

ReportTable parameter_table(const std::string& title, const std::vector<std::string>& names,
                            const std::vector<double>& values, const std::vector<double>& sigma,
                            const std::vector<std::string>& units) {
  ReportTable t;
  t.title = title;
  t.header = {"parameter", "value ± 1σ", "unit"};
  t.numeric = {false, true, false};
  for (std::size_t i = 0; i < names.size(); ++i)
    t.rows.push_back({names[i], format_pm(values[i], i < sigma.size() ? sigma[i] : 0.0),
                      i < units.size() ? units[i] : std::string()});
  return t;
}

std::vector<std::string> residual_row(const std::string& label, const mp::Residuals& r) {
  return {label, std::to_string(r.count), format_num(r.rms, 5), format_num(r.max, 5), format_num(r.cost, 6)};
}

}  // namespace

CommandReport multiposition_report(const pipeline::MultipositionResult& r, const std::string& command) {
  const mp::AccResult& a = r.accelerometer;
  const mp::Options& o = r.options;
  CommandReport rep;
  rep.title = "Multi-position calibration: " + base_name(r.acc_file);
  rep.lead_html = "Accelerometer" + std::string(r.gyroscope ? " and gyroscope" : "") +
                  " calibration from static poses without a turntable (Tedaldi, Pretto &amp; Menegatti 2014) by "
                  "<code>cubecal calibrate multiposition</code>: X′ = T K (X − B), T the misalignment, K the scale "
                  "factors, B the bias of each triad.";
  rep.command = command;
  rep.input = {{"accelerometer", r.acc_file, true}};
  if (r.gyro_file) rep.input.push_back({"gyroscope", *r.gyro_file == r.acc_file ? "(same file)" : *r.gyro_file, true});
  rep.input.push_back({"samples", std::to_string(r.samples) + " at " + format_num(r.rate_hz, 6) + " Hz", false});
  rep.input.push_back({"gravity g", format_num(o.g, 6), false});
  rep.input.push_back({"initial static period",
                       format_num(o.init_static_s, 6) + " s (" + std::to_string(a.init_samples) + " samples)", false});
  rep.input.push_back({"static intervals",
                       std::to_string(a.intervals.size()) + " (th_mult " + std::to_string(a.th_mult) + ", threshold " +
                           format_num(a.threshold, 4) + ")",
                       false});
  if (!a.converged) rep.notes.push_back("The accelerometer fit did not converge.");
  if (r.gyroscope && !r.gyroscope->converged) rep.notes.push_back("The gyroscope fit did not converge.");

  ReportSection poses{"poses", "Static poses", {}};
  ReportTable trials;
  trials.title = "Threshold trials";
  trials.header = {"th_mult", "threshold", "intervals", "cost"};
  for (const mp::Trial& t : a.trials)
    trials.rows.push_back({std::to_string(t.th_mult), format_num(t.threshold, 4), std::to_string(t.intervals),
                           t.fitted ? format_num(t.cost, 4) : std::string("—")});
  trials.note =
      "The calibration uses the threshold multiple with the lowest cost (th_mult " + std::to_string(a.th_mult) + ").";
  poses.blocks.push_back({{}, std::move(trials), {}});
  ReportTable iv;
  iv.title = "Intervals used";
  iv.header = {"#", "first sample", "last sample", "t begin [s]", "t end [s]"};
  for (std::size_t k = 0; k < a.intervals.size(); ++k) {
    const auto [t0, t1] = k < r.interval_times.size() ? r.interval_times[k] : std::pair{0.0, 0.0};
    iv.rows.push_back({std::to_string(k + 1), std::to_string(a.intervals[k].begin), std::to_string(a.intervals[k].end),
                       format_num(t0, 6), format_num(t1, 6)});
  }
  poses.blocks.push_back({{}, std::move(iv), {}});
  rep.sections.push_back(std::move(poses));

  ReportSection acc{"accelerometer", "Accelerometer", {}};
  acc.blocks.push_back(
      {{}, parameter_table("a′ = T K (a − B)", a.names, a.values, a.sigma, pipeline::multiposition_acc_units()), {}});
  ReportTable ar;
  ar.title = "Residuals g − |a′|";
  ar.header = {"", "count", "RMS", "max", "cost Σr²"};
  ar.rows.push_back(residual_row("before (initial guess)", a.before));
  ar.rows.push_back(residual_row("after", a.after));
  ar.note = "In the unit of g; " + std::to_string(a.iterations) + " iterations.";
  acc.blocks.push_back({{}, std::move(ar), {}});
  rep.sections.push_back(std::move(acc));

  if (const auto& g = r.gyroscope) {
    ReportSection gs{"gyroscope", "Gyroscope", {}};
    gs.blocks.push_back({{},
                         parameter_table("w′ = T K (w − B), w′ in rad/s", g->names, g->values, g->sigma,
                                         pipeline::multiposition_gyro_units(g->names.size())),
                         {}});
    ReportTable gr;
    gr.title = "Gravity direction after integration between poses";
    gr.header = {"", "count", "RMS", "max", "cost Σr²"};
    gr.rows.push_back(residual_row("before (scale guess)", g->before));
    gr.rows.push_back(residual_row("after", g->after));
    gr.note = std::to_string(g->pairs) + " pose pairs; angle RMS " + format_num(g->angle_rms_before_deg, 4) + " → " +
              format_num(g->angle_rms_after_deg, 4) + " deg, max after " + format_num(g->angle_max_after_deg, 4) +
              " deg; " + std::to_string(g->iterations) + " iterations.";
    gs.blocks.push_back({{}, std::move(gr), {}});
    rep.sections.push_back(std::move(gs));
  }
  return rep;
}

}  // namespace cubecal::report
