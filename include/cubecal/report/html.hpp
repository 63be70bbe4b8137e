/// @file
/// Building blocks of cubecal's self-contained HTML pages: escaping, number
/// formatting, figures holding a rendered plot as a data: URI, and the page
/// shell (inline CSS, system fonts, print styles, no network references).
#pragma once
#include <optional>
#include <filesystem>
#include <string>
#include <string_view>

#include "cubecal/report/plot.hpp"

namespace cubecal::report {

/// & < > " ' as character references: safe in text and in quoted attributes.
std::string html_escape(std::string_view s);

/// "0.2664 ± 0.0012": the uncertainty to two significant digits and the
/// value to the same decimal place; "1.23e-07 ± 4.5e-09" for very small or
/// large numbers; the value alone (5 significant digits) without a usable
/// sigma; "—" without a value.
std::string format_pm(std::optional<double> value, std::optional<double> sigma);
/// A number to `digits` significant digits ("—" for none / not finite).
std::string format_num(std::optional<double> value, int digits = 5);

/// The bytes in base64 (RFC 4648, with padding). Throws nothing beyond std::bad_alloc.
std::string base64(std::string_view bytes);

/// `<figure>` with the plot's SVG inline as a data: URI (an `<img>`, so ids of
/// different plots never collide), the caption (HTML, already escaped) and
/// the names of the plot's files.
std::string html_figure(const RenderedPlot& plot, std::string_view caption_html,
                        std::string_view files_prefix = "plots/");

/// A complete page: `<head>` with the inline style sheet and a script that marks
/// `<body data-images="ok">` once every image decoded (or "missing: NAMES"),
/// then `body_html`.
std::string html_document(std::string_view title, std::string_view body_html);

/// Writes a finished page to `html` through an io::AtomicFile (NAME.partial
/// and a rename), so a reader never sees half a page. Throws UsageError when it cannot.
void write_page(const std::filesystem::path& html, const std::string& page);

}  // namespace cubecal::report
