// The page of a command report (input, the command, sections of text, tables
// and figures) in the shell of html.hpp, and its writing: plots rendered,
// stale plots of the same kind removed, report.html replaced atomically.
#include "cubecal/report/command_report.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "cubecal/error.hpp"
#include "cubecal/io/output_path.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

namespace fs = std::filesystem;

namespace {

std::string anchor(const std::string& id) {
  std::string a;
  for (char c : id)
    a += ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_') ? c : '-';
  return a.empty() ? std::string("section") : a;
}

std::string table_html(const ReportTable& t) {
  std::string s;
  if (!t.title.empty()) s += "<h3>" + html_escape(t.title) + "</h3>\n";
  auto numeric = [&](std::size_t col) { return col < t.numeric.size() ? t.numeric[col] : col > 0; };
  s += "<div class=\"scroll\"><table>\n";
  if (!t.header.empty()) {
    s += "<thead><tr>";
    for (const auto& h : t.header) s += "<th>" + html_escape(h) + "</th>";
    s += "</tr></thead>\n";
  }
  s += "<tbody>\n";
  for (const auto& row : t.rows) {
    s += "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c == 0)
        s += "<th>" + html_escape(row[c]) + "</th>";
      else
        s += std::string(numeric(c) ? "<td class=\"num\">" : "<td>") + html_escape(row[c]) + "</td>";
    }
    s += "</tr>\n";
  }
  s += "</tbody></table></div>\n";
  if (!t.note.empty()) s += "<p class=\"reasons\">" + html_escape(t.note) + "</p>\n";
  return s;
}

// Plot files of an earlier report of this kind that this one did not write.
void remove_stale_plots(const fs::path& dir, const std::vector<std::string>& prefixes,
                        const std::vector<std::string>& current) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const fs::path& p = e.path();
    const std::string stem = p.stem().string(), ext = p.extension().string();
    const bool ours = ext == ".dat" || ext == ".gp" || ext == ".svg" || ext == ".png" || ext == ".log";
    const bool named = std::any_of(prefixes.begin(), prefixes.end(),
                                   [&](const std::string& pre) { return !pre.empty() && stem.rfind(pre, 0) == 0; });
    const bool regular = fs::is_regular_file(e.symlink_status(ec));  // nothing else is ever removed
    if (ours && named && regular && std::find(current.begin(), current.end(), stem) == current.end())
      stale.push_back(p);
  }
  for (const auto& p : stale) fs::remove(p, ec);
}

}  // namespace

std::vector<Plot> report_plots(const CommandReport& report) {
  std::vector<Plot> plots;
  for (const auto& sec : report.sections)
    for (const auto& b : sec.blocks)
      for (const auto& f : b.figures) plots.push_back(f.plot);
  return plots;
}

std::string command_report_html(const CommandReport& r, const std::vector<RenderedPlot>& rendered,
                                std::string_view note) {
  int figno = 0;
  auto figure = [&](const ReportFigure& f) {
    const std::string cap = "<b>Figure " + std::to_string(++figno) + ".</b> " + f.caption_html;
    const auto it =
        std::find_if(rendered.begin(), rendered.end(), [&](const RenderedPlot& p) { return p.name == f.plot.name; });
    if (it != rendered.end()) return html_figure(*it, cap);
    return "<figure id=\"fig-" + html_escape(f.plot.name) + "\"><p class=\"muted\">[plot " + html_escape(f.plot.name) +
           " not rendered]</p><figcaption>" + cap + "</figcaption></figure>\n";
  };

  std::string b;
  b += "<header>\n<h1>" + html_escape(r.title) + "</h1>\n";
  if (!r.lead_html.empty()) b += "<p class=\"lead\">" + r.lead_html + "</p>\n";
  b += "</header>\n";
  if (!note.empty()) b += "<p class=\"note\">" + html_escape(note) + "</p>\n";
  for (const auto& n : r.notes) b += "<p class=\"note\">" + html_escape(n) + "</p>\n";

  b += "<nav class=\"toc\"><b>Contents</b><ol>";
  b += "<li><a href=\"#input\">Input</a></li><li><a href=\"#reproduce\">Reproduce</a></li>";
  for (const auto& sec : r.sections)
    b += "<li><a href=\"#" + anchor(sec.id) + "\">" + html_escape(sec.title) + "</a></li>";
  b += "<li><a href=\"#files\">Files</a></li></ol></nav>\n";

  b += "<section id=\"input\">\n<h2>Input</h2>\n<table class=\"kv\"><tbody>\n";
  for (const auto& f : r.input) {
    const std::string v = html_escape(f.value);
    b += "<tr><th>" + html_escape(f.label) + "</th><td>" + (f.code ? "<code>" + v + "</code>" : v) + "</td></tr>\n";
  }
  for (const auto& f : r.input_html)
    b += "<tr><th>" + html_escape(f.label) + "</th><td>" + f.value_html + "</td></tr>\n";
  b += "</tbody></table>\n</section>\n";

  b += "<section id=\"reproduce\">\n<h2>Reproduce</h2>\n";
  if (!r.reproduce_html.empty()) {
    b += r.reproduce_html;
  } else {
    if (!r.command.empty())
      b +=
          face_words("<p>The command that wrote this page (add <code>{force}</code> to replace it):</p>\n<pre><code>") +
          html_escape(r.command) + "</code></pre>\n";
    b += "<p>Each plot is a gnuplot script beside its data in <code>plots/</code>: edit the script (line styles "
         "come first) and run <code>gnuplot NAME.gp</code> in that directory for new SVG and PNG files.</p>\n";
  }
  b += "</section>\n";

  for (const auto& sec : r.sections) {
    b += "<section id=\"" + anchor(sec.id) + "\">\n<h2>" + html_escape(sec.title) + "</h2>\n";
    for (const auto& blk : sec.blocks) {
      b += blk.html;
      if (!blk.html.empty() && blk.html.back() != '\n') b += '\n';
      if (blk.table) b += table_html(*blk.table);
      if (blk.figures.size() == 1) b += figure(blk.figures.front());
      if (blk.figures.size() > 1) {
        b += "<div class=\"figrow\">\n";
        for (const auto& f : blk.figures) b += figure(f);
        b += "</div>\n";
      }
    }
    b += "</section>\n";
  }

  const auto plots = report_plots(r);
  b += "<section id=\"files\">\n<h2>Files</h2>\n";
  if (!r.files_html.empty()) {
    b += r.files_html;
  } else if (plots.empty()) {
    b += "<p>This report has no plots.</p>\n";
  } else {
    b += "<p>In <code>plots/</code>, for each figure its data (<code>.dat</code>, one block per series), gnuplot "
         "script (<code>.gp</code>), <code>.svg</code> and <code>.png</code>: ";
    for (std::size_t i = 0; i < plots.size(); ++i)
      b += (i ? ", " : "") + std::string("<code>") + html_escape(plots[i].name) + "</code>";
    b += ".</p>\n";
  }
  b += "</section>\n";
  if (!r.footer_html.empty())
    b += "<footer>" + r.footer_html + "</footer>\n";
  else
    b += "<footer>Written by cubecal. This page is self-contained: no network access, plots embedded as "
         "SVG.</footer>\n";
  return html_document(r.title, b);
}

void check_report_target(const std::string& dir, bool force, const std::string& gnuplot) {
  if (!find_gnuplot(gnuplot)) throw_gnuplot_missing(gnuplot);
  io::prepare_output_dir(dir, force, {"report.html", "plots"}, Field::report);
}

ReportResult write_command_report(const CommandReport& report, const std::string& dir, const ReportOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path d(dir);
  if (!options.force) {
    const auto existing = existing_report_outputs(dir);
    if (!existing.empty())
      throw UsageError(existing.front() + " already exists (add {force} to replace the report" +
                       std::string(fs::exists(d / "plots") ? " and its plots" : "") + ")");
  }
  std::error_code ec;
  fs::create_directories(d, ec);
  if (ec) throw UsageError("cannot create " + d.string() + ": " + ec.message());

  ReportResult res;
  const auto plots = report_plots(report);
  std::vector<RenderedPlot> rendered;
  if (!find_gnuplot(options.gnuplot)) {
    if (options.require_plots) throw_gnuplot_missing(options.gnuplot);
    res.note = "Plots not rendered: " + gnuplot_missing(options.gnuplot) + ".";
  } else if (!plots.empty()) {
    RenderOptions ro;
    ro.gnuplot = options.gnuplot;
    ro.keep_scripts = options.keep_scripts;
    ro.jobs = options.jobs;
    rendered = render_plots(plots, d / "plots", ro);
    for (const auto& r : rendered) res.plots.push_back(r.name);
    if (!options.keep_scripts) remove_stale_plots(d / "plots", report.plot_prefixes, res.plots);
  }

  const std::string page = command_report_html(report, rendered, res.note);
  const fs::path html = d / "report.html";
  write_page(html, page);
  res.html_path = html.string();
  res.html_bytes = page.size();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace cubecal::report
