// Generic pieces of cubecal's HTML pages: escaping, numbers, figures with
// inline SVG (data: URIs), the page shell with its style sheet.
#include "cubecal/report/html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"

namespace cubecal::report {

std::string html_escape(std::string_view s) {
  std::string o;
  o.reserve(s.size() + s.size() / 8);
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&#39;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string format_num(std::optional<double> value, int digits) {
  if (!value || !std::isfinite(*value)) return "—";
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", std::clamp(digits, 1, 17), *value);
  return b;
}

std::string format_pm(std::optional<double> value, std::optional<double> sigma) {
  if (!value || !std::isfinite(*value)) return "—";
  if (!sigma || !std::isfinite(*sigma) || *sigma <= 0) return format_num(value, 5);
  const double v = *value, s = *sigma;
  // Exponent of the last digit kept: two significant digits of sigma.
  const int last = static_cast<int>(std::floor(std::log10(s))) - 1;
  const double mag = std::max(std::abs(v), s);
  char b[96];
  if (mag >= 1e-3 && mag < 1e7) {
    const int dec = std::max(0, -last);
    std::snprintf(b, sizeof b, "%.*f ± %.*f", dec, v, dec, s);
  } else {
    const int e = static_cast<int>(std::floor(std::log10(mag)));
    const double scale = std::pow(10.0, e);
    const int dec = std::clamp(e - last, 0, 15);
    std::snprintf(b, sizeof b, "(%.*f ± %.*f)e%+03d", dec, v / scale, dec, s / scale, e);
  }
  return b;
}

std::string base64(std::string_view in) {
  static constexpr char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  o.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    o += t[(v >> 18) & 63];
    o += t[(v >> 12) & 63];
    o += t[(v >> 6) & 63];
    o += t[v & 63];
  }
  if (i < in.size()) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    o += t[(v >> 18) & 63];
    o += t[(v >> 12) & 63];
    o += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

std::string html_figure(const RenderedPlot& plot, std::string_view caption_html, std::string_view files_prefix) {
  const std::string n = html_escape(plot.name);
  const std::string pre = html_escape(files_prefix);
  std::string s = "<figure id=\"fig-" + n + "\">\n";
  s += "<img class=\"plot\" width=\"" + std::to_string(plot.width) + "\" height=\"" + std::to_string(plot.height) +
       "\" alt=\"" + html_escape(plot.title.empty() ? plot.name : plot.title) + "\" src=\"data:image/svg+xml;base64," +
       base64(plot.svg_text) + "\">\n";
  s += "<figcaption>";
  s += caption_html;
  s += " <span class=\"files\">Files: ";
  const char* ext[] = {".svg", ".png", ".gp", ".dat"};
  for (std::size_t k = 0; k < 4; ++k) {
    if (k) s += " · ";
    s += "<a href=\"" + pre + n + ext[k] + "\">" + pre + n + ext[k] + "</a>";
  }
  s += "</span></figcaption>\n</figure>\n";
  return s;
}

namespace {

constexpr const char* kStyle = R"css(
:root { color-scheme: light; }
* { box-sizing: border-box; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, "Noto Sans",
       "Liberation Sans", sans-serif; font-size: 16px; line-height: 1.5; color: #1b1b1b; background: #fff;
       max-width: 64rem; margin: 0 auto; padding: 1.5rem 1.25rem 3rem; }
h1 { font-size: 1.75rem; line-height: 1.2; margin: 0 0 .3rem; }
h2 { font-size: 1.35rem; margin: 2.4rem 0 .6rem; padding-bottom: .2rem; border-bottom: 1px solid #d8d8d8; }
h3 { font-size: 1.08rem; margin: 1.6rem 0 .4rem; }
p { margin: .5rem 0; max-width: 48rem; }
.lead { color: #444; margin-bottom: 1rem; }
a { color: #0b5cad; }
code, pre, kbd { font-family: ui-monospace, SFMono-Regular, Menlo, Consolas, "DejaVu Sans Mono", "Liberation Mono",
                 monospace; font-size: .88em; }
pre { background: #f6f7f8; border: 1px solid #e1e3e5; border-radius: 4px; padding: .6rem .8rem;
      white-space: pre-wrap; overflow-wrap: anywhere; }
.scroll { overflow-x: auto; }
table { border-collapse: collapse; margin: .4rem 0 1.2rem; font-size: .86rem; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid #d5d7da; padding: .22rem .5rem; vertical-align: top; }
thead th { background: #eef0f2; text-align: left; }
tbody th { text-align: left; font-weight: normal; }
td.num { text-align: right; white-space: nowrap; }
td.unit { color: #555; white-space: nowrap; }
tr.sub th { background: #f7f8f9; font-weight: 600; font-size: .82rem; color: #333; }
table.kv th { width: 14rem; background: #f7f8f9; }
.muted, .files { color: #666; }
.files { font-size: .78rem; display: block; margin-top: .2rem; }
.reasons { font-size: .84rem; color: #444; margin-top: -.6rem; }
.note { background: #fff8e1; border-left: 4px solid #e5a800; padding: .5rem .8rem; margin: 1rem 0; }
figure { margin: 1.2rem 0 1.6rem; }
figure img.plot { display: block; width: 100%; height: auto; border: 1px solid #e3e3e3; }
figcaption { font-size: .88rem; color: #333; margin-top: .35rem; max-width: 52rem; }
.figrow { display: grid; grid-template-columns: repeat(auto-fit, minmax(18rem, 1fr)); gap: 0 1rem; }
.figrow figure { margin: .6rem 0 1rem; }
nav.toc { font-size: .92rem; border: 1px solid #e1e3e5; border-radius: 4px; padding: .5rem 1rem; margin: 1rem 0; }
nav.toc ol { margin: .2rem 0; padding-left: 1.4rem; columns: 2; }
footer { margin-top: 3rem; font-size: .8rem; color: #666; border-top: 1px solid #e1e3e5; padding-top: .6rem; }
@page { size: A4; margin: 14mm 12mm; }
@media print {
  body { max-width: none; padding: 0; font-size: 10pt; }
  nav.toc, .files { display: none; }
  h2, h3 { break-after: avoid; page-break-after: avoid; }
  figure, table, pre { break-inside: avoid; page-break-inside: avoid; }
  figure img.plot { border: none; }
  a { color: inherit; text-decoration: none; }
  .scroll { overflow: visible; }
}
)css";

// Marks <body> once every image is decoded: data-images="ok" or "missing: ...".
constexpr const char* kScript = R"js(
window.addEventListener('load', function () {
  var bad = [], imgs = document.images;
  for (var i = 0; i < imgs.length; i++)
    if (!(imgs[i].complete && imgs[i].naturalWidth > 0)) bad.push(imgs[i].alt || ('image ' + i));
  document.body.setAttribute('data-image-count', String(imgs.length));
  document.body.setAttribute('data-images', bad.length ? 'missing: ' + bad.join('; ') : 'ok');
});
)js";

}  // namespace

std::string html_document(std::string_view title, std::string_view body_html) {
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  s += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  s += "<meta name=\"generator\" content=\"cubecal\">\n";
  s += "<title>" + html_escape(title) + "</title>\n";
  s += "<style>";
  s += kStyle;
  s += "</style>\n<script>";
  s += kScript;
  s += "</script>\n</head>\n<body>\n";
  s += body_html;
  s += "</body>\n</html>\n";
  return s;
}

void write_page(const std::filesystem::path& html, const std::string& page) {
  io::AtomicFile f(html.string());
  if (!f.is_open() || !f.write(page) || !f.commit())
    throw UsageError("cannot write " + html.string() + " (check the directory is writable)");
}

}  // namespace cubecal::report
