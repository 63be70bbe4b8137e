// The page of `cubecal psd`: per channel the one-sided power spectral
// density on log-log axes with the power-law terms fitted to it, and a table
// of the coefficients and the Allan terms they stand for, so the spectrum can
// be read beside `analyze`'s Allan curve (docs/formulas/spectral.md).
#include <cmath>
#include <string>

#include "command_util.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"
#include "cubecal/spectral/log_bins.hpp"
#include "cubecal/spectral/window.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

// Bands per decade drawn when the result holds the raw bins.
constexpr std::size_t kDrawnBinsPerDecade = 20;
// Points per decade of each fitted term's line.
constexpr int kLinePointsPerDecade = 10;

const char* term_color(int alpha) {
  switch (alpha) {
    case 2: return "#9467bd";   // white PM / quantization
    case 0: return "#2ca02c";   // white: N
    case -1: return "#ff7f0e";  // flicker: B
    case -2: return "#d62728";  // random walk: K
    default: return "#8c564b";
  }
}

std::string term_name(int alpha) {
  switch (alpha) {
    case 2: return "f^2 (quantization Q)";
    case 1: return "f^1";
    case 0: return "f^0 (white noise N)";
    case -1: return "f^-1 (bias instability B)";
    case -2: return "f^-2 (rate random walk K)";
    default: return "f^" + std::to_string(alpha);
  }
}

std::string unit_of(const pipeline::PsdChannel& ch) {
  return ch.unit.name.empty() ? std::string("u") : ch.unit.name;
}

ReportFigure spectrum_figure(const pipeline::PsdChannel& ch, std::vector<std::string>& taken) {
  ReportFigure f;
  Plot& p = f.plot;
  p.name = unique_name("psd_", ch.name, taken);
  p.title = "Power spectral density, " + ch.name;
  p.width = 900;
  p.height = 560;
  p.key = "outside right top";
  const Psd drawn = ch.spectrum.bins_per_decade > 0 ? ch.spectrum : log_bin(ch.spectrum, kDrawnBinsPerDecade);
  PlotSeries s;
  s.mark = Mark::points;
  s.point_size = 0.6;
  s.color = "#1f77b4";
  s.label = "measured";
  for (std::size_t k = 0; k < drawn.size(); ++k) {
    if (!(drawn.frequency[k] > 0.0) || !(drawn.density[k] > 0.0)) continue;  // DC and zero bands off a log axis
    s.x.push_back(drawn.frequency[k]);
    s.y.push_back(drawn.density[k]);
  }
  p.series.push_back(std::move(s));
  const PowerLawFit& fit = ch.fit;
  if (!fit.terms.empty() && fit.f_lo > 0.0 && fit.f_hi > fit.f_lo) {
    const double decades = std::log10(fit.f_hi / fit.f_lo);
    const int n = std::max(2, static_cast<int>(std::ceil(decades * kLinePointsPerDecade)) + 1);
    const auto at = [&](int i) { return fit.f_lo * std::pow(10.0, decades * i / (n - 1)); };
    for (const auto& t : fit.terms) {
      if (!t.valid || !(t.h > 0.0)) continue;
      PlotSeries line;
      line.label = term_name(t.alpha);
      line.color = term_color(t.alpha);
      line.dash = Dash::dashed;
      line.scale = false;  // a steep term must not stretch the axis beyond the data
      for (int i = 0; i < n; ++i) {
        line.x.push_back(at(i));
        line.y.push_back(t.h * std::pow(at(i), t.alpha));
      }
      p.series.push_back(std::move(line));
    }
    PlotSeries total;
    total.label = "fitted sum";
    total.color = "#000000";
    total.width = 2.0;
    for (int i = 0; i < n; ++i) {
      total.x.push_back(at(i));
      total.y.push_back(fit.density(at(i)));
    }
    p.series.push_back(std::move(total));
  }
  const std::string u = unit_of(ch);
  p.x = {"frequency [Hz]", true, std::nullopt, std::nullopt};
  p.y = {"one-sided PSD [" + u + "²/Hz]", true, std::nullopt, std::nullopt};
  p.notes.push_back("one-sided Welch PSD of channel " + ch.name + ", the fitted power-law terms h f^alpha over the "
                    "fitted band and their sum");
  f.caption_html = "One-sided power spectral density of <code>" + html_escape(ch.name) + "</code> (" +
                   std::string(to_string(ch.spectrum.window)) + " window, " +
                   std::to_string(ch.spectrum.segments) + " segments of " +
                   std::to_string(ch.spectrum.segment_length) + " samples" +
                   (ch.spectrum.bins_per_decade > 0 || drawn.bins_per_decade == 0
                        ? std::string()
                        : ", drawn averaged over " + std::to_string(kDrawnBinsPerDecade) + " bands per decade") +
                   ")." +
                   (fit.terms.empty() ? (ch.fit_error.empty() ? std::string(" No fit asked for.")
                                                               : " Not fitted: " + html_escape(ch.fit_error) + ".")
                                      : " Dashed: each fitted term over the band " +
                                            html_escape(format_num(fit.f_lo, 3)) + "–" +
                                            html_escape(format_num(fit.f_hi, 3)) + " Hz; black: their sum.");
  return f;
}

ReportTable terms_table(const pipeline::PsdChannel& ch) {
  ReportTable t;
  t.title = ch.name;
  const std::string u = unit_of(ch);
  t.header = {"term", "h", "σ(h)", "Allan term", "value", "σ"};
  for (const auto& term : ch.fit.terms) {
    std::vector<std::string> row{term_name(term.alpha), term.valid ? format_num(term.h, 5) : std::string("0 (bound)"),
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
  t.note = "h: the coefficient of h f^α in " + u + "²/Hz·Hz^-α, from the fit over " + format_num(ch.fit.f_lo, 3) +
           "–" + format_num(ch.fit.f_hi, 3) + " Hz (uncertainties widened by χ²/dof when above 1); the Allan term "
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
  rep.lead_html = "The one-sided power spectral density of each channel by Welch's method, by <code>cubecal "
                  "psd</code>, with the power-law terms fitted to it and the Allan terms they stand for, to read "
                  "beside the Allan deviation of <code>cubecal analyze</code>. Definitions: "
                  "<code>docs/formulas/spectral.md</code>.";
  rep.command = command;
  rep.plot_prefixes = {"psd_"};
  std::string chans;
  for (const auto& c : r.channels) chans += (chans.empty() ? "" : ", ") + c.name;
  rep.input = {{"file", r.file, true},
               {"channels", chans, true},
               {"samples", std::to_string(r.samples) + " at " + format_num(r.rate_hz, 6) + " Hz (" +
                               duration_text(static_cast<double>(r.samples) / r.rate_hz) + ")",
                false}};
  if (!r.channels.empty()) {
    const Psd& s = r.channels.front().spectrum;
    rep.input.push_back({"segments", std::to_string(s.segments) + " of " + std::to_string(s.segment_length) +
                                         " samples (" + format_num(s.resolution_hz(), 4) + " Hz resolution), " +
                                         std::string(to_string(s.window)) + " window, " +
                                         format_num(100.0 * r.overlap, 3) + " % overlap, " +
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
