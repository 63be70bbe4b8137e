// cubecal psd: the Welch power spectral density of each channel, its
// power-law fit and the IEEE 952 terms the fit stands for.
#include <fmt/format.h>
#include <fmt/ostream.h>

#include <cmath>
#include <iostream>
#include <optional>

#include "cubecal/report/command_reports.hpp"
#include "report_option.hpp"
#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/pipeline/psd_json.hpp"
#include "cubecal/pipeline/json_text.hpp"
#include "cubecal/spectral/density_unit.hpp"
#include "output.hpp"

namespace cubecal::cli {

namespace {

struct PsdOptions {
  InputOptions input;
  std::string unit;  // empty: from the column names, else none
  std::string window = "hann";
  std::size_t segment = 0;
  double fmin = 0.0;
  double overlap = 0.5;
  std::string detrend = "constant";
  std::optional<std::size_t> bins_per_decade;  // default: 10 for the table, every bin for csv and json
  double fit_min = 0.0;
  double fit_max = 0.0;
  bool no_fit = false;
  std::string format = "table";
  std::string out;
  bool force = false;
  ReportTarget report;
};

constexpr std::size_t kTableBinsPerDecade = 10;

std::string term_title(Term t) {
  switch (t) {
    case Term::Q: return "Q  angle quantization";
    case Term::N: return "N  white noise (ARW)";
    case Term::B: return "B  bias instability";
    case Term::K: return "K  rate random walk";
    case Term::R: return "R  rate ramp";
  }
  return "";
}

std::string num(double v) { return fmt::format("{:.6g}", v); }

void write_table(std::ostream& out, const pipeline::PsdResult& r) {
  fmt::print(out, "psd of {}: {} channel(s), {} samples at {} Hz", r.file.empty() ? "-" : r.file, r.channels.size(),
             r.samples, rate_text(r.rate_hz));
  if (r.pieces > 1)
    fmt::print(out, ", {} pieces split at gaps ({} long enough for a segment)", r.pieces, r.pieces_used);
  out << '\n';
  if (r.channels.empty()) return;
  const Psd& s = r.channels.front().spectrum;
  fmt::print(out,
             "Welch: {} window, segments of {} samples ({} s) overlapping by {} samples, {} detrend: {} segments "
             "averaged; resolution {} Hz, ENBW {} Hz\n",
             to_string(s.window), s.segment_length, num(static_cast<double>(s.segment_length) / r.rate_hz), s.overlap,
             to_string(s.detrend), s.segments, num(s.resolution_hz()), num(s.enbw_hz));
  fmt::print(out, "One-sided densities: their integral over 0..{} Hz is the variance.{}\n", num(0.5 * r.rate_hz),
             r.bins_per_decade > 0
                 ? fmt::format(" Averaged over {} log bands per decade (bins: raw bins in each).", r.bins_per_decade)
                 : std::string());
  for (const auto& c : r.channels) {
    const DensityUnit du = density_unit(c.unit);
    const auto rate_unit = rate_density_unit(c.unit);
    fmt::print(out, "\n{} [{}]\n", c.name, c.unit.name.empty() ? "no unit given" : c.unit.name);
    if (r.fitted && !c.fit_error.empty()) {
      fmt::print(out, "  power-law fit not made: {}\n", c.fit_error);
    } else if (r.fitted) {
      const PowerLawFit& f = c.fit;
      fmt::print(out, "  power-law fit S(f) = sum h_a f^a over {}..{} Hz ({} bands, chi2/dof {}):\n", num(f.f_lo),
                 num(f.f_hi), f.bands, f.dof > 0 ? num(f.chi2 / static_cast<double>(f.dof)) : std::string("-"));
      fmt::print(out, "  {:>5} {:>13} {:>11}  {:<22} {}\n", "a", "h_a", "sigma", "unit", "holds over [Hz]");
      for (const auto& t : f.terms) {
        const std::string range = !t.valid       ? "(not seen: at its bound 0)"
                                  : t.f_lo > 0.0 ? num(t.f_lo) + " .. " + num(t.f_hi)
                                                 : "(below half of the model everywhere)";
        fmt::print(out, "  {:>5} {:>13.5e} {:>11.3e}  {:<22} {}\n", t.alpha, t.h, t.sigma,
                   power_law_unit(c.unit, t.alpha), range);
      }
      if (!c.allan_terms.empty()) {
        out << "  IEEE 952 terms the coefficients stand for:\n";
        for (const auto& a : c.allan_terms) {
          if (a.estimate.valid)
            fmt::print(out, "    {:<24} {:>12.5g} ± {:<10.3g} {}\n", term_title(a.term), a.display.value,
                       a.display.sigma, a.display.unit);
          else
            fmt::print(out, "    {:<24} {:>12} {:<14} {}\n", term_title(a.term), "-", "", a.display.unit);
        }
      }
    }
    fmt::print(out, "  {:>14} {:>7} {:>9} {:>16}", "frequency [Hz]", "bins", "edf", "PSD [" + du.name + "]");
    if (rate_unit) fmt::print(out, " {:>20}", "[" + rate_unit->name + "]");
    out << '\n';
    const Psd& p = c.spectrum;
    for (std::size_t i = 0; i < p.size(); ++i) {
      fmt::print(out, "  {:>14.6e} {:>7} {:>9.4g} {:>16.6e}", p.frequency[i], p.bins[i], p.edf[i], p.density[i]);
      if (rate_unit) fmt::print(out, " {:>20.6e}", p.density[i] * rate_unit->factor);
      out << '\n';
    }
  }
}

void write_csv(std::ostream& out, const pipeline::PsdResult& r) {
  out << "column,density_unit,frequency_hz,bins,edf,psd\n";
  for (const auto& c : r.channels) {
    const std::string unit = density_unit(c.unit).name;
    const Psd& p = c.spectrum;
    for (std::size_t i = 0; i < p.size(); ++i)
      fmt::print(out, "{},{},{:.17g},{},{:.17g},{:.17g}\n", c.name, unit, p.frequency[i], p.bins[i], p.edf[i],
                 p.density[i]);
  }
}

int run_psd_command(const PsdOptions& o) {
  pipeline::PsdRequest req;
  if (!o.unit.empty()) req.units = parse_units(o.unit);  // a typo fails before the reading
  req.welch.window = *parse_window(o.window);
  req.welch.detrend = *parse_detrend(o.detrend);
  req.welch.segment_length = o.segment;
  req.welch.min_frequency_hz = o.fmin;
  req.welch.overlap = o.overlap;
  req.bins_per_decade = o.bins_per_decade.value_or(o.format == "table" ? kTableBinsPerDecade : 0);
  req.fit = !o.no_fit;
  req.fit_options.min_frequency_hz = o.fit_min;
  req.fit_options.max_frequency_hz = o.fit_max;
  if (o.fit_min > 0.0 && o.fit_max > 0.0 && !(o.fit_max > o.fit_min))
    throw UsageError(Field::fit_range, "the band's upper end must lie above its lower end");
  req.threads = o.input.threads;

  check_report_option(o.report, o.force);
  ResultOutput result(o.out, o.force);  // refuses an unusable --out before the work
  io::SeriesOptions so = to_series_options(o.input);
  so.keep_time = false;  // the spectrum needs the rate and the pieces, not the stamps
  const io::Series series = io::read_series(o.input.file, so);
  std::string unit_note;
  if (o.unit.empty()) {
    try {
      ChannelUnits units = units_for({}, series);
      unit_note = units.note;
      req.units = std::move(units.units);
    } catch (const UsageError&) {
      unit_note = "cubecal: note: " + series.file +
                  ": no unit for the channels: densities in u^2/Hz, u the unit of the values (--unit names it)";
    }
  }
  const pipeline::PsdResult res = pipeline::run_psd(series, req);
  // The notes once the request has proved workable: a refused one is one line.
  note_default_columns(series);
  if (!unit_note.empty()) std::cerr << unit_note << '\n';
  if (series.segments.size() > 1)
    std::cerr << fmt::format(
        "cubecal: note: {} gaps/jitter found; the segments of each of the {} contiguous "
        "pieces are averaged together\n",
        series.irregular_intervals, series.segments.size());

  std::ostream& out = result.stream();
  if (o.format == "json")
    out << pipeline::json_text(pipeline::to_json(res), 1) << '\n';
  else if (o.format == "csv")
    write_csv(out, res);
  else
    write_table(out, res);
  result.finish();
  if (!o.report.dir.empty()) write_report_option(report::psd_report(res, invocation()), o.report);
  return 0;
}

}  // namespace

CLI::App* add_psd_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<PsdOptions>();
  CLI::App* cmd = app.add_subcommand(
      "psd",
      "Power spectral density (Welch's method, one-sided, unit^2/Hz) of each channel, its power-law fit "
      "S(f) = sum h_a f^a and the IEEE 952 terms (N, B, K, Q) the fit stands for");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--unit", opt->unit,
                  "Unit of the values (after --lsb): " + known_units() +
                      "; one for all columns or one per column. Default: from the column names' suffixes; without "
                      "one the densities are in u^2/Hz. Rate sensors get (deg/h)^2/Hz beside and the terms in "
                      "deg/sqrt(h), deg/h, deg/h/sqrt(h)");
  cmd->add_option("--window", opt->window, "Data window of each segment (scipy's periodic windows)")
      ->check(CLI::IsMember({"hann", "hamming", "blackman", "rectangular"}))
      ->capture_default_str();
  auto* segment = cmd->add_option("--segment", opt->segment,
                                  "Samples per segment (the transform length; the resolution is rate/N). Default: "
                                  "the largest power of two up to a record's samples / 8")
                      ->check(whole_number(4, 1e12));
  cmd->add_option("--fmin", opt->fmin,
                  "Lowest frequency to resolve, Hz: segments of the smallest power of two N with rate/N <= fmin")
      ->check(positive_number())
      ->excludes(segment);
  cmd->add_option("--overlap", opt->overlap, "Fraction of a segment shared with the next, 0 <= overlap < 1")
      ->check(number_between(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--detrend", opt->detrend,
                  "Removed from each segment before windowing: none, constant (its mean) "
                  "or linear (its least-squares line)")
      ->check(CLI::IsMember({"none", "constant", "linear"}))
      ->capture_default_str();
  cmd->add_option("--bins-per-decade", opt->bins_per_decade,
                  "Average the spectrum over K log-spaced bands per decade (the bins column counts the raw bins "
                  "of each); 0 keeps every bin. Default: 10 for the table, every bin for csv and json")
      ->check(whole_number(0, 1000));
  cmd->add_option("--fit-min", opt->fit_min,
                  "Lower end of the power-law fit, Hz (default: raw bin 10, rate*10/N: below it the window's leakage "
                  "of a steep spectrum biases the bins)")
      ->check(positive_number());
  cmd->add_option("--fit-max", opt->fit_max, "Upper end of the power-law fit, Hz (default: Nyquist)")
      ->check(positive_number());
  cmd->add_flag("--no-fit", opt->no_fit, "The spectrum only: no power-law fit, no IEEE 952 terms");
  cmd->add_option("--format", opt->format, "Output format")
      ->check(CLI::IsMember({"table", "csv", "json"}))
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Write the result to this file instead of standard output");
  cmd->add_flag("--force", opt->force, "Replace the --out file and the --report files if they exist");
  add_report_option(*cmd, opt->report);
  cmd->callback([opt, &run] { run = [opt] { return run_psd_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
