// The pages of `cubecal turnon` and `cubecal compare`: runs of one sensor side
// by side. Allan curves of every run overlaid per channel (a colour per run,
// intervals as bars), and for turnon each run's bias against the mean over the
// runs and its turn-on standard deviation.
#include <algorithm>
#include <cmath>

#include "command_util.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

// Legend text of each run: its file name (the whole path when two runs share
// one), with the sampling rate when the runs differ in it.
std::vector<std::string> run_labels(const std::vector<pipeline::RunSummary>& runs) {
  bool same_base = false, same_rate = true;
  for (std::size_t a = 0; a < runs.size(); ++a)
    for (std::size_t b = a + 1; b < runs.size(); ++b) {
      same_base = same_base || base_name(runs[a].file) == base_name(runs[b].file);
      same_rate = same_rate && runs[a].rate_hz == runs[b].rate_hz;
    }
  std::vector<std::string> v;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    std::string l = std::to_string(k + 1) + ": " + (same_base ? runs[k].file : base_name(runs[k].file));
    if (!same_rate) l += " (" + format_num(runs[k].rate_hz, 4) + " Hz)";
    v.push_back(std::move(l));
  }
  return v;
}

std::string ci_text(double ci) { return printf_text("%.4g %%", 100.0 * ci); }

std::string term_text(const TermEstimate& t, Term which, const Unit& u) {
  if (!t.valid) return "—";
  const Quantity q = display(t, which, u);
  return format_pm(q.value, q.sigma) + " " + q.unit;
}

// Channels matched across runs by name and unit, in first-seen order; for each,
// the index of the channel in every run (npos: the run lacks it).
struct ChannelKey {
  std::string name;
  Unit unit;
  std::vector<std::size_t> index;  // per run
};

std::vector<ChannelKey> channel_keys(const std::vector<pipeline::RunSummary>& runs) {
  std::vector<ChannelKey> keys;
  for (std::size_t r = 0; r < runs.size(); ++r)
    for (std::size_t c = 0; c < runs[r].channels.size(); ++c) {
      const auto& ch = runs[r].channels[c];
      auto it = std::find_if(keys.begin(), keys.end(),
                             [&](const ChannelKey& k) { return k.name == ch.name && k.unit.name == ch.unit.name; });
      if (it == keys.end()) {
        keys.push_back({ch.name, ch.unit, std::vector<std::size_t>(runs.size(), std::string::npos)});
        it = keys.end() - 1;
      }
      if (it->index[r] == std::string::npos) it->index[r] = c;
    }
  return keys;
}

std::vector<ReportField> runs_input(const std::vector<pipeline::RunSummary>& runs, double ci, const std::string& taus) {
  std::vector<ReportField> in;
  in.push_back({"runs", std::to_string(runs.size()), false});
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& r = runs[k];
    const double dur = r.rate_hz > 0 ? static_cast<double>(r.samples) / r.rate_hz : 0.0;
    in.push_back({"run " + std::to_string(k + 1),
                  r.file + "  (" + std::to_string(r.samples) + " samples at " + format_num(r.rate_hz, 6) + " Hz, " +
                      duration_text(dur) + ")",
                  true});
  }
  std::string chans;
  for (const auto& k : channel_keys(runs)) chans += (chans.empty() ? "" : ", ") + k.name + " [" + k.unit.name + "]";
  in.push_back({"channels", chans, false});
  if (!taus.empty()) in.push_back({"tau grid", taus, true});
  in.push_back({"confidence of the intervals", ci_text(ci), false});
  return in;
}

// Rows (run, channel): bias, N, B, T.
ReportTable runs_table(const std::vector<pipeline::RunSummary>& runs) {
  ReportTable t;
  t.title = "Every run";
  t.header = {"run",         "file",           "rate [Hz]",           "samples", "channel",
              "bias (mean)", "N, white noise", "B, bias instability", "T [s]"};
  t.numeric = {false, false, true, true, false, true, true, true, true};
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (const auto& c : runs[k].channels) {
      const auto& ro = c.readoffs;
      t.rows.push_back({std::to_string(k + 1), base_name(runs[k].file), format_num(runs[k].rate_hz, 6),
                        std::to_string(runs[k].samples), c.name, format_num(c.mean, 6) + " " + c.unit.name,
                        term_text(ro.N, Term::N, c.unit), term_text(ro.B, Term::B, c.unit),
                        ro.B.valid ? format_num(ro.tau_min, 3) : std::string("—")});
    }
  t.note =
      "Bias: the mean of the run. N read at τ = 1 s on the white-noise arm, B = σ_min / 0.664, T the τ of the "
      "minimum (IEEE 952 slope read-offs, 1σ from the confidence intervals); — where the curve has no such "
      "region.";
  return t;
}

std::string runs_lead_note(const std::vector<pipeline::RunSummary>& runs) {
  double lo = INFINITY, hi = 0;
  for (const auto& r : runs) {
    lo = std::min(lo, r.rate_hz);
    hi = std::max(hi, r.rate_hz);
  }
  return lo < hi ? " The runs differ in sampling rate (" + html_escape(format_num(lo, 4)) + " to " +
                       html_escape(format_num(hi, 4)) +
                       " Hz): white noise in °/√h or unit·√h compares across them, the per-sample deviation does not."
                 : std::string();
}

}  // namespace

std::vector<ReportFigure> allan_overlay_figures(const std::vector<pipeline::RunSummary>& runs, double ci) {
  const auto labels = run_labels(runs);
  std::vector<ReportFigure> figs;
  std::vector<std::string> taken;
  for (const auto& key : channel_keys(runs)) {
    ReportFigure f;
    Plot& p = f.plot;
    p.name = unique_name("runs_allan_", key.name, taken);
    p.title = "Allan deviation of the runs, " + key.name + " [" + key.unit.name + "]";
    p.x = {"averaging time τ [s]", true, std::nullopt, std::nullopt};
    p.y = {"Allan deviation σ(τ) [" + key.unit.name + "]", true, std::nullopt, std::nullopt};
    p.key = "outside bottom center horizontal Left reverse maxrows 4";
    p.height = 640;
    std::size_t shown = 0;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (key.index[r] == std::string::npos) continue;
      const auto& ch = runs[r].channels[key.index[r]];
      PlotSeries s;
      for (const auto& pt : ch.adev) {
        s.x.push_back(pt.tau);
        s.y.push_back(pt.dev);
        s.lo.push_back(pt.interval.lo);
        s.hi.push_back(pt.interval.hi);
      }
      if (s.x.empty()) continue;
      s.mark = Mark::errorlines;
      s.label = labels[r];
      s.id = labels[r] + ", " + ch.name + " OADEV";
      s.color = run_color(r);
      // Past ten runs the colours repeat: dashes tell them apart.
      s.dash = r >= 10 ? Dash::dashed : Dash::solid;
      s.width = 1.3;
      s.point_size = 0.25;
      p.series.push_back(std::move(s));
      ++shown;
    }
    if (shown == 0) {  // no run has a curve for it (records too short): no plot
      taken.pop_back();
      continue;
    }
    p.notes.push_back("overlapping Allan deviation of channel " + key.name + " in every run, with its " + ci_text(ci) +
                      " confidence interval; one block per run");
    f.caption_html = "Overlapping Allan deviation of <code>" + html_escape(key.name) + "</code> in each of the " +
                     std::to_string(shown) + " runs (a colour per run; bars: " + html_escape(ci_text(ci)) +
                     " confidence intervals). Curves that agree within their bars show the same noise; a run whose "
                     "long-τ end lies above the others drifted more.";
    figs.push_back(std::move(f));
  }
  return figs;
}

std::vector<ReportFigure> turnon_bias_figures(const pipeline::TurnOnResult& t) {
  std::vector<ReportFigure> figs;
  std::vector<std::string> taken;
  const std::size_t k = t.runs.size();
  const double x0 = 0.5, x1 = static_cast<double>(k) + 0.5;
  for (std::size_t c = 0; c < t.names.size(); ++c) {
    const std::string& unit = t.units[c].name;
    const double mean = t.mean_bias[c], sd = t.turn_on[c];
    ReportFigure f;
    Plot& p = f.plot;
    p.name = unique_name("turnon_bias_", t.names[c], taken);
    p.title = "Turn-on bias, " + t.names[c] + ": " + std::to_string(k) + " runs";
    p.x = {"run", false, x0, x1};
    if (k <= 20) p.x_tics = 1.0;
    p.y = {"bias, the run's mean [" + unit + "]", false, std::nullopt, std::nullopt};
    p.key = "outside bottom center horizontal Left reverse maxrows 3";
    p.width = 520;
    p.height = 480;

    PlotSeries band;
    band.mark = Mark::band;
    band.x = {x0, x1};
    band.y = {mean, mean};
    band.lo = {mean - sd, mean - sd};
    band.hi = {mean + sd, mean + sd};
    band.color = kInkColor;
    band.opacity = 0.15;
    band.label = "mean ± turn-on σ (" + format_num(sd, 4) + " " + unit + ")";
    band.id = "mean +- turn-on standard deviation";
    p.series.push_back(std::move(band));

    PlotSeries m = hline(mean, x0, x1, kInkColor, Dash::dashed, "mean over the runs");
    m.label = "mean over the runs (" + format_num(mean, 6) + " " + unit + ")";
    m.width = 1.4;
    p.series.push_back(std::move(m));

    // Each run's point in its colour of the Allan plots.
    for (std::size_t r = 0; r < k; ++r) {
      PlotSeries pt;
      pt.mark = Mark::points;
      pt.x = {static_cast<double>(r + 1)};
      pt.y = {t.runs[r].channels[c].mean};
      pt.color = run_color(r);
      pt.point_size = 1.2;
      pt.id = "run " + std::to_string(r + 1) + " bias";
      p.series.push_back(std::move(pt));
    }
    p.series.push_back(legend_only("bias of each run (its colour in the Allan plots)", kInkColor, Mark::points));
    p.series.back().point_size = 1.2;

    p.notes.push_back("x: run number (the order of the files on the command line), y: the run's mean");
    p.notes.push_back("band: mean over the runs ± their sample standard deviation (the turn-on bias)");
    f.caption_html = "Bias of <code>" + html_escape(t.names[c]) + "</code> in each run (its mean), the mean over the " +
                     std::to_string(k) +
                     " runs (dashed) and ± the turn-on bias σ = " + html_escape(format_num(sd, 4) + " " + unit) +
                     " (band; " + html_escape(ci_text(t.ci)) + " interval of σ: " +
                     html_escape(format_num(t.turn_on_interval[c].lo, 3) + " – " +
                                 format_num(t.turn_on_interval[c].hi, 3) + " " + unit) +
                     ", " + std::to_string(k - 1) + " degrees of freedom).";
    figs.push_back(std::move(f));
  }
  return figs;
}

CommandReport turnon_report(const pipeline::TurnOnResult& t, const RunsReportContext& ctx) {
  CommandReport r;
  r.title = "Turn-on bias: " + std::to_string(t.runs.size()) + " runs";
  r.lead_html =
      "Run-to-run bias by <code>cubecal turnon</code>: each power-cycled run's bias (its mean), the mean "
      "over the runs and the standard deviation of the run biases — the turn-on bias — with its "
      "chi-squared interval; each run's noise terms, and the Allan curves of the runs overlaid per "
      "channel (the paper's five 3 h runs)." +
      runs_lead_note(t.runs);
  r.input = runs_input(t.runs, t.ci, ctx.taus);
  r.command = ctx.command;
  r.plot_prefixes = {"runs_allan_", "turnon_bias_"};

  ReportTable sum;
  sum.title = "Turn-on bias per channel";
  sum.header = {"channel", "unit", "mean bias", "turn-on bias σ", "interval of σ (" + ci_text(t.ci) + ")", "runs"};
  sum.numeric = {false, false, true, true, true, true};
  for (std::size_t c = 0; c < t.names.size(); ++c)
    sum.rows.push_back({t.names[c], t.units[c].name, format_num(t.mean_bias[c], 6), format_num(t.turn_on[c], 4),
                        format_num(t.turn_on_interval[c].lo, 4) + " – " + format_num(t.turn_on_interval[c].hi, 4),
                        std::to_string(t.runs.size())});
  sum.note = "σ: sample standard deviation of the run biases (n − 1); its interval from (n − 1) s² / σ² ~ χ²(n − 1).";

  ReportSection s1{"turnon", "Turn-on bias", {}};
  ReportBlock b1;
  b1.table = std::move(sum);
  b1.figures = turnon_bias_figures(t);
  s1.blocks.push_back(std::move(b1));
  r.sections.push_back(std::move(s1));

  ReportSection s2{"runs", "Runs", {}};
  ReportBlock b2;
  b2.table = runs_table(t.runs);
  s2.blocks.push_back(std::move(b2));
  r.sections.push_back(std::move(s2));

  ReportSection s3{"allan", "Allan deviation of the runs", {}};
  for (auto& f : allan_overlay_figures(t.runs, t.ci)) s3.blocks.push_back({{}, std::nullopt, {std::move(f)}});
  r.sections.push_back(std::move(s3));
  return r;
}

CommandReport compare_report(const std::vector<pipeline::RunSummary>& runs, const RunsReportContext& ctx) {
  CommandReport r;
  r.title = "Runs compared: " + std::to_string(runs.size()) + " records";
  r.lead_html =
      "Allan curves and N, B, T of several records side by side by <code>cubecal compare</code> (other "
      "sampling rates, lengths, units or sensors), overlaid per channel." +
      runs_lead_note(runs);
  r.input = runs_input(runs, ctx.ci, ctx.taus);
  r.command = ctx.command;
  r.plot_prefixes = {"runs_allan_"};

  ReportSection s1{"runs", "Runs", {}};
  ReportBlock b1;
  b1.table = runs_table(runs);
  s1.blocks.push_back(std::move(b1));
  r.sections.push_back(std::move(s1));

  ReportSection s2{"allan", "Allan deviation of the runs", {}};
  for (auto& f : allan_overlay_figures(runs, ctx.ci)) s2.blocks.push_back({{}, std::nullopt, {std::move(f)}});
  r.sections.push_back(std::move(s2));
  return r;
}

}  // namespace cubecal::report
