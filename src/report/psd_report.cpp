// The page of `cubecal psd`: per channel the one-sided power spectral
// density on log-log axes with the power-law terms fitted to it
// (spectrum_figure.hpp, drawn also on the analysis page), and a table
// of the coefficients and the Allan terms they stand for, so the spectrum can
// be read beside `analyze`'s Allan curve (docs/formulas/spectral.md).
#include <algorithm>
#include <string>

#include "command_util.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"
#include "cubecal/spectral/window.hpp"
#include "spectrum_figure.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

std::string unit_of(const pipeline::PsdChannel& ch) { return ch.unit.name.empty() ? std::string("u") : ch.unit.name; }

ReportFigure spectrum_figure(const pipeline::PsdChannel& ch, std::vector<std::string>& taken) {
  return detail::spectrum_figure(unique_name("psd_", ch.name, taken), ch.name, ch.unit, ch.spectrum, ch.fit,
                                 ch.fit_error);
}

ReportTable terms_table(const pipeline::PsdChannel& ch) {
  ReportTable t;
  t.title = ch.name;
  const std::string u = unit_of(ch);
  t.header = {"term", "h", "σ(h)", "Allan term", "value", "σ"};
  for (const auto& term : ch.fit.terms) {
    std::vector<std::string> row{power_law_term_name(term.alpha),
                                 term.valid ? format_num(term.h, 5) : std::string("0 (bound)"),
                                 term.valid ? format_num(term.sigma, 3) : std::string("—")};
    const pipeline::PsdAllanTerm* a = nullptr;
    for (const auto& x : ch.allan_terms)
      if (x.alpha == term.alpha) a = &x;
    if (a != nullptr && a->estimate.valid) {
      const char* names[] = {"Q", "N", "B", "K", "R"};
      row.push_back(names[static_cast<int>(a->term)]);
      row.push_back(format_num(a->display.value, 5) + " " + a->display.unit);
      row.push_back(format_num(a->display.sigma, 3));
    } else {
      row.insert(row.end(), {"—", "—", "—"});
    }
    t.rows.push_back(std::move(row));
  }
  t.note = "h: the coefficient of h f^α in " + u + "²/Hz·Hz^-α, from the fit over " + format_num(ch.fit.f_lo, 3) + "–" +
           format_num(ch.fit.f_hi, 3) +
           " Hz (uncertainties widened by χ²/dof when above 1); the Allan term "
           "it stands for in the unit people quote (docs/formulas/spectral.md).";
  return t;
}

}  // namespace

std::vector<ReportFigure> psd_figures(const pipeline::PsdResult& r) {
  std::vector<ReportFigure> figs;
  std::vector<std::string> taken;
  for (const auto& ch : r.channels)
    if (ch.spectrum.size() > 0) figs.push_back(spectrum_figure(ch, taken));
  return figs;
}

CommandReport psd_report(const pipeline::PsdResult& r, const std::string& command) {
  CommandReport rep;
  rep.title = "Power spectral density: " + base_name(r.file);
  rep.lead_html =
      "The one-sided power spectral density of each channel by Welch's method, by <code>cubecal "
      "psd</code>, with the power-law terms fitted to it and the Allan terms they stand for, to read "
      "beside the Allan deviation of <code>cubecal analyze</code>. Definitions: "
      "<code>docs/formulas/spectral.md</code>.";
  rep.command = command;
  rep.plot_prefixes = {"psd_"};
  std::string chans;
  for (const auto& c : r.channels) chans += (chans.empty() ? "" : ", ") + c.name;
  rep.input = {{"file", r.file, true},
               {"channels", chans, true},
               {"samples",
                std::to_string(r.samples) + " at " + format_num(r.rate_hz, 6) + " Hz (" +
                    duration_text(static_cast<double>(r.samples) / r.rate_hz) + ")",
                false}};
  if (!r.channels.empty()) {
    const Psd& s = r.channels.front().spectrum;
    rep.input.push_back({"segments",
                         std::to_string(s.segments) + " of " + std::to_string(s.segment_length) + " samples (" +
                             format_num(s.resolution_hz(), 4) + " Hz resolution), " + std::string(to_string(s.window)) +
                             " window, " + format_num(100.0 * r.overlap, 3) + " % overlap, " +
                             std::string(to_string(s.detrend)) + " detrend",
                         false});
  }
  const auto figs = psd_figures(r);
  std::size_t f = 0;
  for (const auto& ch : r.channels) {
    std::string id = "channel-" + slug(ch.name);
    std::replace(id.begin(), id.end(), '_', '-');
    ReportSection s{id, ch.name, {}};
    if (ch.spectrum.size() > 0 && f < figs.size()) s.blocks.push_back({{}, std::nullopt, {figs[f++]}});
    if (!ch.fit.terms.empty()) {
      ReportBlock table;
      table.table = terms_table(ch);
      s.blocks.push_back(std::move(table));
    } else if (!ch.fit_error.empty()) {
      s.blocks.push_back({"<p>Not fitted: " + html_escape(ch.fit_error) + "</p>", std::nullopt, {}});
    }
    rep.sections.push_back(std::move(s));
  }
  return rep;
}

}  // namespace cubecal::report
