// The page of `cubecal calibrate rate-table`: the calibration (A, β and the
// forward scale factors, misalignments and biases with 1σ), and the plateau
// residuals per axis before calibration (identity, no bias) and after.
#include <algorithm>
#include <cmath>

#include "command_util.hpp"
#include "cubecal/report/command_reports.hpp"
#include "cubecal/report/html.hpp"

namespace cubecal::report {

using namespace detail;

namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z"};

// w_g - (w + earth) per plateau: the residual of the identity calibration.
std::vector<std::array<double, 3>> residuals_before(const PlateauDetection& found, const RateTableReportContext& ctx) {
  std::vector<std::array<double, 3>> v;
  for (const auto& p : found.plateaus) {
    std::array<double, 3> r{};
    for (int a = 0; a < 3; ++a) r[a] = p.mean[a] - (p.ref[a] + ctx.earth_rate[a]);
    v.push_back(r);
  }
  return v;
}

ReportFigure residual_figure(const PlateauDetection& found, const std::vector<std::array<double, 3>>& res, bool after,
                             const RateTableReportContext& ctx, const RateTableCalibration& cal) {
  ReportFigure f;
  Plot& p = f.plot;
  const std::size_t n = std::min(found.plateaus.size(), res.size());
  p.name = after ? "rate_residual_after" : "rate_residual_before";
  p.title =
      after ? "Plateau residuals after calibration, A w_g + β − w" : "Plateau residuals before calibration, w_g − w";
  p.x = {"plateau", false, 0.5, static_cast<double>(n) + 0.5};
  if (n <= 30) p.x_tics = 1.0;
  p.y = {"residual [" + ctx.unit + "]", false, std::nullopt, std::nullopt};
  p.key = "outside bottom center horizontal Left reverse maxrows 2";
  p.width = 900;
  p.height = 520;
  p.series.push_back(hline(0.0, 0.5, static_cast<double>(n) + 0.5, kInkColor, Dash::solid, "zero"));
  p.series.back().opacity = 0.5;
  for (int a = 0; a < 3; ++a) {
    PlotSeries s;
    s.mark = Mark::errorbars;
    // The axes side by side around each plateau's number.
    const double dx = 0.15 * (a - 1);
    for (std::size_t k = 0; k < n; ++k) {
      const Plateau& pl = found.plateaus[k];
      const double se = pl.n > 0 ? pl.stddev[a] / std::sqrt(static_cast<double>(pl.n)) : 0.0;
      s.x.push_back(static_cast<double>(k + 1) + dx);
      s.y.push_back(res[k][a]);
      s.lo.push_back(res[k][a] - se);
      s.hi.push_back(res[k][a] + se);
    }
    s.color = axis_color(static_cast<std::size_t>(a));
    s.point_size = 0.9;
    s.width = 1.2;
    s.label = std::string("axis ") + kAxisNames[a];
    s.id = std::string(after ? "after" : "before") + ", axis " + kAxisNames[a];
    p.series.push_back(std::move(s));
  }
  // Room above and below the outermost bars (autoscaling stops at the data).
  double lo = 0.0, hi = 0.0;
  for (const auto& s : p.series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      lo = std::min({lo, s.y[i], i < s.lo.size() ? s.lo[i] : s.y[i]});
      hi = std::max({hi, s.y[i], i < s.hi.size() ? s.hi[i] : s.y[i]});
    }
  if (hi > lo && std::isfinite(hi - lo)) {
    p.y.min = lo - 0.08 * (hi - lo);
    p.y.max = hi + 0.08 * (hi - lo);
  }
  const ResidualStats& st = after ? cal.residual_after : cal.residual_before;
  p.notes.push_back(after ? "residual A w_g + beta - w of each plateau mean, per axis (x offset by -0.15, 0, +0.15)"
                          : "residual w_g - w of each plateau mean, per axis, identity calibration without bias "
                            "(x offset by -0.15, 0, +0.15)");
  p.notes.push_back("error bars: standard error of the plateau mean, std / sqrt(n)");
  const std::string stats =
      "RMS " + format_num(st.rms, 4) + " " + ctx.unit + ", largest " + format_num(st.max_abs, 4) + " " + ctx.unit;
  if (after)
    f.caption_html = "Residual A w<sub>g</sub> + β − w of every plateau mean after calibration, per axis (" +
                     html_escape(stats) +
                     "), bars ± the standard error of the mean (std / √n). What is left is "
                     "noise, bias drift between plateaus and table-rate errors; the fit used these same plateaus, "
                     "so this is how well the model fits, not an independent check.";
  else
    f.caption_html =
        "Residual w<sub>g</sub> − w of every plateau mean before calibration — the identity, no bias "
        "(" +
        html_escape(stats) +
        "). The bias shows as a constant offset per axis, scale-factor "
        "errors as residuals growing with the rate about that axis, misalignments as residuals on the "
        "other axes.";
  return f;
}

std::string pm_cell(double v, double s) { return format_pm(v, s); }

}  // namespace

std::vector<ReportFigure> rate_table_residual_figures(const PlateauDetection& found, const RateTableCalibration& cal,
                                                      const RateTableReportContext& ctx) {
  return {residual_figure(found, residuals_before(found, ctx), false, ctx, cal),
          residual_figure(found, cal.residuals_after, true, ctx, cal)};
}

namespace {

// The input fields: the file, the plateaus used and dropped, the Earth rate.
void rate_table_input(CommandReport& r, const PlateauDetection& found, const RateTableCalibration& cal,
                      const RateTableReportContext& ctx) {
  const std::string& u = ctx.unit;
  r.input = {{"file", ctx.file, true},
             {"unit", u, false},
             {"plateaus from", ctx.source_text, false},
             {"plateaus used", std::to_string(cal.plateaus), false}};
  if (found.dropped_short > 0)
    r.input.push_back({"dropped", std::to_string(found.dropped_short) + " too short after the margins", false});
  if (found.unmatched > 0)
    r.input.push_back({"unmatched", std::to_string(found.unmatched) + " outside the schedule (dropped)", false});
  r.input.push_back(
      {"residual degrees of freedom",
       std::to_string(cal.dof) + (cal.noise_from_residuals ? " (plateau noise estimated from the fit residuals)"
                                                           : " (none: sigmas from the within-plateau noise)"),
       false});
  const bool earth = ctx.earth_rate[0] != 0.0 || ctx.earth_rate[1] != 0.0 || ctx.earth_rate[2] != 0.0;
  r.input.push_back({"Earth rate",
                     earth ? "added to every reference rate: (" + format_num(ctx.earth_rate[0], 5) + ", " +
                                 format_num(ctx.earth_rate[1], 5) + ", " + format_num(ctx.earth_rate[2], 5) + ") " + u
                           : "ignored (as when the table compensates it)",
                     false});
}

// The calibration, inverted (paper eq. 6) and forward.
ReportSection calibration_section(const RateTableCalibration& cal, const std::string& u) {
  // Calibration.
  ReportTable inv;
  inv.title = "Calibration w = A w_g + β (paper eq. 6), 1σ";
  inv.header = {"axis", "A · x", "A · y", "A · z", "β [" + u + "]"};
  for (int i = 0; i < 3; ++i)
    inv.rows.push_back({kAxisNames[i], pm_cell(cal.A[i][0], cal.A_sigma[i][0]), pm_cell(cal.A[i][1], cal.A_sigma[i][1]),
                        pm_cell(cal.A[i][2], cal.A_sigma[i][2]), pm_cell(cal.beta[i], cal.beta_sigma[i])});
  ReportTable fwd;
  fwd.title = "Forward model w_g = S w + b_g: what datasheets quote";
  fwd.header = {"axis",
                "scale-factor error [ppm]",
                "bias b_g [" + u + "]",
                "misalignment toward x [mrad]",
                "toward y [mrad]",
                "toward z [mrad]"};
  for (int i = 0; i < 3; ++i) {
    std::vector<std::string> row{kAxisNames[i],
                                 pm_cell(1e6 * cal.scale_factor_error[i], 1e6 * cal.scale_factor_error_sigma[i]),
                                 pm_cell(cal.bias[i], cal.bias_sigma[i])};
    for (int k = 0; k < 3; ++k)
      row.push_back(i == k ? std::string("—")
                           : pm_cell(1e3 * cal.misalignment[i][k], 1e3 * cal.misalignment_sigma[i][k]));
    fwd.rows.push_back(std::move(row));
  }
  fwd.note =
      "Misalignment of row i toward column j: the angle by which gyro axis i leans toward reference axis j, "
      "atan(S_ij / S_ii).";
  ReportSection cal_sec{"calibration", "Calibration", {}};
  cal_sec.blocks.push_back({{}, std::move(inv), {}});
  cal_sec.blocks.push_back({{}, std::move(fwd), {}});
  return cal_sec;
}

// The plateau residuals before and after, with their figures and the plateaus.
ReportSection residual_section(const PlateauDetection& found, const RateTableCalibration& cal,
                               const RateTableReportContext& ctx) {
  const std::string& u = ctx.unit;
  // Residuals.
  ReportTable sum;
  sum.title = "Plateau residuals";
  sum.header = {"", "largest |residual| [" + u + "]", "RMS [" + u + "]"};
  sum.rows.push_back({"before calibration (identity, no bias)", format_num(cal.residual_before.max_abs, 4),
                      format_num(cal.residual_before.rms, 4)});
  sum.rows.push_back(
      {"after calibration", format_num(cal.residual_after.max_abs, 4), format_num(cal.residual_after.rms, 4)});
  ReportSection res_sec{"residuals", "Plateau residuals before and after", {}};
  res_sec.blocks.push_back({{}, std::move(sum), {}});
  for (auto& f : rate_table_residual_figures(found, cal, ctx))
    res_sec.blocks.push_back({{}, std::nullopt, {std::move(f)}});

  ReportTable pl;
  pl.title = "Plateaus";
  pl.header = {"#",        "t begin [s]", "t end [s]", "n",       "reference x", "y", "z",
               "before x", "y",           "z",         "after x", "y",           "z"};
  const auto before = residuals_before(found, ctx);
  for (std::size_t k = 0; k < found.plateaus.size(); ++k) {
    const Plateau& p = found.plateaus[k];
    std::vector<std::string> row{std::to_string(k + 1), format_num(p.t_begin, 6), format_num(p.t_end, 6),
                                 std::to_string(p.n)};
    for (int a = 0; a < 3; ++a) row.push_back(format_num(p.ref[a], 6));
    for (int a = 0; a < 3; ++a) row.push_back(format_num(before[k][a], 3));
    for (int a = 0; a < 3; ++a)
      row.push_back(k < cal.residuals_after.size() ? format_num(cal.residuals_after[k][a], 3) : std::string("—"));
    pl.rows.push_back(std::move(row));
  }
  pl.note = "Reference rates and residuals in " + u + "; the plateau numbers are those of the figures.";
  res_sec.blocks.push_back({{}, std::move(pl), {}});
  return res_sec;
}

// The error covariance of the calibrated samples (eq. 12).
ReportSection covariance_section(const RateTableCalibration& cal, const std::string& u) {
  // Error covariance (eq. 12).
  ReportTable cov;
  cov.title = "Error covariance of the calibrated samples (paper eq. 12), (" + u + ")²";
  cov.header = {"", "x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    cov.rows.push_back({kAxisNames[i], printf_text("%.4e", cal.error_covariance[i][0]),
                        printf_text("%.4e", cal.error_covariance[i][1]),
                        printf_text("%.4e", cal.error_covariance[i][2])});
  cov.note =
      "Covariance of A w_g + β − w over every sample of every plateau (within-plateau scatter mapped by A "
      "plus the spread of the plateau residuals): the measurement noise of the calibrated gyro.";
  ReportSection cov_sec{"covariance", "Error covariance", {}};
  cov_sec.blocks.push_back({{}, std::move(cov), {}});
  return cov_sec;
}

}  // namespace

CommandReport rate_table_report(const PlateauDetection& found, const RateTableCalibration& cal,
                                const RateTableReportContext& ctx) {
  const std::string& u = ctx.unit;
  CommandReport r;
  r.title = "Rate-table calibration: " + base_name(ctx.file);
  r.lead_html =
      "Gyro scale factors, misalignment and bias by <code>cubecal calibrate rate-table</code> from the "
      "gyro means of constant-rate plateaus (the paper's fourth gyro test, eq. 6–13): the forward model "
      "w<sub>g</sub> = S w + b<sub>g</sub> fitted by least squares and inverted to the paper's "
      "w = A w<sub>g</sub> + β, with 1σ uncertainties.";
  r.command = ctx.command;
  r.plot_prefixes = {"rate_residual_"};
  rate_table_input(r, found, cal, ctx);

  r.sections.push_back(calibration_section(cal, u));
  r.sections.push_back(residual_section(found, cal, ctx));
  r.sections.push_back(covariance_section(cal, u));
  return r;
}

}  // namespace cubecal::report

namespace cubecal::report {

CommandReport rate_table_report(const pipeline::RateTableResult& r, const std::string& command) {
  return rate_table_report(r.found, r.calibration,
                           {command, r.file, r.unit, std::string(pipeline::describe(r.source)), r.earth_rate});
}

}  // namespace cubecal::report
