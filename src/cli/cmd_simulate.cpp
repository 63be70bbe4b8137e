// cubecal simulate: records from sensor models, in the layout the readers
// take (t, axes..., temp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <string_view>
#include <sstream>

#include <unistd.h>

#include "commands.hpp"
#include "common_options.hpp"
#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"
#include "cubecal/io/output_path.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/pipeline/analysis_json.hpp"
#include "cubecal/pipeline/model_fit_json.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/pipeline/simulate_size.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/acquire/frame_spec.hpp"
#include "frame_encoder.hpp"
#include "paced_output.hpp"
#include "progress.hpp"

namespace cubecal::cli {

namespace {

struct SimulateOptions {
  std::string presets;
  std::string model_file;
  std::string bias = "twin";
  bool bias_given = false;  // --bias on the command line (a model.json takes composite without it)
  double rate_hz = 10.0;
  bool rate_given = false;  // --rate on the command line (else: the model's rate, or 10 Hz)
  std::string duration = "1h";
  std::uint64_t seed = 1;
  std::string temp = "sine:25,5";
  std::string true_input;
  std::string flicker;  // --flicker B[,B...]: bias instability as flicker FM, per triad
  std::string out;
  std::string format = "csv";
  bool force = false;
  bool realtime = false;  // --realtime: paced at the rate, to the standard output
  std::string frame;      // --frame SPEC: binary frames (with --realtime)
};

std::vector<double> numbers(const std::string& list, const std::string& what) {
  std::vector<double> v;
  for (const auto& item : split_list(list)) {
    double x = 0.0;
    const auto [p, ec] = std::from_chars(item.data(), item.data() + item.size(), x);
    if (ec != std::errc() || p != item.data() + item.size() || !std::isfinite(x))
      throw UsageError(what + ": '" + item + "' is not a number");
    v.push_back(x);
  }
  return v;
}

// const:T | sine:MEAN,AMPLITUDE[,PERIOD_S] | FILE (a temperature column, one
// value per sample, held at its last value).
TemperatureProfile parse_temperature(const std::string& spec) {
  TemperatureProfile p;
  if (spec.rfind("const:", 0) == 0) {
    const auto v = numbers(spec.substr(6), "--temp const");
    if (v.size() != 1) throw UsageError("--temp const:T takes one temperature in degC");
    p.kind = TemperatureProfile::Kind::constant;
    p.mean = v[0];
  } else if (spec.rfind("sine:", 0) == 0) {
    const auto v = numbers(spec.substr(5), "--temp sine");
    if (v.size() < 2 || v.size() > 3) throw UsageError("--temp sine:MEAN,AMPLITUDE[,PERIOD_S]");
    p.kind = TemperatureProfile::Kind::sinusoid;
    p.mean = v[0];
    p.amplitude = v[1];
    if (v.size() == 3) {
      if (!(v[2] > 0)) throw UsageError("--temp sine: the period must be positive");
      p.period_s = v[2];
    }
  } else {
    io::SeriesOptions so;
    so.rate_hz = 1.0;             // one value per sample; the time stamps, if any, are not used
    so.skip_temperature = false;  // the file is read for its temperature column
    so.check_rate_against_time = false;
    so.min_samples = 1;
    const auto s = io::read_series(spec, so);
    p.kind = TemperatureProfile::Kind::series;
    p.values = s.channels.at(0);
  }
  return p;
}

pipeline::RateProfile read_rate_profile(const std::string& path) {
  io::SeriesOptions so;  // needs a time column (t, time, t_s...) and 3 rate columns
  so.min_samples = 1;
  const auto s = io::read_series(path, so);
  if (s.time.empty() || s.channels.size() != 3)
    throw UsageError(path +
                     ": a true-input profile needs a time column and three rate columns "
                     "(e.g. t,wx,wy,wz in the gyro's unit)");
  pipeline::RateProfile p;
  p.t = s.time;
  for (int a = 0; a < 3; ++a) p.w[a] = s.channels[a];
  return p;
}

// Largest record written without --force: 2 GB of text, or the value of the
// environment variable CUBECAL_SIMULATE_MAX_BYTES.
double max_output_bytes() {
  if (const char* v = std::getenv("CUBECAL_SIMULATE_MAX_BYTES")) {
    char* end = nullptr;
    const double b = std::strtod(v, &end);
    if (end != v && *end == '\0' && b >= 0.0) return b;
  }
  return 2e9;
}

std::string format_bytes(double b) {
  if (b >= 1e12) return fmt::format("{:.3g} TB", b / 1e12);
  if (b >= 1e9) return fmt::format("{:.3g} GB", b / 1e9);
  if (b >= 1e6) return fmt::format("{:.3g} MB", b / 1e6);
  return fmt::format("{:.0f} kB", std::ceil(b / 1e3));
}

// Raw float64 little-endian frames (the channels in channel_names order, no
// time column), block by block: to a file through NAME.partial, or to the
// standard output for `cubecal dev - --binary float64le,... --stream`.
int write_raw(const pipeline::SimulateRequest& req_in, const SimulateOptions& o, std::size_t n, double bytes,
              std::size_t columns) {
  pipeline::SimulateRequest req = req_in;
  const bool to_stdout = o.out == "-";
  std::optional<io::AtomicFile> file;
  if (!to_stdout) {
    io::check_output_file(o.out, o.force);
    file.emplace(o.out);
    if (!file->is_open())
      throw UsageError("cannot write " + o.out + " (check that the directory exists and is writable)");
  }
  Progress progress(!to_stdout && n > 1'000'000, !to_stdout && bytes > 500e6);
  progress.stage(fmt::format("simulating {} samples into {} (about {})", n, o.out, format_bytes(bytes)));
  req.progress = [&](double fr) { progress.fraction(fr); };
  static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);
  std::vector<double> swapped;
  try {
    pipeline::simulate_blocks(req, [&](std::size_t, std::span<const double> frames) {
      const double* p = frames.data();
      if constexpr (std::endian::native == std::endian::big) {
        swapped.resize(frames.size());
        for (std::size_t i = 0; i < frames.size(); ++i)
          swapped[i] = std::bit_cast<double>(__builtin_bswap64(std::bit_cast<std::uint64_t>(frames[i])));
        p = swapped.data();
      }
      const bool written =
          to_stdout ? std::fwrite(p, sizeof(double), frames.size(), stdout) == frames.size()
                    : file->write(std::string_view(reinterpret_cast<const char*>(p), frames.size() * sizeof(double)));
      if (!written)
        throw UsageError(to_stdout ? "could not write the standard output (closed pipe?)"
                                   : "could not write " + o.out + " (disk full?)");
    });
  } catch (...) {
    if (file) file->discard();
    throw;
  }
  if (to_stdout) {
    if (std::fflush(stdout) != 0) throw UsageError("could not write the standard output");
  } else {
    if (!file->commit()) throw UsageError("could not finish writing " + o.out + " (disk full?)");
  }
  progress.done();
  std::string types;
  for (std::size_t c = 0; c < columns; ++c) types += c ? ",float64le" : "float64le";
  std::cerr << fmt::format(
      "cubecal: wrote {} ({} samples at {:g} Hz, {} float64le columns {}, seed {}; read "
      "it with --binary {} --rate {:g})\n",
      to_stdout ? "the standard output" : o.out, n, req.rate_hz, columns, fmt::join(pipeline::channel_names(req), ","),
      o.seed, types, req.rate_hz);
  return 0;
}

// --realtime: the samples on the standard output as a sensor would send
// them, each at its time (t0 + k / rate): CSV text with its header,
// float64le frames (--format raw) or the binary frames of --frame. A reader
// that closes the pipe ends the run (exit 0, said on stderr).
int write_realtime(const pipeline::SimulateRequest& req, const SimulateOptions& o, std::size_t n) {
  const bool raw = o.format == "raw";
  const std::size_t columns = pipeline::channel_names(req).size();
  std::optional<FrameEncoder> frames_of;
  std::vector<double> with_time(columns + 1);
  if (!o.frame.empty()) {
    std::vector<std::string> names{"t"};
    for (const auto& name : pipeline::channel_names(req)) names.push_back(name);
    frames_of.emplace(acquire::parse_frame_spec(o.frame), names);
  }
  PacedOutput out(STDOUT_FILENO, req.rate_hz);
  if (!raw && !frames_of) {
    std::string header = "t";
    for (const auto& name : pipeline::channel_names(req)) header += "," + name;
    out.write_now(header + "\n");
  }
  const double dt = 1.0 / req.rate_hz;
  std::string line;
  char tmp[32];
  struct ReaderGone {};
  try {
    pipeline::simulate_blocks(req, [&](std::size_t k0, std::span<const double> frames) {
      const std::size_t len = frames.size() / columns;
      for (std::size_t j = 0; j < len; ++j) {
        const double* row = frames.data() + j * columns;
        line.clear();
        if (frames_of) {
          with_time[0] = static_cast<double>(k0 + j) * dt;
          std::copy(row, row + columns, with_time.begin() + 1);
          frames_of->encode(with_time, line);
        } else if (raw) {
          for (std::size_t c = 0; c < columns; ++c) {
            std::uint64_t bits = std::bit_cast<std::uint64_t>(row[c]);
            if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap64(bits);
            line.append(reinterpret_cast<const char*>(&bits), sizeof bits);
          }
        } else {
          auto r =
              std::to_chars(tmp, tmp + sizeof tmp, static_cast<double>(k0 + j) * dt, std::chars_format::general, 9);
          line.append(tmp, r.ptr);
          for (std::size_t c = 0; c < columns; ++c) {
            r = std::to_chars(tmp, tmp + sizeof tmp, row[c], std::chars_format::general, 9);
            line += ',';
            line.append(tmp, r.ptr);
          }
          line += '\n';
        }
        if (!out.sample(k0 + j, line)) throw ReaderGone{};
      }
      // The block's last samples out before the next block is generated.
      if (!out.finish()) throw ReaderGone{};
    });
  } catch (const ReaderGone&) {
  }
  if (!out.reader_gone()) out.finish();
  if (out.reader_gone()) {
    std::cerr << fmt::format(
        "cubecal: the reader of the standard output went away after {} of {} samples: "
        "stopped\n",
        out.written(), n);
    return 0;
  }
  std::cerr << fmt::format("cubecal: streamed {} samples at {:g} Hz in real time ({} {}, seed {})\n", n, req.rate_hz,
                           frames_of ? (std::string("frames ") += o.frame) += " of t and"
                                     : std::string(raw ? "float64le frames of" : "CSV lines of t and"),
                           fmt::join(pipeline::channel_names(req), ","), o.seed);
  return 0;
}

// The presets' triads, each the same sensor at --rate.
void add_preset_triads(pipeline::SimulateRequest& req, const SimulateOptions& o) {
  for (const auto& name : split_list(o.presets)) {
    try {
      // The same sensor at --rate: its N and K, not its per-sample sigmas.
      req.triads.push_back(pipeline::model_at_rate(preset(name), kPresetRateHz, o.rate_hz));
    } catch (const std::invalid_argument&) {
      std::string known;
      for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
      throw UsageError("unknown preset '" + name + "' (known: " + known + ")");
    }
  }
}

// The triads of --model: a `cubecal model` result or an analysis.json; the
// rate becomes the model's when neither --rate nor a preset sets it.
void add_model_triads(pipeline::SimulateRequest& req, const SimulateOptions& o) {
  std::ifstream in(o.model_file);
  if (!in) throw UsageError("cannot read " + o.model_file);
  std::stringstream ss;
  ss << in.rdbuf();
  // The model's parameters hold per sample at the rate it was measured
  // at; without --rate (and without presets, which then keep the default
  // 10 Hz) simulate at that rate, else convert to --rate.
  const nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, false);
  std::vector<TriadModel> models;
  if (j.is_object() && j.contains("command") && j["command"] == "model") {
    // `cubecal model --format json`: composite models only.
    if (o.bias_given && o.bias != "composite" && o.bias != "twin")
      throw UsageError("--bias: " + o.model_file +
                       " is a `cubecal model` result, which holds composite models "
                       "only (--bias composite, or leave --bias out)");
    const pipeline::ModelResult m = pipeline::model_result_from_json(j, o.model_file);
    if (!o.rate_given && req.triads.empty()) req.rate_hz = m.rate_hz;
    models = pipeline::models_from_composite(m, o.model_file, req.rate_hz);
  } else {
    const pipeline::AnalysisDocument doc = pipeline::parse_analysis_json(ss.str(), o.model_file);
    if (!o.rate_given && req.triads.empty()) req.rate_hz = doc.result.rate_hz;
    // The twin by default; an analysis without one (written before it, or
    // of a record that could not carry it) gives the paper's model, said so.
    const bool has_twin =
        !doc.result.channels.empty() && std::all_of(doc.result.channels.begin(), doc.result.channels.end(),
                                                    [](const auto& ch) { return ch.model.composite.has_value(); });
    std::string bias = o.bias;
    if (bias == "twin" && !o.bias_given && !has_twin) {
      bias = "random-walk";
      fmt::print(stderr, "cubecal: note: {} holds no twin ({}); simulating the paper's random-walk model\n",
                 o.model_file,
                 doc.result.composite_skipped.empty() ? std::string("analyze it again to fit one")
                                                      : doc.result.composite_skipped);
    }
    models = bias == "composite" || bias == "twin"
                 ? pipeline::models_from_composite(doc.result, o.model_file, req.rate_hz)
                 : pipeline::models_from_analysis(doc.result, o.model_file, bias == "gauss-markov", req.rate_hz);
  }
  for (auto& m : models) req.triads.push_back(std::move(m));
}

// --flicker: bias instability as flicker FM on every axis of a triad.
void add_flicker(pipeline::SimulateRequest& req, const SimulateOptions& o) {
  // Bias instability as flicker FM on every axis of a triad (Kasdin &
  // Walter's generator): one B for all triads or one per triad, in each
  // triad's unit.
  const auto b = numbers(o.flicker, "--flicker");
  if (b.size() != 1 && b.size() != req.triads.size())
    throw UsageError("--flicker: give one bias instability B for all triads or one per triad (" +
                     std::to_string(req.triads.size()) + ")");
  for (std::size_t k = 0; k < req.triads.size(); ++k) {
    const double bk = b.size() == 1 ? b[0] : b[k];
    if (!(bk >= 0.0)) throw UsageError("--flicker: B must be 0 or more");
    for (auto& axis : req.triads[k].axes) axis.power_law.push_back(flicker_term(bk));
  }
}

// The record written to --out (a file or the standard output), as text
// or raw frames.
int write_record_output(pipeline::SimulateRequest& req, const SimulateOptions& o) {
  // Refuse a record no one meant to ask for before any work (and before
  // sample_count, which an absurd duration would overflow).
  const bool raw = o.format == "raw";
  const std::size_t columns = pipeline::channel_names(req).size();
  const double bytes =
      raw ? req.duration_s * req.rate_hz * 8.0 * static_cast<double>(columns) : pipeline::estimated_text_bytes(req);
  if (bytes > max_output_bytes() && !o.force)
    throw UsageError(fmt::format(
        "the record would be about {} of {} ({:.3g} samples x {} columns): add --force to write "
        "it anyway, or shorten --duration or lower --rate",
        format_bytes(bytes), raw ? "float64" : "text", req.duration_s * req.rate_hz, raw ? columns : columns + 1));
  const std::size_t n = pipeline::sample_count(req);
  if (n < 1) throw UsageError("--duration shorter than one sample period");
  const bool to_stdout = o.out == "-";
  if (raw) return write_raw(req, o, n, bytes, columns);

  io::CsvWriter w(o.out, o.force);
  // Into a pipe the reader's progress is the one to show.
  Progress progress(!to_stdout && n > 1'000'000, !to_stdout && bytes > 500e6);
  progress.stage(fmt::format("simulating {} samples into {} (about {})", n, o.out, format_bytes(bytes)));
  req.progress = [&](double f) { progress.fraction(f); };
  write_simulation(req, w);
  w.commit();
  progress.done();
  std::cerr << fmt::format("cubecal: wrote {} ({} samples at {:g} Hz, {} columns, seed {})\n",
                           to_stdout ? "the standard output" : o.out, n, req.rate_hz,
                           pipeline::channel_names(req).size() + 1, o.seed);
  return 0;
}

int run_simulate(const SimulateOptions& o) {
  pipeline::SimulateRequest req;
  if (!(o.rate_hz > 0.0) || !std::isfinite(o.rate_hz)) throw UsageError("--rate must be positive");
  add_preset_triads(req, o);
  req.rate_hz = o.rate_hz;
  if (!o.model_file.empty()) add_model_triads(req, o);
  if (req.triads.empty()) throw UsageError("nothing to simulate: give --preset and/or --model");
  if (!o.frame.empty() && !o.realtime)
    throw UsageError("--frame streams binary frames with --realtime: add --realtime --out -, or leave out --frame");
  if (!o.flicker.empty()) add_flicker(req, o);
  req.duration_s = pipeline::parse_duration(o.duration);
  req.seed = o.seed;
  req.temperature = parse_temperature(o.temp);
  if (!o.true_input.empty()) req.true_input = read_rate_profile(o.true_input);
  if (o.realtime) {
    // Nothing is stored: no size limit.
    if (o.out != "-") throw UsageError("--realtime streams to the standard output: give --out -");
    if (!o.frame.empty() && o.format == "raw")
      throw UsageError("--frame: binary frames of their own; leave out --format raw");
    const std::size_t n = pipeline::sample_count(req);
    if (n < 1) throw UsageError("--duration shorter than one sample period");
    return write_realtime(req, o, n);
  }
  return write_record_output(req, o);
}

}  // namespace

CLI::App* add_simulate_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<SimulateOptions>();
  std::string presets;
  for (const auto& n : preset_names()) presets += (presets.empty() ? "" : ", ") + n;
  CLI::App* cmd =
      app.add_subcommand("simulate",
                         "Simulate sensor records from presets (the paper's gyro and magnetometer) or from an "
                         "analyze result: white noise, bias random walk or Gauss-Markov, turn-on bias, "
                         "temperature, scale factor, quantization; or a composite noise model (analyze --composite, "
                         "cubecal model)");
  cmd->add_option("--preset", opt->presets, "Comma-separated presets: " + presets);
  cmd->add_option("--model", opt->model_file,
                  "analysis.json from cubecal analyze: simulate the measured sensor; or the JSON of cubecal model "
                  "(--format json): simulate its composite models");
  CLI::Option* bias =
      cmd->add_option("--bias", opt->bias,
                      "Noise model taken from --model: twin (the default: the composite model analyze fits to "
                      "every channel, each term in its discrete-time form at --rate, with the analysis's fixed bias, "
                      "quantizer and temperature coefficients; an analysis without one gives random-walk, said so; "
                      "composite is the same; the only one of a cubecal model result), random-walk (the paper's) "
                      "or gauss-markov")
          ->check(CLI::IsMember({"twin", "random-walk", "gauss-markov", "composite"}))
          ->capture_default_str();
  CLI::Option* rate = cmd->add_option("--rate", opt->rate_hz,
                                      "Sampling rate in Hz (default: the rate of --model, else 10 Hz); a model is "
                                      "rescaled to it, keeping its N and K")
                          ->check(number_between(io::kMinRateHz, io::kMaxRateHz))
                          ->capture_default_str();
  cmd->add_option("--flicker", opt->flicker,
                  "Add bias instability B as flicker noise (a flicker floor of 0.664 B in the Allan deviation) to "
                  "every axis: one B for all triads or one per triad, in the triad's unit (Kasdin & Walter's "
                  "generator; its 1/f reaches 2^18 samples back)");
  cmd->add_option("--duration", opt->duration, "Record length: 72h, 30m, 3600s, 2d")->capture_default_str();
  cmd->add_option("--seed", opt->seed, "Random seed (same seed, same bytes)")
      ->check(whole_number(0, 1e18))
      ->capture_default_str();
  cmd->add_option("--temp", opt->temp,
                  "Temperature profile: const:T, sine:MEAN,AMPLITUDE[,PERIOD_S] (default period one day) "
                  "or a file with one temperature per sample")
      ->capture_default_str();
  cmd->add_option("--true-input", opt->true_input,
                  "Rate profile for the gyro (CSV: t and three rates), held between its time stamps");
  cmd->add_option("--out", opt->out, "Output file (.csv, or .csv.gz for gzip); - for the standard output")->required();
  cmd->add_option("--format", opt->format,
                  "csv (a time column and the channels) or raw (float64le frames of the channels, no time "
                  "column: read back with --binary float64le,... --rate)")
      ->check(CLI::IsMember({"csv", "raw"}))
      ->capture_default_str();
  cmd->add_flag("--realtime", opt->realtime,
                "Stream the samples at the model's rate, each at its time from the start (with --out -): a stand-in "
                "for a sensor, e.g. `simulate ... --realtime --out - | cubecal record - --out DIR`");
  cmd->add_option("--frame", opt->frame,
                  "With --realtime: binary frames as cubecal record --frame reads them, e.g. "
                  "'sync=A55A;fields=t:f64,gx:f32,gy:f32,gz:f32;checksum=crc16' (fields named after t and the "
                  "channels; integer fields take the value rounded)");
  cmd->add_flag("--force", opt->force, "Replace --out if it exists, and write a record larger than 2 GB of text");
  cmd->callback([opt, rate, bias, &run] {
    opt->rate_given = rate->count() > 0;
    opt->bias_given = bias->count() > 0;
    run = [opt] { return run_simulate(*opt); };
  });
  return cmd;
}

}  // namespace cubecal::cli
