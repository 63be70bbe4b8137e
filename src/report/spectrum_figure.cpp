// The figure of a power spectral density with its fitted power-law terms
// (spectrum_figure.hpp), shared by the `psd` page and the analysis page.
#include "spectrum_figure.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cubecal/report/html.hpp"
#include "cubecal/spectral/log_bins.hpp"
#include "cubecal/spectral/window.hpp"

namespace cubecal::report::detail {

namespace {

// Bands per decade drawn when the spectrum holds the raw bins.
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

}  // namespace

std::string power_law_term_name(int alpha) {
  switch (alpha) {
    case 2: return "f^2 (quantization Q)";
    case 1: return "f^1";
    case 0: return "f^0 (white noise N)";
    case -1: return "f^-1 (bias instability B)";
    case -2: return "f^-2 (rate random walk K)";
    default: return "f^" + std::to_string(alpha);
  }
}

ReportFigure spectrum_figure(const std::string& plot_name, const std::string& channel, const Unit& unit,
                             const Psd& spectrum, const PowerLawFit& fit, const std::string& fit_error) {
  ReportFigure f;
  Plot& p = f.plot;
  p.name = plot_name;
  p.title = "Power spectral density, " + channel;
  p.width = 900;
  p.height = 560;
  p.key = "outside right top";
  const Psd drawn = spectrum.bins_per_decade > 0 ? spectrum : log_bin(spectrum, kDrawnBinsPerDecade);
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
  if (!fit.terms.empty() && fit.f_lo > 0.0 && fit.f_hi > fit.f_lo) {
    const double decades = std::log10(fit.f_hi / fit.f_lo);
    const int n = std::max(2, static_cast<int>(std::ceil(decades * kLinePointsPerDecade)) + 1);
    const auto at = [&](int i) { return fit.f_lo * std::pow(10.0, decades * i / (n - 1)); };
    for (const auto& t : fit.terms) {
      if (!t.valid || !(t.h > 0.0)) continue;
      PlotSeries line;
      line.label = power_law_term_name(t.alpha);
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
  const std::string u = unit.name.empty() ? std::string("u") : unit.name;
  p.x = {"frequency [Hz]", true, std::nullopt, std::nullopt};
  p.y = {"one-sided PSD [" + u + "²/Hz]", true, std::nullopt, std::nullopt};
  p.notes.push_back("one-sided Welch PSD of channel " + channel +
                    ", the fitted power-law terms h f^alpha over the "
                    "fitted band and their sum");
  f.caption_html =
      "One-sided power spectral density of <code>" + html_escape(channel) + "</code> (" +
      std::string(to_string(spectrum.window)) + " window, " + std::to_string(spectrum.segments) + " segments of " +
      std::to_string(spectrum.segment_length) + " samples" +
      (spectrum.bins_per_decade > 0 || drawn.bins_per_decade == 0
           ? std::string()
           : ", drawn averaged over " + std::to_string(kDrawnBinsPerDecade) + " bands per decade") +
      ")." +
      (fit.terms.empty()
           ? (fit_error.empty() ? std::string(" No fit asked for.") : " Not fitted: " + html_escape(fit_error) + ".")
           : " Dashed: each fitted term over the band " + html_escape(format_num(fit.f_lo, 3)) + "–" +
                 html_escape(format_num(fit.f_hi, 3)) + " Hz; black: their sum.");
  return f;
}

}  // namespace cubecal::report::detail
