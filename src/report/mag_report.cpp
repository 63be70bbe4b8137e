// The page of `cubecal calibrate mag`: the hard- and soft-iron calibration,
// the points before and after it (three projections with the circle of
// radius F) and the norm error |h| − F of every point before and after.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "command_util.hpp"
#include "cubecal/field.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

constexpr const char* kRawColor = "#7f7f7f";
constexpr const char* kCalColor = "#1f77b4";
constexpr const char* kRejectColor = "#ff7f0e";
constexpr const char* kAxisNames[] = {"x", "y", "z"};

std::string unit_of(const MagReportContext& ctx) { return ctx.unit.empty() ? std::string("input units") : ctx.unit; }

const char* method_text(mag::Method m) {
  switch (m) {
    case mag::Method::twostep: return "TWOSTEP, bias only (Alonso & Shuster 2002)";
    case mag::Method::twostep_full: return "TWOSTEP, bias + symmetric D (Alonso & Shuster 2002)";
    case mag::Method::ellipsoid: return "Li–Griffiths ellipsoid fit, k = 4 (as Magneto)";
  }
  return "";
}

double norm3(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// The points as the figures show them: which were rejected, every k-th of the others.
struct PointSets {
  std::vector<bool> rejected;
  std::vector<std::size_t> shown;          // used points drawn (indices into h)
  std::vector<std::size_t> rejected_list;  // rejected points drawn (gross outliers are not)
  std::size_t rejected_count = 0;          // every rejected point
  std::size_t stride = 1;
};

PointSets point_sets(std::size_t n, const mag::Result& r, std::size_t max_points) {
  PointSets s;
  s.rejected.assign(n, false);
  for (std::size_t k : r.rejected)
    if (k < n) s.rejected[k] = true;
  // Gross outliers (|h| = 1e50) are not drawn: they would set the axes.
  for (std::size_t k : r.rejected)
    if (k < n && !std::binary_search(r.rejected_gross.begin(), r.rejected_gross.end(), k)) s.rejected_list.push_back(k);
  for (bool b : s.rejected) s.rejected_count += b ? 1 : 0;
  const std::size_t used = n - s.rejected_count;
  const std::size_t cap = std::max<std::size_t>(1, max_points);
  s.stride = used > cap ? (used + cap - 1) / cap : 1;
  std::size_t seen = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (!s.rejected[k] && seen++ % s.stride == 0) s.shown.push_back(k);
  return s;
}

double field_at(const MagReportContext& ctx, const mag::Result& r, std::size_t k) {
  return k < ctx.field_norms.size() ? ctx.field_norms[k] : r.field_norm;
}

std::string gross_note(const PointSets& ps) {
  const std::size_t g = ps.rejected_count - ps.rejected_list.size();
  if (g == 0) return {};
  return " " + std::to_string(g) + (g == 1 ? " gross outlier" : " gross outliers") +
         " (|h| beyond 10 robust sigmas of the median |h|) not drawn.";
}

std::string shown_note(const PointSets& ps, std::size_t n) {
  if (ps.stride <= 1) return {};
  return " Every " + std::to_string(ps.stride) + "th of the " + std::to_string(n - ps.rejected_count) +
         " points used is drawn.";
}

PlotSeries point_series(std::string label, const char* color, double size, double opacity = 1.0) {
  PlotSeries s;
  s.mark = Mark::points;
  s.label = std::move(label);
  s.color = color;
  s.point_size = size;
  s.opacity = opacity;
  return s;
}

}  // namespace

std::vector<ReportFigure> mag_projection_figures(std::span<const Vec3> h, const mag::Result& r,
                                                 const MagReportContext& ctx) {
  const std::string u = unit_of(ctx);
  const PointSets ps = point_sets(h.size(), r, ctx.max_points);
  double fmean = r.field_norm;
  if (!ctx.field_norms.empty()) {
    fmean = 0.0;
    for (double f : ctx.field_norms) fmean += f;
    fmean /= static_cast<double>(ctx.field_norms.size());
  }
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  std::vector<ReportFigure> figs;
  for (const auto& pair : kPairs) {
    const int a = pair[0], b = pair[1];
    const std::string an = kAxisNames[a], bn = kAxisNames[b];
    ReportFigure f;
    Plot& p = f.plot;
    p.name = "mag_" + an + bn;
    p.title = "Points before and after calibration, " + an + "–" + bn;
    p.x = {"h_" + an + " [" + u + "]", false, std::nullopt, std::nullopt};
    p.y = {"h_" + bn + " [" + u + "]", false, std::nullopt, std::nullopt};
    p.key = "outside bottom center horizontal Left reverse maxrows 3";
    p.width = 520;
    p.height = 600;
    p.equal_axes = true;

    PlotSeries raw = point_series("raw h", kRawColor, 0.35, 0.7);
    raw.id = "raw points (used)";
    PlotSeries cal = point_series("calibrated A⁻¹(h − b)", kCalColor, 0.35);
    cal.id = "calibrated points";
    for (std::size_t k : ps.shown) {
      raw.x.push_back(h[k][a]);
      raw.y.push_back(h[k][b]);
      const Vec3 c = mag::apply(h[k], r.bias, r.soft_iron);
      cal.x.push_back(c[a]);
      cal.y.push_back(c[b]);
    }
    p.series.push_back(std::move(raw));
    p.series.push_back(std::move(cal));
    if (!ps.rejected_list.empty()) {
      PlotSeries rej = point_series("rejected (raw)", kRejectColor, 0.6);
      rej.id = "rejected points, raw";
      for (std::size_t k : ps.rejected_list) {
        rej.x.push_back(h[k][a]);
        rej.y.push_back(h[k][b]);
      }
      p.series.push_back(std::move(rej));
    }
    PlotSeries circle;
    for (int i = 0; i <= 180; ++i) {
      const double t = 2.0 * std::numbers::pi * i / 180.0;
      circle.x.push_back(fmean * std::cos(t));
      circle.y.push_back(fmean * std::sin(t));
    }
    circle.color = "#000000";
    circle.dash = Dash::dashed;
    circle.width = 1.6;
    circle.label =
        std::string(ctx.field_norms.empty() ? "|h| = F = " : "|h| = mean F = ") + format_num(fmean, 5) + " " + u;
    circle.id = "circle of radius F about the origin";
    p.series.push_back(std::move(circle));
    PlotSeries centre = point_series("hard-iron offset b", "#000000", 1.4);
    centre.x = {r.bias[a]};
    centre.y = {r.bias[b]};
    centre.id = "hard-iron offset b";
    p.series.push_back(std::move(centre));

    p.notes.push_back(face_words("raw: the input points (after {counts_per_unit}); ") +
                      "calibrated: A^-1 (h - b); both projected on " + an + "-" + bn);
    if (ps.stride > 1) p.notes.push_back("every " + std::to_string(ps.stride) + "th point used is drawn");
    if (figs.empty())
      f.caption_html = "The points projected on the " + an + "–" + bn +
                       " plane: as measured (grey), centred on the hard-iron offset b (black dot) and stretched by "
                       "the soft iron, and calibrated, A<sup>−1</sup>(h − b) (blue), which should fill the sphere of "
                       "radius F about the origin: its outline is the dashed circle." +
                       std::string(ps.rejected_list.empty() ? "" : " Rejected points in orange.") + gross_note(ps) +
                       shown_note(ps, h.size());
    else
      f.caption_html = "The same on the " + an + "–" + bn + " plane.";
    figs.push_back(std::move(f));
  }
  return figs;
}

std::vector<ReportFigure> mag_norm_error_figures(std::span<const Vec3> h, const mag::Result& r,
                                                 const MagReportContext& ctx) {
  const std::string u = unit_of(ctx);
  const PointSets ps = point_sets(h.size(), r, ctx.max_points);
  const double n = static_cast<double>(h.size());
  PlotSeries before = point_series("before: |h| − F", kRawColor, 0.4, 0.6);
  before.id = "norm error before calibration (used points)";
  PlotSeries after = point_series("after: |A⁻¹(h − b)| − F", kCalColor, 0.4);
  after.id = "norm error after calibration (used points)";
  for (std::size_t k : ps.shown) {
    const double fk = field_at(ctx, r, k);
    before.x.push_back(static_cast<double>(k + 1));
    before.y.push_back(norm3(h[k]) - fk);
    after.x.push_back(static_cast<double>(k + 1));
    after.y.push_back(norm3(mag::apply(h[k], r.bias, r.soft_iron)) - fk);
  }
  PlotSeries rej = point_series("rejected, before", kRejectColor, 0.7);
  rej.id = "rejected points, norm error before calibration";
  for (std::size_t k : ps.rejected_list) {
    rej.x.push_back(static_cast<double>(k + 1));
    rej.y.push_back(norm3(h[k]) - field_at(ctx, r, k));
  }

  ReportFigure both;
  {
    Plot& p = both.plot;
    p.name = "mag_norm_error";
    p.title = "Norm error |h| − F of every point, before and after calibration";
    p.x = {"point (input order)", false, 0.0, n + 1.0};
    p.y = {"|h| − F [" + u + "]", false, std::nullopt, std::nullopt};
    p.key = "outside bottom center horizontal Left reverse maxrows 2";
    p.height = 520;
    p.series.push_back(hline(0.0, 0.0, n + 1.0, kInkColor, Dash::solid, "zero"));
    p.series.back().opacity = 0.5;
    p.series.push_back(before);
    p.series.push_back(after);
    if (!rej.x.empty()) p.series.push_back(rej);
    p.notes.push_back("x: the point's position in the input (1 = first data row)");
    both.caption_html = "Norm error of every point before calibration, |h| − F (grey: RMS " +
                        html_escape(format_num(r.before.rms, 4) + " " + u) +
                        "), and after, |A<sup>−1</sup>(h − b)| − F (blue: RMS " +
                        html_escape(format_num(r.after.rms, 4) + " " + u) +
                        "). Before, the offset and the soft iron make |h| swing with the orientation; after, what "
                        "is left is noise and what the model cannot absorb." +
                        std::string(rej.x.empty() ? "" : " Rejected points in orange.") + shown_note(ps, h.size());
  }
  ReportFigure only_after;
  {
    Plot& p = only_after.plot;
    p.name = "mag_norm_error_after";
    p.title = "Norm error after calibration, |A⁻¹(h − b)| − F";
    p.x = {"point (input order)", false, 0.0, n + 1.0};
    p.y = {"|A⁻¹(h − b)| − F [" + u + "]", false, std::nullopt, std::nullopt};
    p.key = "outside bottom center horizontal Left reverse maxrows 2";
    p.height = 520;
    PlotSeries band;
    band.mark = Mark::band;
    band.x = {0.0, n + 1.0};
    band.y = {0.0, 0.0};
    band.lo = {-r.after.rms, -r.after.rms};
    band.hi = {r.after.rms, r.after.rms};
    band.color = kCalColor;
    band.opacity = 0.15;
    band.label = "± RMS (" + format_num(r.after.rms, 3) + " " + u + ")";
    band.id = "+- RMS of the norm error after calibration";
    p.series.push_back(std::move(band));
    p.series.push_back(hline(0.0, 0.0, n + 1.0, kInkColor, Dash::solid, "zero"));
    p.series.back().opacity = 0.5;
    after.label = "after calibration";
    p.series.push_back(std::move(after));
    p.notes.push_back("the used points only (rejected ones are not part of the fit)");
    only_after.caption_html =
        "The norm error after calibration alone, with ± its RMS (" + html_escape(format_num(r.after.rms, 4) + " " + u) +
        ", " + html_escape(printf_text("%.3g", 100.0 * r.after.rms / r.field_norm)) +
        " % of F; per-axis noise s = " + html_escape(format_num(r.noise, 4) + " " + u) +
        (r.noise_estimated ? ", estimated from the residuals" : ", given") +
        "). A pattern along the input order (a slow trend, steps) points at drift or a disturbance during the "
        "tumble rather than at the calibration.";
  }
  return {std::move(both), std::move(only_after)};
}

CommandReport mag_report(std::span<const Vec3> h, const mag::Result& r, const MagReportContext& ctx) {
  const std::string u = unit_of(ctx);
  CommandReport rep;
  rep.title = "Magnetometer calibration: " + base_name(ctx.file);
  rep.lead_html =
      "Hard- and soft-iron calibration by <code>cubecal calibrate mag</code> from points measured over "
      "many orientations: h<sub>cal</sub> = A<sup>−1</sup>(h − b) with |h<sub>cal</sub>| = F, b the "
      "hard-iron offset, A<sup>−1</sup> the symmetric soft-iron correction.";
  rep.command = ctx.command;
  rep.plot_prefixes = {"mag_"};
  const std::string fsrc =
      face_words(ctx.field_source == "given"    ? "given ({field_norm})"
                 : ctx.field_source == "column" ? "the mean of the field-norm column ({field_column})"
                                                : "the mean raw |h| (Magneto's default; give {field_norm} "
                                                  "for an absolute scale)");
  rep.input = {{"file", ctx.file, true},
               {"points",
                std::to_string(r.points_used) + " used of " + std::to_string(h.size()) +
                    (r.points_rejected > 0 ? " (" + std::to_string(r.points_rejected) + " rejected at " +
                                                 format_num(r.reject_sigma, 3) + " σ)"
                                           : std::string()),
                false},
               {"unit", u, false},
               {"method", method_text(r.method), false},
               {"field norm F", format_num(r.field_norm, 6) + " " + u + ", " + fsrc, false}};
  if (!r.rejected.empty()) {
    std::string lines;
    for (std::size_t i = 0; i < r.rejected.size() && i < 20; ++i)
      lines += (i ? ", " : "") + std::to_string(ctx.first_data_line + r.rejected[i]);
    if (r.rejected.size() > 20) lines += ", …";
    rep.input.push_back({"rejected lines", lines, false});
  }

  // Calibration.
  const bool bias_only = r.method == mag::Method::twostep;
  ReportTable cal;
  cal.title = "Calibration h_cal = A⁻¹ (h − b), 1σ";
  cal.header = {"axis", "b [" + u + "]"};
  if (!bias_only) cal.header.insert(cal.header.end(), {"A⁻¹ · x", "A⁻¹ · y", "A⁻¹ · z"});
  for (int i = 0; i < 3; ++i) {
    std::vector<std::string> row{kAxisNames[i], format_pm(r.bias[i], r.bias_sigma[i])};
    if (!bias_only)
      for (int k = 0; k < 3; ++k) row.push_back(format_pm(r.soft_iron[i][k], r.soft_iron_sigma[i][k]));
    cal.rows.push_back(std::move(row));
  }
  if (bias_only) cal.note = "Bias only: A⁻¹ = I.";

  ReportTable fit;
  fit.title = "Fit";
  fit.header = {"", "value"};
  fit.rows.push_back(
      {"semi-axes of the raw ellipsoid [" + u + "]",
       format_num(r.semi_axes[0], 6) + ", " + format_num(r.semi_axes[1], 6) + ", " + format_num(r.semi_axes[2], 6)});
  fit.rows.push_back({"axis ratio (longest / shortest)", format_num(r.axis_ratio, 6)});
  fit.rows.push_back({"noise s per axis [" + u + "]",
                      format_num(r.noise, 4) + (r.noise_estimated ? " (estimated from the residuals)" : " (given)")});
  fit.rows.push_back(
      {"χ² / degrees of freedom", format_num(r.chi2, 5) + " / " + std::to_string(r.dof) +
                                      (r.p_value ? ", p = " + format_num(*r.p_value, 3) : std::string())});
  if (r.method != mag::Method::ellipsoid)
    fit.rows.push_back(
        {"TWOSTEP iterations", std::to_string(r.iterations) + (r.converged ? " (converged)" : " (NOT converged)")});
  fit.rows.push_back(
      {"coverage: mean resultant", format_num(r.coverage.resultant, 3) + " (0 whole sphere, 0.5 hemisphere)"});
  fit.rows.push_back(
      {"coverage: smallest scatter eigenvalue", format_num(r.coverage.lambda_min, 3) + " (1/3 whole sphere)"});
  fit.rows.push_back({"coverage: octants", std::to_string(r.coverage.octants) + " of 8"});

  ReportSection s1{"calibration", "Calibration", {}};
  s1.blocks.push_back({{}, std::move(cal), {}});
  s1.blocks.push_back({{}, std::move(fit), {}});
  if (!r.notes.empty()) {
    std::string notes = "<ul class=\"reasons\">\n";
    for (const auto& n : r.notes) notes += "<li>" + html_escape(n) + "</li>\n";
    notes += "</ul>\n";
    s1.blocks.push_back({"<p>Notes of the fit:</p>\n" + notes, std::nullopt, {}});
  }
  rep.sections.push_back(std::move(s1));

  ReportSection s2{"points", "Points before and after calibration", {}};
  s2.blocks.push_back(
      {"<p>Three projections of the same points; equal scales on both axes, so a sphere shows as "
       "a circle.</p>",
       std::nullopt, mag_projection_figures(h, r, ctx)});
  rep.sections.push_back(std::move(s2));

  ReportTable ne;
  ne.title = "Norm error |h| − F";
  ne.header = {"", "mean [" + u + "]", "RMS [" + u + "]", "largest |·| [" + u + "]", "RMS / F"};
  ne.rows.push_back({"before calibration", format_num(r.before.mean, 4), format_num(r.before.rms, 4),
                     format_num(r.before.max, 4), printf_text("%.3g %%", 100.0 * r.before.rms / r.field_norm)});
  ne.rows.push_back({"after calibration", format_num(r.after.mean, 4), format_num(r.after.rms, 4),
                     format_num(r.after.max, 4), printf_text("%.3g %%", 100.0 * r.after.rms / r.field_norm)});
  ReportSection s3{"norm", "Norm error before and after", {}};
  s3.blocks.push_back({{}, std::move(ne), {}});
  for (auto& f : mag_norm_error_figures(h, r, ctx)) s3.blocks.push_back({{}, std::nullopt, {std::move(f)}});
  rep.sections.push_back(std::move(s3));
  return rep;
}

}  // namespace cubecal::report

namespace cubecal::report {

CommandReport mag_report(const pipeline::MagResult& r, const std::string& command) {
  const std::string unit = r.unit == "input units" ? std::string() : r.unit;
  return mag_report(
      r.points, r.calibration,
      {command, r.file, unit, std::string(pipeline::to_string(r.field_source)), r.field_norms, r.first_data_line});
}

}  // namespace cubecal::report
