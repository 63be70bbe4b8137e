// cubecal calibrate mag: hard- and soft-iron calibration of a magnetometer
// from points measured over many orientations (no time stamps needed):
// TWOSTEP bias only, TWOSTEP bias + symmetric D, or the Li-Griffiths
// ellipsoid fit Magneto uses. Result: h_cal = A^-1 (h - b).
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "commands.hpp"
#include "common_options.hpp"
#include "calibration_hints.hpp"
#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/pipeline/calibrate_mag.hpp"
#include "cubecal/pipeline/calibrate_mag_json.hpp"
#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/error.hpp"
#include "cubecal/report/command_reports.hpp"
#include "output.hpp"
#include "report_option.hpp"

namespace cubecal::cli {

namespace {

struct MagCliOptions {
  std::string file;
  std::string columns;
  std::size_t skip_rows = 0;
  double lsb = 1.0;
  std::string method = "ellipsoid";
  double field_norm = 0.0;
  bool field_norm_given = false;
  std::string field_col;
  double noise = 0.0;
  bool noise_given = false;
  double reject = 0.0;
  bool partial = false;
  std::string unit;
  std::string format = "table";
  std::string out;
  bool force = false;
  unsigned threads = 0;
  ReportTarget report;  // --report DIR, --gnuplot PATH
};

const char* method_text(mag::Method m) {
  switch (m) {
    case mag::Method::twostep: return "TWOSTEP, bias only (Alonso & Shuster 2002)";
    case mag::Method::twostep_full: return "TWOSTEP, bias + symmetric D (Alonso & Shuster 2002)";
    case mag::Method::ellipsoid: return "Li-Griffiths ellipsoid fit, k = 4 (as Magneto)";
  }
  return "";
}

void print_table(std::ostream& out, const pipeline::MagResult& m) {
  const mag::Result& r = m.calibration;
  const std::string u = m.unit == "input units" ? std::string() : m.unit;
  fmt::print(out, "{}: {} points used of {}", m.file, r.points_used, m.points.size());
  const std::size_t gross = r.rejected_gross.size();
  if (r.points_rejected > gross)
    fmt::print(out, " ({} rejected at {:g} sigma{})", r.points_rejected, r.reject_sigma,
               gross > 0 ? fmt::format(", {} of them gross outliers", gross) : std::string());
  else if (gross > 0)
    fmt::print(out, " ({} rejected as gross {})", gross, gross == 1 ? "outlier" : "outliers");
  fmt::print(out, "\nmethod     {}\n", method_text(r.method));
  fmt::print(out, "field norm {:.6g} {} ({})\n", r.field_norm, u,
             m.field_source == pipeline::FieldNormSource::given ? "given"
             : m.field_source == pipeline::FieldNormSource::column
                 ? "mean of the field-norm column"
                 : "mean raw |h|, Magneto's default: give --field-norm for an absolute scale");
  const bool bias_only = r.method == mag::Method::twostep;
  fmt::print(out, "\ncalibration  h_cal = A^-1 (h - b), 1-sigma{}\n", bias_only ? "; A^-1 = I (bias only)" : "");
  const char* axes = "xyz";
  for (std::size_t i = 0; i < 3; ++i) {
    fmt::print(out, "  {}  b {:>12.6g} ± {:<9.2g} {}", axes[i], r.bias[i], r.bias_sigma[i], u);
    if (!bias_only) {
      fmt::print(out, "  A^-1");
      for (std::size_t k = 0; k < 3; ++k)
        fmt::print(out, " {:>10.6f} ± {:<8.2g}", r.soft_iron[i][k], r.soft_iron_sigma[i][k]);
    }
    out << '\n';
  }
  fmt::print(out, "  semi-axes of the raw ellipsoid {:.6g} {:.6g} {:.6g} {}, axis ratio {:.5f}\n", r.semi_axes[0],
             r.semi_axes[1], r.semi_axes[2], u, r.axis_ratio);
  fmt::print(out,
             "\n|h| - F{}:  before mean {:.4g} rms {:.4g} max {:.4g};  after mean {:.4g} rms {:.4g} max {:.4g} "
             "({:.3g} % of F)\n",
             u.empty() ? std::string() : " [" + u + "]", r.before.mean, r.before.rms, r.before.max, r.after.mean,
             r.after.rms, r.after.max, 100.0 * r.after.rms / r.field_norm);
  if (r.noise_estimated)
    fmt::print(out, "noise      s = {:.4g} {} per axis, estimated from the residuals (chi2 = dof = {})\n", r.noise, u,
               r.dof);
  else
    fmt::print(out, "noise      s = {:.4g} {} per axis given; chi2 {:.1f} for {} dof, p = {:.3g}\n", r.noise, u, r.chi2,
               r.dof, r.p_value.value_or(0.0));
  if (r.method != mag::Method::ellipsoid)
    fmt::print(out, "TWOSTEP    {} iterations of step 2, {}\n", r.iterations,
               r.converged ? "converged" : "NOT converged");
  fmt::print(out,
             "coverage   mean resultant {:.3f} (0 whole sphere, 0.5 hemisphere), smallest scatter eigenvalue {:.3f} "
             "(1/3 whole sphere), {} of 8 octants\n",
             r.coverage.resultant, r.coverage.lambda_min, r.coverage.octants);
  for (const auto& n : r.notes) fmt::print(out, "note: {}\n", n);
}

int run_calibrate_mag(const MagCliOptions& o) {
  const auto method = mag::parse_method(o.method);
  if (!method) throw UsageError("--method must be twostep, twostep-full or ellipsoid");
  pipeline::MagRequest req;
  req.method = *method;
  req.counts_per_unit = o.lsb;
  if (o.field_norm_given) req.field_norm = o.field_norm;
  req.field_column = !o.field_col.empty();
  if (o.noise_given) req.noise = o.noise;
  req.reject_sigma = o.reject;
  req.allow_partial = o.partial;
  req.unit = o.unit;
  req.validate();
  const std::vector<std::string> cols = split_list(o.columns);
  pipeline::check_mag_columns(cols);

  // Refuse to replace a result before spending any time.
  ResultOutput result(o.out, o.force);  // refuses an existing file before the work
  check_report_option(o.report, o.force);

  io::TableOptions to;
  to.columns = cols;
  to.skip_rows = o.skip_rows;
  to.threads = o.threads;
  if (!o.field_col.empty()) to.extra_columns.push_back(o.field_col);
  const io::Table t = io::read_table(o.file, to);
  if (t.data.size() != 3)
    throw UsageError(o.file + " has " + std::to_string(t.data.size()) +
                     " data columns: name the 3 magnetometer columns with --columns mx,my,mz");

  if (o.field_norm_given) {
    const std::string w = field_norm_warning(o.field_norm, t.data, o.lsb);
    if (!w.empty()) std::cerr << "cubecal: warning: " << o.file << ": " << w << '\n';
  }

  HintContext hints;
  hints.command = CalibrationCommand::mag;
  hints.bias_only = *method == mag::Method::twostep;
  hints.field_col = req.field_column;
  const pipeline::MagResult r = with_calibration_hints(o.file, hints, [&] { return pipeline::calibrate_mag(t, req); });

  write_result(result, o.format == "json", r, invocation(),
               [](std::ostream& os, const auto& res) { print_table(os, res); });
  if (!o.report.dir.empty()) write_report_option(report::mag_report(r, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_calibrate_mag_command(CLI::App& calibrate, Command& run) {
  auto opt = std::make_shared<MagCliOptions>();
  CLI::App* cmd = calibrate.add_subcommand(
      "mag",
      "Magnetometer hard- and soft-iron calibration from points over many orientations (no time stamps): "
      "h_cal = A^-1 (h - b) with |h_cal| = F. Methods: twostep (bias only, tolerates partial coverage), "
      "twostep-full (bias + symmetric D), ellipsoid (Li-Griffiths, as Magneto)");
  cmd->add_option("file", opt->file, "Points: delimited text with 3 magnetometer columns, optionally gzip-compressed")
      ->required();
  cmd->add_option("--method", opt->method, "twostep, twostep-full or ellipsoid")
      ->check(CLI::IsMember({"twostep", "twostep-full", "ellipsoid"}))
      ->capture_default_str();
  cmd->add_option("--columns", opt->columns,
                  "The 3 magnetometer columns, by header name or 1-based index (mx,my,mz or 2,3,4); default: "
                  "every column, which must then be 3");
  cmd->add_option("--skip-rows", opt->skip_rows, "Lines to skip before the header/data (preamble)");
  cmd->add_option("--lsb", opt->lsb,
                  "Counts per unit: values are divided by this (one value: the three axes "
                  "share the scale the fit solves for)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            return s.find(',') == std::string::npos
                       ? std::string()
                       : "'" + s +
                             "': one value here, for all three axes (the fit's scale factors absorb "
                             "any difference between them)";
          },
          ""));
  auto* fn = cmd->add_option("--field-norm", opt->field_norm,
                             "Local field magnitude F (e.g. from IGRF), in the units after --lsb; default: the "
                             "mean raw |h| (Magneto's default)");
  cmd->add_option("--field-col", opt->field_col,
                  "Column with the reference field magnitude |H_k| of each point (TWOSTEP only, e.g. IGRF along "
                  "an orbit), in the units of the values after --lsb (the column itself is not divided by --lsb)");
  auto* ns = cmd->add_option("--noise", opt->noise,
                             "Per-axis measurement noise (1 sigma, units after --lsb) for the weights and the "
                             "chi-squared test; default: estimated from the residuals");
  cmd->add_option("--reject", opt->reject,
                  "Reject points whose |h| is more than SIGMA standard deviations from the mean |h| "
                  "(Magneto's rule, one pass), after the gross outliers (|h| beyond 10 robust sigmas of the "
                  "median |h|); the default field norm is then the mean |h| of the points kept; 0: none")
      ->capture_default_str();
  cmd->add_flag("--allow-partial", opt->partial,
                "Fit even when the points do not cover enough of the sphere for the method");
  cmd->add_option("--unit", opt->unit, "Name of the unit of the values after --lsb (e.g. uT, mG), for the output");
  cmd->add_option("--format", opt->format, "Output format")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->add_option("--threads", opt->threads, "Reader threads (default: all cores)");
  cmd->callback([opt, fn, ns, &run] {
    opt->field_norm_given = fn->count() > 0;
    opt->noise_given = ns->count() > 0;
    run = [opt] { return run_calibrate_mag(*opt); };
  });
  return cmd;
}

}  // namespace cubecal::cli
