// cubecal record: crash-safe acquisition of a sensor's stream (a serial
// device, a TCP server, UDP datagrams or a pipe) into a recording directory
// (docs/record.md) that the analysis commands read as a record.
#include <fmt/format.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "record_targets.hpp"
#include "cubecal/acquire/frame_spec.hpp"
#include "cubecal/acquire/recorder.hpp"
#include "cubecal/acquire/source.hpp"
#include "cubecal/acquire/write_failure.hpp"
#include "cubecal/error.hpp"
#include "cubecal/pipeline/simulate.hpp"
#include "cubecal/printable_text.hpp"
#include "cubecal/stats/streaming_deviation.hpp"

namespace cubecal::cli {

namespace {

struct RecordCliOptions {
  std::string source;
  std::string out;
  int baud = 115200;
  std::vector<std::string> columns;
  std::string time_col;
  std::optional<double> rate;
  std::string unit;
  std::string delimiter;
  std::string frame;
  std::string duration;
  double chunk_seconds = 600.0;
  std::size_t chunk_bytes = std::size_t{64} << 20;
  bool live = false;
  bool quiet = false;
  std::string target;  // --target: the live status (record_targets.hpp)
  double ci = 0.683;
  std::string status_every = "120s";
  bool stop_when_met = false;
};

volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int) { g_stop = 1; }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a wait is interrupted and the loop sees the flag
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  ::sigaction(SIGHUP, &sa, nullptr);
  // A file-size limit makes write() fail with EFBIG (reported) instead of
  // killing the recorder; a closed socket is a read error, not a signal.
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGPIPE, SIG_IGN);
}

std::string clock_text(double s) {
  const auto t = static_cast<long long>(s);
  return fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60);
}

std::string bytes_text(double b) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (b >= 1024.0 && u < 4) {
    b /= 1024.0;
    ++u;
  }
  return fmt::format("{:.1f} {}", b, units[u]);
}

double free_bytes(const std::string& dir) {
  struct statvfs st {};
  if (::statvfs(dir.c_str(), &st) != 0) return -1;
  return static_cast<double>(st.f_bavail) * static_cast<double>(st.f_frsize);
}

// The running OADEV of every data channel at a few taus, for --live.
class LiveDeviation {
 public:
  LiveDeviation(const std::vector<std::string>& names, std::optional<std::string> time_column) {
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (time_column && names[i] == *time_column) continue;
      channels_.push_back(i);
      names_.push_back(names[i]);
      devs_.emplace_back(Stat::oadev, std::span<const std::size_t>(kFactors), 1024);
    }
  }
  void push(std::span<const double> values) {
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      const double v = values[channels_[c]];
      devs_[c].push(std::span<const double>(&v, 1));
    }
  }
  // "OADEV gx: 1s 1.2e-3  10s 4.0e-4 ..." per channel.
  std::vector<std::string> lines(double rate_hz) const {
    std::vector<std::string> out;
    if (!(rate_hz > 0)) return out;
    StabilityOptions so;
    so.intervals = false;
    for (std::size_t c = 0; c < devs_.size() && c < 6; ++c) {
      StreamingDeviation copy = devs_[c];
      const auto r = copy.finish(1.0 / rate_hz, so);
      std::string s = fmt::format("OADEV {:>8}:", names_[c]);
      for (const auto& p : r.points) s += fmt::format("  {:.3g}s {:.3e}", p.tau, p.dev);
      if (r.points.empty()) s += "  (too few samples yet)";
      out.push_back(s);
    }
    return out;
  }

 private:
  static constexpr std::size_t kFactors[] = {1, 10, 100, 1000, 10000};
  std::vector<std::size_t> channels_;
  std::vector<std::string> names_;
  std::vector<StreamingDeviation> devs_;
};

// The recorder's options from the command line (the callbacks aside).
acquire::RecorderOptions recorder_options(const RecordCliOptions& o) {
  acquire::RecorderOptions ro;
  ro.out_dir = o.out;
  while (ro.out_dir.size() > 1 && ro.out_dir.back() == '/') ro.out_dir.pop_back();
  if (!o.frame.empty()) {
    if (!o.delimiter.empty() || !o.columns.empty())
      throw UsageError("--frame names its fields: --delimiter and --columns are for text lines");
    ro.frame = acquire::parse_frame_spec(o.frame);
  }
  ro.text.columns = o.columns;
  if (!o.delimiter.empty()) {
    const std::string& d = o.delimiter;
    if (d == "," || d == "comma")
      ro.text.delimiter = ',';
    else if (d == ";" || d == "semicolon")
      ro.text.delimiter = ';';
    else if (d == "\t" || d == "\\t" || d == "tab")
      ro.text.delimiter = '\t';
    else if (d == " " || d == "space" || d == "whitespace")
      ro.text.delimiter = ' ';
    else
      throw UsageError("--delimiter is one of , ; tab space");
  }
  ro.time_col = o.time_col;
  ro.rate_hz = o.rate;
  if (!o.unit.empty()) ro.unit = o.unit;
  if (!o.duration.empty()) {
    ro.duration_s = pipeline::parse_duration(o.duration);
    if (!(ro.duration_s > 0)) throw UsageError("--duration must be positive (72h, 90m, 10s)");
  }
  ro.chunk_seconds = o.chunk_seconds;
  ro.chunk_bytes = o.chunk_bytes;

  return ro;
}

// The status block on a terminal: the status line and, with --live, the
// OADEV lines of the samples so far, redrawn in place.
struct StatusBlock {
  double requested = 0.0;
  std::string out_dir;
  std::unique_ptr<LiveDeviation>& live;
  acquire::Recorder*& recorder_ptr;
  const TargetWatch* targets = nullptr;
  std::vector<std::string> live_lines;
  double last_live = 0.0;
  std::size_t drawn_lines = 0;  // status lines drawn below the cursor's line

  void draw(const acquire::RecorderStatus& st) {
    std::string line =
        fmt::format("{}{}  {:.0f} samples/s  {} samples  rejected {}  gaps {}  resets {}", clock_text(st.elapsed_s),
                    requested > 0 ? " / " + clock_text(requested) : std::string(), st.samples_per_s, st.samples,
                    st.rejects, st.gaps, st.resets);
    if (st.reconnects > 0) line += fmt::format("  reconnects {}", st.reconnects);
    if (!st.last.empty()) {
      line += "  last";
      for (std::size_t i = 0; i < st.last.size() && i < 6; ++i) line += fmt::format(" {:.6g}", st.last[i]);
      if (st.last.size() > 6) line += " ...";
    }
    const double fb = free_bytes(out_dir);
    if (fb >= 0) line += "  free " + bytes_text(fb);
    if (const std::string t = targets != nullptr ? targets->line() : std::string(); !t.empty()) line += "  " + t;
    if (live && st.elapsed_s - last_live >= 5.0) {
      const double rate = recorder_ptr->manifest().rate_hz.value_or(
          st.device_rate_hz > 0 ? st.device_rate_hz
                                : (st.elapsed_s > 0 ? static_cast<double>(st.samples) / st.elapsed_s : 0.0));
      live_lines = live->lines(rate);
      last_live = st.elapsed_s;
    }
    // Redraw: back to the first line of the block, clear to the end.
    std::string out;
    if (drawn_lines > 0) out += fmt::format("\r\x1b[{}A", drawn_lines);
    out += "\r\x1b[J" + printable_text(line);
    for (const auto& l : live_lines) out += "\n" + printable_text(l);
    drawn_lines = live_lines.size();
    std::fputs(out.c_str(), stderr);
    std::fflush(stderr);
  }
};

// What the recording did, on stderr; the command's exit status.
int report_record_end(const acquire::RecorderSummary& sum, const std::string& out_dir, const TargetWatch* targets) {
  std::string met;
  if (targets != nullptr && targets->stopped_met())
    met = fmt::format("targets met at {} samples ({} recorded)", targets->met_at_samples(),
                      clock_text(targets->met_at_record_s()));
  const char* why = !met.empty()                              ? met.c_str()
                    : sum.end == acquire::RecordEnd::duration ? "duration reached"
                    : sum.end == acquire::RecordEnd::stopped  ? "stopped"
                                                              : "source ended";
  if (sum.segment_dir.empty() && sum.unrecorded_rejects > 0) {
    std::string first = sum.first_unrecorded_data.substr(0, 80);
    std::fprintf(stderr,
                 "cubecal: error: record: %s after %.1f s: no data line or frame arrived, so nothing was recorded in "
                 "%s; %zu piece(s) of input were not data, the first (%s): '%s'; check --baud, --delimiter, "
                 "--columns or --frame\n",
                 why, sum.status.elapsed_s, out_dir.c_str(), sum.unrecorded_rejects,
                 printable_text(sum.first_unrecorded_reason).c_str(), printable_text(first).c_str());
    return 2;
  }
  if (sum.segment_dir.empty()) {
    // No sample, nothing recorded: an error, as when only non-data arrived.
    std::fprintf(stderr,
                 "cubecal: error: record: %s after %.1f s: %s, so nothing was recorded in %s; check the source\n", why,
                 sum.status.elapsed_s,
                 sum.layout_known ? "the layout (a header line) arrived but no data line or frame" : "no input arrived",
                 printable_text(out_dir).c_str());
    return 2;
  }
  std::fprintf(stderr,
               "cubecal: record: %s after %s: %zu samples (%.1f/s) in %zu chunk(s) of %s, %s; %zu rejected, "
               "%zu gap(s), %zu reset(s)%s\n",
               why, clock_text(sum.status.elapsed_s).c_str(), sum.status.samples, sum.status.samples_per_s, sum.chunks,
               printable_text(sum.segment_dir).c_str(), bytes_text(static_cast<double>(sum.status.bytes)).c_str(),
               sum.status.rejects, sum.status.gaps, sum.status.resets,
               sum.status.reconnects > 0 ? fmt::format(", {} reconnect(s)", sum.status.reconnects).c_str() : "");
  return 0;
}

int run_record_command(const RecordCliOptions& o) {
  acquire::RecorderOptions ro = recorder_options(o);
  const RecordTargets rt = parse_record_targets(o.target, o.ci, o.status_every, o.stop_when_met);

  const bool tty = ::isatty(STDERR_FILENO) != 0 && !o.quiet;
  install_signal_handlers();
  ro.stop = &g_stop;
  ro.on_notice = [](const std::string& s) { std::fprintf(stderr, "cubecal: %s\n", printable_text(s).c_str()); };

  acquire::SourceOptions so;
  so.baud = o.baud;
  std::unique_ptr<acquire::Source> source = acquire::open_source(o.source, so);

  std::unique_ptr<LiveDeviation> live;
  const double requested = ro.duration_s;
  const std::string out_dir = ro.out_dir;
  acquire::Recorder* recorder_ptr = nullptr;
  std::unique_ptr<TargetWatch> watch;
  if (!rt.targets.empty())
    watch = std::make_unique<TargetWatch>(rt, out_dir, &g_stop, [&recorder_ptr] { recorder_ptr->flush(); });
  if (o.live || watch) {
    ro.on_sample = [&live, &recorder_ptr, &watch, want_live = o.live](std::span<const double> v) {
      const auto& m = recorder_ptr->manifest();
      if (want_live) {
        if (!live) live = std::make_unique<LiveDeviation>(m.columns, m.time_column);
        live->push(v);
      }
      if (watch) watch->on_sample(v, m);
    };
  }
  StatusBlock status{requested, out_dir, live, recorder_ptr, watch.get(), {}, 0.0, 0};
  if (tty) ro.on_status = [&status](const acquire::RecorderStatus& st) { status.draw(st); };

  acquire::Recorder recorder(*source, std::move(ro));
  recorder_ptr = &recorder;
  acquire::RecorderSummary sum;
  try {
    sum = recorder.run();
  } catch (const acquire::WriteFailure& e) {
    if (tty) std::fputs("\n", stderr);
    std::fprintf(stderr,
                 "cubecal: error: %s; the chunks before it are intact and the manifest describes what was "
                 "synced; free space or raise the limit, then run again with the same --out to append a segment\n",
                 printable_text(e.what()).c_str());
    return 2;
  }
  if (tty) std::fputs("\n", stderr);
  if (watch && !sum.segment_dir.empty()) watch->finish(recorder.manifest());
  if (watch)
    for (const auto& n : watch->take_notices()) std::fprintf(stderr, "cubecal: %s\n", printable_text(n).c_str());
  return report_record_end(sum, out_dir, watch.get());
}

}  // namespace

CLI::App* add_record_command(CLI::App& app, Command& run) {
  auto opt = std::make_shared<RecordCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "record",
      "Record a sensor's stream (serial device, TCP, UDP or a pipe) into a crash-safe recording directory: "
      "CSV chunks fsync'd every half second, a manifest replaced atomically; a restart appends a segment");
  cmd->add_option("source", opt->source,
                  "- (standard input), tcp:HOST:PORT (connect to a server), udp:PORT (listen on 127.0.0.1), "
                  "udp:ADDRESS:PORT (listen on a local address; udp:0.0.0.0:PORT on every interface) or a serial "
                  "device (/dev/ttyUSB0)")
      ->required();
  cmd->add_option("--out", opt->out, "The recording directory (created; an existing recording gets a new segment)")
      ->required();
  cmd->add_option("--baud", opt->baud, "Serial devices: the baud rate (8N1, no flow control)")->capture_default_str();
  cmd->add_option("--columns", opt->columns, "Text: the names of the fields of each line (else the header line's)")
      ->delimiter(',');
  cmd->add_option("--time-col", opt->time_col,
                  "The device's time column (name or 1-based index), checked for gaps and resets; default: a "
                  "column named t, time, timestamp, ...");
  cmd->add_option("--rate", opt->rate, "The sampling rate in Hz (else the device time or the host stamps decide)");
  cmd->add_option("--unit", opt->unit, "The unit of the data columns (deg/s, rad/s, m/s^2, ...), kept in the manifest");
  cmd->add_option("--delimiter", opt->delimiter, "Text: the field delimiter (, ; tab space); default: detected");
  cmd->add_option("--frame", opt->frame,
                  "Binary frames: 'sync=A55A;fields=t:u32,gx:i16,gy:i16,gz:i16;checksum=xor8;endian=le' "
                  "(types u8..i64 f32 f64; checksums none xor8 sum8 crc16 crc32)");
  cmd->add_option("--duration", opt->duration,
                  "Stop after this long: 72h, 90m, 10s (default: until the source ends or Ctrl-C)");
  cmd->add_option("--chunk-seconds", opt->chunk_seconds, "Start a new chunk file after this many seconds")
      ->check(CLI::Validator(
          [](const std::string& v) -> std::string {
            double x = 0;
            try {
              x = std::stod(v);
            } catch (const std::exception&) {
              return "not a number of seconds: " + printable_text(v);
            }
            return x > 0 && std::isfinite(x) ? std::string() : "a positive number of seconds, not " + printable_text(v);
          },
          "SECONDS > 0"))
      ->capture_default_str();
  cmd->add_option("--chunk-bytes", opt->chunk_bytes, "Start a new chunk file after this many bytes")
      ->check(CLI::Range(std::size_t{4096}, std::size_t{1} << 40))
      ->capture_default_str();
  cmd->add_flag("--live", opt->live, "On a terminal: the running OADEV at a few taus, updated every 5 s");
  cmd->add_flag("--quiet", opt->quiet, "No status line, even on a terminal");
  cmd->add_option("--target", opt->target,
                  "Precision targets, e.g. B:10%,K:20% (terms Q N B K R T; relative half-width at --ci): every "
                  "--status-every of recorded time, DIR/status.json gets each channel's terms, their precision, "
                  "whether each target holds and the time still needed (cubecal status DIR shows it)");
  cmd->add_option("--ci", opt->ci, "With --target: the confidence of the precisions (0.683: 1 sigma)")
      ->capture_default_str();
  cmd->add_option("--status-every", opt->status_every,
                  "With --target: recorded time between two statuses (120s, 5m, 1h); also at the end")
      ->capture_default_str();
  cmd->add_flag("--stop-when-met", opt->stop_when_met,
                "With --target: end the run cleanly at the first status where every target holds");
  cmd->callback([opt, &run] { run = [opt] { return run_record_command(*opt); }; });
  return cmd;
}

}  // namespace cubecal::cli
