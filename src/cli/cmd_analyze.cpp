// cubecal analyze: static characterization of a record (the paper's
// sections 2 and 3): noise terms, sensor models, drift, covariance,
// temperature dependence.
#include <fmt/format.h>

#include <fmt/ostream.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

#include "calibration_hints.hpp"
#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/output_path.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/noise/bias_verdict.hpp"
#include "cubecal/noise/wic.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/pipeline/analysis_output.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/analyze_stream.hpp"
#include "cubecal/pipeline/spectral_analysis.hpp"
#include "cubecal/io/sample_stream.hpp"
#include "cubecal/pipeline/estimator_config.hpp"
#include "cubecal/pipeline/simulator_export.hpp"
#include "cubecal/report/plot.hpp"
#include "cubecal/report/report.hpp"
#include "memory_budget.hpp"
#include "output.hpp"
#include "progress.hpp"
#include "report_option.hpp"
#include "timings.hpp"

namespace cubecal::cli {

namespace {

struct AnalyzeOptions {
  InputOptions input;
  std::string unit;  // empty: from the column names (units_for)
  std::string temp_col;
  std::size_t temp_order = 1;
  double drift_window = 0.0;
  std::size_t cov_samples = 0;
  std::size_t max_samples = 0;
  std::string model_lsb;
  std::string taus = "log:10";
  double ci = 0.683;
  std::string out;
  bool force = false;
  bool report = false;
  std::string gnuplot;  // --gnuplot PATH; empty: gnuplot on PATH
  std::string format = "table";
  std::string rostopic = "/imu0";
  std::vector<std::string> estimators;  // --for
  double inflate = 1.0;
  bool psd = false;
  std::string composite;  // --composite [MODEL]; given bare: "auto"
  bool composite_given = false;
  std::size_t composite_bootstrap = 0;
  std::size_t twin_check = 0;  // --twin-check K
  MemoryOptions memory;
  Timings timings;
};

// --for names, in the order given, without repeats.
std::vector<pipeline::Estimator> parse_estimators(const std::vector<std::string>& names) {
  std::vector<pipeline::Estimator> list;
  for (const auto& n : names) {
    const auto e = pipeline::parse_estimator(n);
    if (!e) throw UsageError("--for: '" + n + "' is not one of " + pipeline::estimator_names());
    if (std::find(list.begin(), list.end(), *e) == list.end()) list.push_back(*e);
  }
  return list;
}

std::string pm(const Quantity& q, bool valid, int digits = 4) {
  if (!valid) return "—";
  return fmt::format("{:.{}g} ± {:.2g} {}", q.value, digits, q.sigma, q.unit);
}

// A reported term: the estimate with its uncertainty, or "< bound".
std::string reported(const ReportedTerm& t, Term which, const Unit& u) {
  if (!t.estimate.valid) return "—";
  const Quantity q = display(t.estimate, which, u);
  if (t.bound()) return fmt::format("< {:.4g} {} (upper bound)", q.value, q.unit);
  return pm(q, true);
}

// The accelerometer terms as inertial navigation quotes them (units.hpp).
void print_accelerometer_terms(std::ostream& out, const pipeline::NoiseAnalysis& n, const ReportedTerms& t,
                               const Unit& u) {
  if (u.kind != SensorKind::acceleration) return;
  const auto both = [&](const TermEstimate& e, Term which, bool bound = false) {
    if (!e.valid) return std::string("—");
    const auto q = accelerometer_display(e, which, u);
    if (bound) return fmt::format("< {:.4g} {} = {:.4g} {}", q[0].value, q[0].unit, q[1].value, q[1].unit);
    return pm(q[0], true) + " = " + pm(q[1], true);
  };
  fmt::print(out, "  {:<10} VRW {}   B {}   AccRW {}\n", "reported", both(t.N.estimate, Term::N, t.N.bound()),
             both(t.B.estimate, Term::B, t.B.bound()), both(t.K.estimate, Term::K, t.K.bound()));
  fmt::print(out, "  {:<10} white {}   B {}   AccRW {}\n", "5-term fit", both(n.fit.N, Term::N), both(n.fit.B, Term::B),
             both(n.fit.K, Term::K));
}

// The reported K: the estimate when significant, else why not and the bound.
std::string k_line(const ReportedTerms& t, const Unit& u) {
  if (!t.K.estimate.valid) return "—";
  if (!t.K.bound())
    return fmt::format("{} ({}, significant: > 2 sigma)", reported(t.K, Term::K, u), to_string(t.K.source));
  if (t.K_candidate.valid)
    return fmt::format("not significant: {} {} is not above 2 sigma; {}",
                       t.K_candidate_source == TermSource::fit ? "5-term fit" : "read-off",
                       pm(display(t.K_candidate, Term::K, u), true), reported(t.K, Term::K, u));
  return fmt::format("not identified (no +1/2 slope, none in the 5-term fit); {}", reported(t.K, Term::K, u));
}

// One line when the read-off and the fit disagree on B: which to use and why.
void print_bias_verdict(std::ostream& out, const pipeline::NoiseAnalysis& n, const Unit& u) {
  const BiasVerdict v = judge_bias_instability(n.readoffs, n.fit);
  if (v.trust != BiasTrust::read_off && v.trust != BiasTrust::fit) return;
  const std::string ro = pm(display(n.readoffs.B, Term::B, u), true);
  const std::string fit = n.fit.B.valid ? pm(display(n.fit.B, Term::B, u), true) : std::string("—");
  fmt::print(out, "  B         read-off {} vs fit {}{}: use the {}: {}\n", ro, fit,
             v.compared ? fmt::format(" (x{:.2g}{})", v.ratio, v.beyond_sigma ? ", beyond their uncertainty" : "")
                        : std::string(),
             v.trust == BiasTrust::fit ? "fit" : "read-off", v.reason);
}

// The temperature coefficient (jointly with the random-walk bias, or least
// squares when no random-walk model fits), and the compensated series: its
// noise terms and sensor models beside the record's above.
void print_temperature(std::ostream& out, const pipeline::TemperatureAnalysis& t, const Unit& u) {
  const auto c1 = [](const TemperatureFit& f) {
    return fmt::format("{:.4g} ± {:.2g}", f.coeff.size() > 1 ? f.coeff[1] : 0.0,
                       f.coeff_sigma.size() > 1 ? f.coeff_sigma[1] : 0.0);
  };
  if (t.joint)
    fmt::print(out,
               "  temperature  {} {}/degC jointly with the random-walk bias (least squares {}); R^2 {:.3f}, T_ref "
               "{:.2f} degC\n",
               c1(t.fit), u.name, c1(t.ols), t.fit.r2, t.fit.t_ref);
  else
    fmt::print(out, "  temperature  {} {}/degC by least squares; R^2 {:.3f}, T_ref {:.2f} degC\n               ({})\n",
               c1(t.fit), u.name, t.fit.r2, t.fit.t_ref, t.joint_error);
  fmt::print(out, "  compensated  N {}   B {}   K {}\n",
             pm(display(t.compensated.readoffs.N, Term::N, u), t.compensated.readoffs.N.valid),
             pm(display(t.compensated.readoffs.B, Term::B, u), t.compensated.readoffs.B.valid),
             pm(display(t.compensated.readoffs.K, Term::K, u), t.compensated.readoffs.K.valid));
  const pipeline::ModelAnalysis& m = t.compensated_model;
  if (m.ok)
    fmt::print(out, "               model sigma_n {:.4g} {}  sigma_mu {:.4g} {}/s  ({} samples; AV residual {:.3f})\n",
               m.random_walk.sigma_n, u.name, m.random_walk.sigma_mu, u.name, m.samples,
               m.random_walk_residual.rms_log);
  else
    fmt::print(out, "               model not fitted: {}\n", m.error);
  if (m.gm_ok)
    fmt::print(out,
               "               Gauss-Markov sigma_b {:.4g} {}  T_c {:.4g} s  sigma_n {:.4g} {}  (AV residual {:.3f})\n",
               m.gauss_markov.sigma_b, u.name, m.gauss_markov.tau_c, m.gauss_markov.sigma_n, u.name,
               m.gauss_markov_residual.rms_log);
  else
    fmt::print(out, "               Gauss-Markov not fitted: {}\n", m.gm_error);
}

// The spectral view (--psd): N, B, K of the spectrum's power-law fit, each
// with its difference from the five-term fit above in combined sigmas.
void print_spectral(std::ostream& out, const pipeline::ChannelAnalysis& c) {
  const pipeline::SpectralAnalysis& s = *c.spectral;
  if (s.fit.terms.empty()) {
    fmt::print(out, "  spectrum  no power-law fit: {}\n", s.fit_error.empty() ? "not made" : s.fit_error);
    return;
  }
  std::string line;
  for (const pipeline::TermViews& v : pipeline::compare_views(c.noise.fit, s)) {
    if (v.term == Term::Q) continue;
    const char* name = v.term == Term::N ? "N" : v.term == Term::B ? "B" : "K";
    line += fmt::format("{}{} {}", line.empty() ? "" : "   ", name,
                        pm(display(v.spectrum, v.term, c.unit), v.spectrum.valid));
    if (v.difference_sigmas) line += fmt::format(" ({:+.1f} sigma)", *v.difference_sigmas);
  }
  fmt::print(out,
             "  spectrum  {}\n            (PSD power-law fit over {:.3g}–{:.3g} Hz; in parentheses: minus the "
             "5-term fit, in combined sigmas)\n",
             line, s.fit.f_lo, s.fit.f_hi);
}

// The composite model (--composite) beside the two sensor models: its terms
// in quoted units (with the bootstrap's sigma when made), how it was chosen,
// and its residual on the same Allan curve.
void print_composite(std::ostream& out, const pipeline::ModelAnalysis& m, const pipeline::AnalysisResult& r) {
  const pipeline::ModelChannel& c = *m.composite;
  const bool sd = r.composite && r.composite->bootstrap > 0 && c.replicates >= 2;
  std::string terms;
  for (const pipeline::ModelTerm& t : c.terms)
    for (const pipeline::ModelQuantity& q : t.quantities)
      // The bootstrap's sigma when made, else the sandwich one (a for asymptotic).
      terms +=
          fmt::format("{}{} {}", terms.empty() ? "" : "   ", q.name,
                      sd ? fmt::format("{:.4g} ± {:.2g} {}", q.display.value, q.display.sigma, q.display.unit)
                      : std::isfinite(q.display_asymptotic_sd)
                          ? fmt::format("{:.4g} ± {:.2g}a {}", q.display.value, q.display_asymptotic_sd, q.display.unit)
                          : fmt::format("{:.4g} {}", q.display.value, q.display.unit));
  std::string chosen = "as asked";
  if (c.fidelity) {
    // The twin: its search, and how close its curve lies to the measured one.
    chosen = fmt::format(
        "twin: {} models searched{}; twin error {:.1f} % to 10 s, {:.1f} % to 100 s, {:.1f} % at "
        "{:.4g} s, {} of {} taus inside the intervals{}",
        c.candidates.size(), c.lines.empty() ? std::string() : fmt::format(", {} spectral line(s)", c.lines.size()),
        100.0 * m.twin_error.max_error_10s, 100.0 * m.twin_error.max_error_100s, 100.0 * m.twin_error.max_error,
        m.twin_error.max_error_tau_s, m.twin_error.inside, m.twin_error.taus,
        c.faithful ? "" : "; not inside the wavelet variance's at nearly every scale");
  } else if (c.candidates.size() > 1) {
    // The selected one is the fewest parameters near the lowest WIC (noise/wic.hpp).
    const auto lowest = std::min_element(c.candidates.begin(), c.candidates.end(),
                                         [](const auto& a, const auto& b) { return a.score.wic < b.score.wic; });
    chosen = fmt::format(
        "selected by the WIC among {} candidates: WIC {:.4g}{}", c.candidates.size(), c.candidates.front().score.wic,
        lowest == c.candidates.begin() ? std::string(", the lowest")
                                       : fmt::format(", the lowest {:.4g} ({})", lowest->score.wic, lowest->model));
  }
  fmt::print(out, "  composite {} ({}; GMWM on {} samples; AV residual {:.3f}{})\n            {}{}\n", c.model, chosen,
             m.samples, m.composite_residual.rms_log,
             (m.ok || m.gm_ok) && (!m.ok || m.composite_residual.rms_log < m.random_walk_residual.rms_log) &&
                     (!m.gm_ok || m.composite_residual.rms_log < m.gauss_markov_residual.rms_log)
                 ? ", fits best of the three"
                 : "",
             terms, sd ? fmt::format("  (± bootstrap sd, {} replicates)", c.replicates) : "  (±a: asymptotic sd)");
}

void print_summary(std::ostream& out, const pipeline::AnalysisResult& r) {
  fmt::print(out, "{}: {} samples at {} Hz ({:.2f} h){}\n", r.file, r.samples, rate_text(r.rate_hz),
             r.duration_s / 3600.0, r.segments > 1 ? fmt::format(", {} segments split at gaps", r.segments) : "");
  if (r.window_bound > 0 && !r.channels.empty()) {
    const auto& st = r.channels[0].adev_strides;
    const auto strided = std::find_if(st.begin(), st.end(), [](std::size_t x) { return x > 1; });
    if (strided == st.end())
      fmt::print(out, "streamed (window bound {} samples): every Allan term summed\n", r.window_bound);
    else
      fmt::print(out, "streamed (window bound {} samples): Allan terms from AF {} on at a stride of up to {} samples\n",
                 r.window_bound, r.channels[0].noise.adev[static_cast<std::size_t>(strided - st.begin())].m, st.back());
  }
  if (!r.composite_skipped.empty()) fmt::print(out, "twin not fitted: {}\n", r.composite_skipped);
  if (!r.drift_skipped.empty()) fmt::print(out, "no bias drift: {} (--drift-window)\n", r.drift_skipped);
  for (const auto& c : r.channels) {
    const auto& ro = c.noise.readoffs;
    const auto& f = c.noise.fit;
    const Unit& u = c.unit;
    fmt::print(out, "\n{} [{}, {}]  fixed bias {:.6g} {}  std {:.4g} {}\n", c.name, u.name, to_string(u.kind), c.mean,
               u.name, c.stddev, u.name);
    const ReportedTerms rt = reported_terms(ro, f, to_allan_curve(c.noise.adev));
    if (rt.constant) {
      fmt::print(out, "  (the record is constant: every Allan deviation is zero)\n");
    } else {
      const std::string range =
          !ro.N.valid ? std::string(" (no -1/2 slope in the curve)")
          : ro.N.tau_lo <= 1.0 && 1.0 <= ro.N.tau_hi
              ? fmt::format(" (-1/2 line at tau = 1 s, read over {:.3g}–{:.3g} s)", ro.N.tau_lo, ro.N.tau_hi)
              : fmt::format(
                    " (-1/2 line of the white arm at {:.3g}–{:.3g} s, extended to tau = 1 s: the curve is "
                    "not white at 1 s)",
                    ro.N.tau_lo, ro.N.tau_hi);
      fmt::print(out, "  N         {}{}\n", reported(rt.N, Term::N, u), range);
      if (rt.no_minimum)
        fmt::print(out,
                   "  B         no minimum within the record (the curve is lowest at its {} tau, {:.3g} s): B {}\n",
                   ro.tau_min == c.noise.adev.back().tau ? "last" : "first", ro.tau_min, reported(rt.B, Term::B, u));
      else
        fmt::print(out, "  B         {}   T {:.3g} s ({:.3g}–{:.3g})\n", reported(rt.B, Term::B, u), ro.tau_min,
                   ro.tau_min_lo, ro.tau_min_hi);
      fmt::print(out, "  K         {}\n", k_line(rt, u));
    }
    fmt::print(out, "  read-off  K {}   Q {}   R {}\n", pm(display(ro.K, Term::K, u), ro.K.valid),
               pm(display(ro.Q, Term::Q, u), ro.Q.valid), pm(display(ro.R, Term::R, u), ro.R.valid));
    fmt::print(out, "  5-term fit  white {}   B {}   K {}   Q {}   R {}   (rms residual {:.1f} %)\n",
               pm(display(f.N, Term::N, u), f.N.valid), pm(display(f.B, Term::B, u), f.B.valid),
               pm(display(f.K, Term::K, u), f.K.valid), pm(display(f.Q, Term::Q, u), f.Q.valid),
               pm(display(f.R, Term::R, u), f.R.valid), 100.0 * f.rms_rel_residual);
    print_accelerometer_terms(out, c.noise, rt, u);
    print_bias_verdict(out, c.noise, u);
    if (c.model.ok)
      fmt::print(
          out, "  model     sigma_n {:.4g} {}  sigma_mu {:.4g} {}/s  (paper eq. 1-3; {} samples; AV residual {:.3f})\n",
          c.model.random_walk.sigma_n, u.name, c.model.random_walk.sigma_mu, u.name, c.model.samples,
          c.model.random_walk_residual.rms_log);
    else
      fmt::print(out, "  model     not fitted: {}\n", c.model.error);
    if (!c.model.gm_ok) fmt::print(out, "  Gauss-Markov not fitted: {}\n", c.model.gm_error);
    if (c.model.gm_ok)
      fmt::print(out, "  Gauss-Markov sigma_b {:.4g} {}  T_c {:.4g} s  sigma_n {:.4g} {}  (AV residual {:.3f}{})\n",
                 c.model.gauss_markov.sigma_b, u.name, c.model.gauss_markov.tau_c, c.model.gauss_markov.sigma_n, u.name,
                 c.model.gauss_markov_residual.rms_log,
                 c.model.ok && c.model.gauss_markov_residual.rms_log < c.model.random_walk_residual.rms_log
                     ? ", fits better"
                     : "");
    if (c.model.composite) print_composite(out, c.model, r);
    if (r.twin_check)
      for (const pipeline::TwinCheckChannel& t : r.twin_check->channels)
        if (t.name == c.name)
          fmt::print(out,
                     "  twin check {} twins of {} samples: mean curve vs measured, worst {:.1f} % to 10 s, {:.1f} % to "
                     "100 s, {:.1f} % at {:.4g} s overall\n",
                     r.twin_check->twins, r.twin_check->samples, 100.0 * t.max_error_10s, 100.0 * t.max_error_100s,
                     100.0 * t.max_error, t.max_error_tau_s);
    if (c.spectral) print_spectral(out, c);
    if (c.temperature) print_temperature(out, *c.temperature, u);
  }
  if (r.covariance.rows() > 1) {
    fmt::print(out, "\ncovariance of the first {} samples:\n", r.cov_samples);
    fmt::print(out, "{:>10}", "");
    for (const auto& n : r.cov_names) fmt::print(out, " {:>12}", n);
    out << '\n';
    for (std::size_t a = 0; a < r.covariance.rows(); ++a) {
      fmt::print(out, "{:>10}", r.cov_names[a]);
      for (double v : r.covariance.row(a)) fmt::print(out, " {:>12.4e}", v);
      out << '\n';
    }
  }
}

// The record read whole (io::read_series), then pipeline::run_analyze.
pipeline::AnalysisResult analyze_in_memory(AnalyzeOptions& o, io::SeriesOptions so, pipeline::AnalyzeRequest req) {
  const std::size_t bytes = file_size_or_zero(o.input.file);
  Progress progress(bytes > 50'000'000);
  progress.stage(fmt::format("reading {} ({:.0f} MB)", o.input.file, static_cast<double>(bytes) / 1e6));
  so.keep_time = false;  // one segment's stamps carry nothing the analysis uses beyond the rate
  so.max_inflated_bytes = memory_budget(o.memory);  // a gzip file's text within --memory
  StageTimer reading(o.timings.sink(), Stage::read);
  const io::Series series = io::read_series(o.input.file, so);
  reading.stop();
  ChannelUnits units = units_for(o.unit, series);  // a column without a unit stops here
  note_default_columns(series);
  if (!units.note.empty()) std::cerr << units.note << '\n';
  req.units = std::move(units.units);
  progress.stage(fmt::format("analyzing {} channels", series.channels.size()));
  req.times = o.timings.sink();
  // A composite model the GMWM cannot fit is a calibration error on the file.
  pipeline::AnalysisResult r = with_calibration_hints(series.file, {CalibrationCommand::composite},
                                                      [&] { return pipeline::run_analyze(series, req); });
  progress.done();
  return r;
}

// The record read in pieces (io::SampleStream), then
// pipeline::run_analyze_stream: one pass, two with a temperature (the file
// is opened again).
pipeline::AnalysisResult analyze_streamed(const AnalyzeOptions& o, const io::SeriesOptions& so,
                                          pipeline::AnalyzeRequest req, std::size_t budget) {
  const bool file = o.input.file != "-";
  pipeline::check_analyze_streamable(req, file);  // before the input is opened
  const auto input = io::SampleStream::open(o.input.file, so);
  io::Series header;  // the names the units come from
  header.file = input->file();
  header.names = input->names();
  header.default_columns = input->default_columns();
  header.left_out = input->left_out();
  if (io::looks_like_recording(o.input.file))
    if (const io::RecordingManifest m = io::read_manifest(o.input.file); m.unit) {
      header.units.assign(header.names.size(), *m.unit);  // as the whole read gives them
      header.units_from = "the recording's manifest";
    }
  ChannelUnits units = units_for(o.unit, header);
  note_default_columns(header);
  if (!units.note.empty()) std::cerr << units.note << '\n';
  req.units = std::move(units.units);
  const std::size_t bound = stream_window(o.memory, budget, input->names().size(), estimated_samples(o.input.file, so));
  pipeline::ReopenStream reopen;
  if (file) reopen = [&] { return io::SampleStream::open(o.input.file, so); };
  Progress progress(true);
  progress.stage(fmt::format("analyzing {} channel(s), streamed{}", input->names().size(),
                             req.temp_index ? " (two passes: the temperature)" : ""));
  req.progress = [&](double f) {
    if (input->total_bytes() > 0)
      progress.fraction(f);
    else
      progress.count(static_cast<double>(input->rows_read()), "samples");
  };
  pipeline::AnalysisResult r = pipeline::run_analyze_stream(*input, req, bound, reopen);
  progress.done();
  return r;
}

// The request of the command line (the options the reading adds aside).
pipeline::AnalyzeRequest analyze_request(const AnalyzeOptions& o) {
  pipeline::AnalyzeRequest req;
  if (!o.unit.empty()) req.units = parse_units(o.unit);  // before the reading: a typo fails at once
  req.grid = parse_taus(o.taus);
  if (!(o.ci > 0.0 && o.ci < 1.0)) throw UsageError("--ci must be between 0 and 1");
  req.ci = o.ci;
  req.temp_order = o.temp_order;
  req.drift_window_s = o.drift_window;
  req.cov_samples = o.cov_samples;
  req.max_samples = o.max_samples;
  for (const auto& v : split_list(o.model_lsb)) {
    double x = 0.0;
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || p != v.data() + v.size() || !(x >= 0.0) || !std::isfinite(x))
      throw UsageError("--model-lsb: '" + v + "' is not a number of counts per unit");
    req.lsb.push_back(x);
  }
  req.threads = o.input.threads;
  req.psd = o.psd;
  req.twin_check = o.twin_check;
  if (o.composite_given && o.composite == "none") {
    req.composite.reset();
  } else if (o.composite_given) {
    pipeline::ModelRequest m;
    m.model = o.composite.empty() ? "auto" : o.composite;
    req.composite_required = true;
    // A selection scores its candidates by the WIC's asymptotic optimism:
    // seconds, where the bootstrap's takes a minute per channel of a 72 h
    // record (`cubecal model --wic-replicates` has the bootstrap).
    m.selection_replicates = 0;
    // A typo fails before the reading, named as the option it came from.
    try {
      if (!pipeline::is_twin(m.model)) (void)parse_candidate_models(m.model);
    } catch (const UsageError& e) {
      if (e.field() != Field::model) throw;
      throw UsageError(Field::composite, marker(Field::composite) + ": " + e.text(), UsageError::Named::in_text);
    }
    if (o.composite_bootstrap == 1) throw UsageError("--composite-bootstrap: give 0 (none) or at least 2 replicates");
    m.bootstrap = o.composite_bootstrap;
    req.composite = std::move(m);
  }

  return req;
}

// Whether to stream a record that was not asked to be: when reading it
// whole would exceed the budget (a pipe's size is not known: --stream).
bool stream_beyond_budget(const AnalyzeOptions& o, const io::SeriesOptions& so, std::size_t budget) {
  // Streamed by itself when reading the file whole would exceed the budget
  // (a pipe's size is not known: --stream).
  const std::size_t need = in_memory_bytes(o.input.file, so);
  const std::string recording_warning = recording_beyond_budget(o.input.file, need, budget);
  if (!recording_warning.empty()) {
    std::cerr << recording_warning;
  } else if (need > budget) {
    std::cerr << fmt::format(
        "cubecal: note: reading {} whole would take about {:.0f} MB, more than the "
        "memory budget ({:.0f} MB, --memory): streaming it\n",
        o.input.file, static_cast<double>(need) / 1e6, static_cast<double>(budget) / 1e6);
    return true;
  }
  return false;
}

// The result on the standard output, and the files and report in --out.
void write_analysis_output(AnalyzeOptions& o, const pipeline::AnalysisResult& r, const pipeline::OutputContext& ctx) {
  StageTimer writing(o.timings.sink(), Stage::output);
  if (o.format == "json")
    std::cout << pipeline::analysis_json(r, ctx);
  else
    print_summary(std::cout, r);

  if (!o.out.empty()) {
    std::string list;
    for (const auto& f : write_analysis_files(o.out, r, ctx)) list += (list.empty() ? "" : ", ") + f;
    std::cerr << "cubecal: wrote " << list << " in " << o.out << '\n';
    if (o.report) {
      report::ReportOptions ro;
      ro.force = true;  // existing report files were refused above unless --force
      ro.gnuplot = o.gnuplot;
      const auto rep = report::write_report(r, {ctx.command, {}}, o.out, ro);
      std::cerr << "cubecal: wrote " << rep.html_path << " (" << rep.plots.size() << " plots in "
                << (std::filesystem::path(o.out) / "plots/").string() << ")\n";
    }
  }
  writing.stop();
}

int run_analyze_command(AnalyzeOptions& o) {
  pipeline::AnalyzeRequest req = analyze_request(o);
  io::SeriesOptions so = to_series_options(o.input);
  // The quantizer follows --lsb column by column; a column at 1 count per
  // unit (the default: values already in units) has none.
  const bool scaled = std::any_of(so.lsb.begin(), so.lsb.end(), [](double x) { return x != 1.0; });
  if (req.lsb.empty() && scaled)
    for (const double x : so.lsb) req.lsb.push_back(x == 1.0 ? 0.0 : x);
  if (!o.temp_col.empty()) {
    so.table.extra_columns.push_back(o.temp_col);
    req.temp_index = 0;
  }

  pipeline::OutputContext ctx{invocation(), o.rostopic, parse_estimators(o.estimators), o.inflate};
  if (!ctx.estimators.empty() && !req.units.empty()) pipeline::require_imu_units(req.units);
  for (const pipeline::Estimator e : ctx.estimators)
    if (pipeline::is_simulator(e) && !req.composite)
      throw UsageError("--for " + std::string(pipeline::estimator_name(e)) +
                       ": a simulator's noise model is the projection of each channel's twin; leave out "
                       "--composite none");

  // A request a stream cannot take (--psd) refused before --out is made.
  if (o.memory.stream) pipeline::check_analyze_streamable(req, o.input.file != "-");
  // Every output checked (and --out created) before any time is spent.
  if (o.report && !report::find_gnuplot(o.gnuplot)) report::throw_gnuplot_missing(o.gnuplot);
  if (!o.out.empty()) {
    std::vector<std::string> files = pipeline::analysis_file_names(ctx.estimators);
    if (o.report) files.insert(files.end(), {"report.html", "plots"});
    io::prepare_output_dir(o.out, o.force, files);
  }

  const std::size_t budget = memory_budget(o.memory);
  const bool stream = o.memory.stream || stream_beyond_budget(o, so, budget);
  const pipeline::AnalysisResult r = stream ? analyze_streamed(o, so, req, budget) : analyze_in_memory(o, so, req);
  for (const std::string& line :
       {excluded_taus_warning(r.tau_list, r.model_excluded_taus), merged_taus_note(r.tau_list)})
    if (!line.empty()) std::cerr << line << '\n';

  write_analysis_output(o, r, ctx);
  print_timings(o.timings, req.threads);
  return 0;
}

}  // namespace

CLI::App* add_analyze_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<AnalyzeOptions>();
  CLI::App* cmd =
      app.add_subcommand("analyze",
                         "Static characterization: noise terms (N, B, T, K, Q, R) with uncertainties, the paper's "
                         "sensor model and a Gauss-Markov alternative, bias drift, covariance, temperature");
  add_input_options(*cmd, opt->input);
  cmd->add_option("--unit", opt->unit, unit_option_help());
  cmd->add_option("--temp-col", opt->temp_col, "Temperature column (degC): regress each channel on it");
  cmd->add_option("--temp-order", opt->temp_order, "Polynomial order of the temperature fit")
      ->check(CLI::Range(1, 5))
      ->capture_default_str();
  cmd->add_option("--drift-window", opt->drift_window,
                  "Moving-average window of the bias drift in seconds (default 300 s for rate sensors, "
                  "1000 s otherwise, as the paper); from one sample period to the record's length (the longest "
                  "part without a gap)")
      ->check(positive_number());
  cmd->add_option("--cov-samples", opt->cov_samples, "Covariance from the first N samples (default all)")
      ->check(whole_number(2, 1e15));
  cmd->add_option("--max-samples", opt->max_samples,
                  "Fit the sensor model on the first N samples (the paper used 42000)")
      ->check(whole_number(3, 1e15));
  cmd->add_option("--model-lsb", opt->model_lsb,
                  "Quantizer of the model in counts per unit, one for all columns or one per column "
                  "(default: --lsb, column by column; none for a column at 1), eq. (3)");
  cmd->add_option("--taus", opt->taus, "Tau grid of the Allan curve")->capture_default_str();
  cmd->add_option("--ci", opt->ci, "Confidence factor of the intervals")
      ->check(number_between(0.0, 1.0))
      ->capture_default_str();
  CLI::Option* out_opt = cmd->add_option(
      "--out", opt->out, "Directory for analysis.json, adev.csv, drift.csv, (gyro) imu.yaml and the --for files");
  cmd->add_flag("--force", opt->force, "Replace files in --out");
  cmd->add_flag("--report", opt->report, "Also write --out/report.html with its plots (as `cubecal report`)")
      ->needs(out_opt);
  cmd->add_flag("--psd", opt->psd,
                "Also the spectral view: each channel's power spectral density as `cubecal psd` makes it (Welch, "
                "its defaults), its power-law fit and the N, B, K it stands for beside the Allan curve's, with "
                "their difference in combined sigmas (analysis.json \"spectral\", a table and a plot in the "
                "report; about 0.1 s more per channel of 2.6 million samples; not with --stream)");
  CLI::Option* composite =
      cmd->add_option("--composite", opt->composite,
                      "The composite noise model beside the paper's and the Gauss-Markov model, fitted by the "
                      "GMWM as `cubecal model` does, on the samples the models are fitted on. Default: twin, each "
                      "channel's twin (WN or MA1, QN, RW, DR, Gauss-Markov terms and the lines of its spectrum, "
                      "docs/twins.md; left out with the reason for a record cut at gaps, too short or streamed); "
                      "MODEL (\"WN+GM+RW\"), candidates joined by commas, or, bare or \"auto\", selected by the WIC "
                      "among the default candidates; none: no composite model. Given, it is required (not with "
                      "--stream)")
          ->expected(0, 1);
  cmd->add_option("--twin-check", opt->twin_check,
                  "Simulate K twins of every channel at the record's length and print (and plot in the report) "
                  "their mean Allan deviation against the measured one, with the worst error to 10 s and 100 s "
                  "(analysis.json twin_check; seeds 1..K)")
      ->check(whole_number(0, 10000))
      ->capture_default_str();
  cmd->add_option("--composite-bootstrap", opt->composite_bootstrap,
                  "Parametric-bootstrap replicates of the composite model's uncertainties (0: none)")
      ->check(whole_number(0, 100000))
      ->needs(composite)
      ->capture_default_str();
  add_gnuplot_option(*cmd, opt->gnuplot);
  add_memory_options(*cmd, opt->memory);
  add_timings_option(*cmd, opt->timings);
  cmd->add_option("--format", opt->format, "Standard output: table or json")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  cmd->add_option("--rostopic", opt->rostopic, "rostopic written to imu.yaml and kalibr_imu_chain.yaml")
      ->capture_default_str();
  cmd->add_option("--for", opt->estimators,
                  "Also write the noise parameters in an estimator's format into --out: " +
                      pipeline::estimator_names() + " (comma list or repeated)")
      ->delimiter(',')
      ->needs(out_opt);
  cmd->add_option("--inflate", opt->inflate,
                  "Multiply the noise densities, random walks and bias terms of the estimator files by K >= 1")
      ->check(number_between(1.0, 1e6))
      ->needs(out_opt)
      ->capture_default_str();
  cmd->callback([opt, composite, &run] {
    opt->composite_given = composite->count() > 0;
    run = [opt] { return run_analyze_command(*opt); };
  });
  return cmd;
}

}  // namespace cubecal::cli
