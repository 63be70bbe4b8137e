// The page of `cubecal plan`: the plan's rows as a table, and per channel the
// precision of each term against record length on log-log axes, with the
// targets and the planned lengths drawn in, so a reader sees how much a
// shorter or longer record gives or costs (docs/formulas/planning.md).
#include "cubecal/report/plan_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "command_util.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

const char* term_color(PlanTerm t) {
  switch (t) {
    case PlanTerm::Q: return "#8c564b";
    case PlanTerm::N: return "#1f77b4";
    case PlanTerm::B: return "#d62728";
    case PlanTerm::K: return "#2ca02c";
    case PlanTerm::R: return "#9467bd";
    case PlanTerm::T: return "#ff7f0e";
  }
  return kInkColor;
}

constexpr double kHour = 3600.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string value_text(const pipeline::PlanRow& row) {
  if (!std::isfinite(row.display.value)) return "—";
  return format_num(row.display.value, 4) + " " + row.display.unit;
}

ReportTable rows_table(const pipeline::PlanResult& r) {
  ReportTable t;
  t.header = {"channel", "term", "value", "target", "record length", "precision", "reason"};
  t.numeric = {false, false, true, true, true, true, false};
  for (const auto& ch : r.channels) {
    for (const auto& row : ch.targets)
      t.rows.push_back({ch.name, std::string(to_string(row.at.term)), value_text(row),
                        pipeline::percent_words(*row.target), pipeline::duration_words(row.duration_s),
                        pipeline::percent_words(row.at.reason == PlanReason::none ? row.at.precision : kNaN),
                        row.at.why});
    for (const auto& row : ch.at_duration)
      t.rows.push_back({ch.name, std::string(to_string(row.at.term)), value_text(row), "—",
                        pipeline::duration_words(row.duration_s) + " (asked)",
                        pipeline::percent_words(row.at.reason == PlanReason::none ? row.at.precision : kNaN),
                        row.at.why});
  }
  t.note = "precision: the half-width of the term's " + format_num(100.0 * r.ci, 3) +
           " % interval relative to the term; record length: the shortest static record whose analysis gives the "
           "target (a target row), or the length asked (its precision beside it).";
  return t;
}

// A marker at each row's (length, precision) on its term's curve.
void mark_rows(Plot& p, const pipeline::PlanChannel& ch) {
  for (const auto* rows : {&ch.targets, &ch.at_duration})
    for (const auto& row : *rows) {
      if (row.at.reason != PlanReason::none || !std::isfinite(row.duration_s)) continue;
      PlotSeries s;
      s.id = std::string(to_string(row.at.term)) + (row.target ? " planned length" : " at the asked length");
      s.x = {row.duration_s / kHour};
      s.y = {100.0 * row.at.precision};
      s.mark = Mark::points;
      s.point_size = 1.2;
      s.color = term_color(row.at.term);
      p.series.push_back(std::move(s));
    }
}

ReportFigure channel_figure(const pipeline::PlanResult& r, const pipeline::PlanChannel& ch,
                            std::vector<std::string>& taken) {
  ReportFigure f;
  Plot& p = f.plot;
  p.name = unique_name("plan_", ch.name, taken);
  p.title = ch.name + ": precision against record length";
  p.x = {"record length [h]", true, std::nullopt, std::nullopt};
  p.y = {"precision [%] (half-width of the " + format_num(100.0 * r.ci, 3) + " % interval)", true, std::nullopt,
         std::nullopt};
  double x0 = std::numeric_limits<double>::infinity(), x1 = 0.0;
  for (const auto& c : ch.curves) {
    PlotSeries s;
    s.label = std::string(to_string(c.term));
    for (std::size_t i = 0; i < c.duration_s.size(); ++i) {
      x0 = std::min(x0, c.duration_s[i] / kHour);
      x1 = std::max(x1, c.duration_s[i] / kHour);
      if (!std::isfinite(c.precision[i])) continue;
      s.x.push_back(c.duration_s[i] / kHour);
      s.y.push_back(100.0 * c.precision[i]);
    }
    s.color = term_color(c.term);
    if (!s.x.empty()) p.series.push_back(std::move(s));
  }
  for (const auto& row : ch.targets)
    if (x1 > x0)
      p.series.push_back(hline(100.0 * *row.target, x0, x1, term_color(row.at.term), Dash::dashed,
                               std::string(to_string(row.at.term)) + " target"));
  mark_rows(p, ch);
  p.series.push_back(legend_only("target", kInkColor, Mark::line, Dash::dashed));
  PlotSeries marks = legend_only("planned length", kInkColor, Mark::points);
  marks.point_size = 1.2;
  p.series.push_back(std::move(marks));
  f.caption_html = "<b>" + html_escape(ch.name) +
                   "</b>: each term's precision from a static record of the length on the x axis (solid), the "
                   "targets (dashed, in the term's colour) and the length each needs (a mark where the curve meets "
                   "it; also the precision at an asked length). A term missing from a length is not resolved there.";
  return f;
}

}  // namespace

std::vector<ReportFigure> plan_figures(const pipeline::PlanResult& r) {
  std::vector<ReportFigure> figs;
  std::vector<std::string> taken;
  for (const auto& ch : r.channels) figs.push_back(channel_figure(r, ch, taken));
  return figs;
}

CommandReport plan_report(const pipeline::PlanResult& r, const std::string& command) {
  CommandReport rep;
  rep.title =
      "Record plan: " + (r.source == pipeline::PlanSource::datasheet ? std::string("datasheet") : r.source_name);
  rep.lead_html =
      "How long a static record must be for the precision asked of each noise term, and the precision a record of "
      "a given length gives, by <code>cubecal plan</code>: from the sensor model's own Allan curve, its EDF at the "
      "taus each term is read from and the spread of the curve's minimum. Derivation: "
      "<code>docs/formulas/planning.md</code>.";
  rep.command = command;
  rep.plot_prefixes = {"plan_"};
  rep.input = {
      {"model", r.source_name, true},
      {"model source",
       std::string(to_string(r.source)) + (r.source_note.empty() ? std::string() : ": " + r.source_note), false},
      {"sampling rate", format_num(r.rate_hz, 6) + " Hz", false},
      {"confidence", format_num(100.0 * r.ci, 3) + " %", false}};
  if (r.defaults)
    rep.notes.push_back(
        "Neither targets nor a duration were asked: the defaults, the length for B:10%,N:1%,K:20%,T:30% and the "
        "precision at the paper's 72 h.");
  ReportSection table{"plan", "Plan", {}};
  ReportBlock b;
  b.table = rows_table(r);
  table.blocks.push_back(std::move(b));
  rep.sections.push_back(std::move(table));
  const auto figs = plan_figures(r);
  for (std::size_t k = 0; k < r.channels.size() && k < figs.size(); ++k) {
    std::string id = "channel-" + slug(r.channels[k].name);
    std::replace(id.begin(), id.end(), '_', '-');
    rep.sections.push_back({id, r.channels[k].name, {{{}, std::nullopt, {figs[k]}}}});
  }
  return rep;
}

}  // namespace cubecal::report
