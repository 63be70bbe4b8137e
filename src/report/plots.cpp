// Plot descriptions to .dat + .gp files, rendered to SVG and PNG by gnuplot
// run as child processes (several at once).
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <thread>

#include "cubecal/error.hpp"
#include "cubecal/io/atomic_file.hpp"
#include "cubecal/report/plot.hpp"

extern char** environ;

namespace cubecal::report {

namespace fs = std::filesystem;

namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

// A gnuplot single-quoted string: only ' is special (doubled). Newlines end
// a command, so they become spaces.
std::string gp_quote(std::string_view s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "''";
    else if (c == '\n' || c == '\r')
      q += ' ';
    else
      q += c;
  }
  return q + "'";
}

// One line of a comment: no newline may end it early.
std::string comment(std::string_view s) {
  std::string c = "# ";
  for (char ch : s) c += (ch == '\n' || ch == '\r') ? ' ' : ch;
  return c + "\n";
}

bool valid_name(const std::string& n) {
  return !n.empty() && std::all_of(n.begin(), n.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

bool has_data(const PlotSeries& s) { return !s.x.empty(); }

std::string describe(const PlotSeries& s) {
  if (!s.id.empty()) return s.id;
  if (!s.label.empty()) return s.label;
  return "(no legend)";
}

// Series written as x y lo hi (error bars, or the edges of a band).
bool has_bars(const PlotSeries& s) {
  return s.mark == Mark::errorlines || s.mark == Mark::errorbars || s.mark == Mark::band;
}

// The range of a log axis when none is given: the finite positive values of
// the data (error bounds included), widened to whole decades.
std::optional<std::pair<double, double>> log_range(const Plot& p, bool x_axis) {
  double lo = INFINITY, hi = -INFINITY;
  auto take = [&](double v) {
    if (std::isfinite(v) && v > 0) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  };
  for (const auto& s : p.series) {
    if (!s.scale) continue;
    if (x_axis) {
      for (double v : s.x) take(v);
    } else {
      for (double v : s.y) take(v);
      if (has_bars(s)) {
        for (double v : s.lo) take(v);
        for (double v : s.hi) take(v);
      }
    }
  }
  if (!(lo <= hi)) return std::nullopt;
  const double a = std::pow(10.0, std::floor(std::log10(lo) + 1e-9));
  double b = std::pow(10.0, std::ceil(std::log10(hi) - 1e-9));
  if (b <= a) b = a * 10.0;
  return std::make_pair(a, b);
}

void axis_commands(std::string& s, const Plot& p, const PlotAxis& a, const char* name) {
  const std::string n = name;
  s += "set " + n + "label " + gp_quote(a.label) + " noenhanced\n";
  std::optional<double> lo = a.min, hi = a.max;
  if (a.log) {
    s += "set logscale " + n + " 10\n";
    s += "set format " + n + " '10^{%L}'\n";
    if (!lo || !hi) {
      if (const auto r = log_range(p, n == "x")) {
        if (!lo) lo = r->first;
        if (!hi) hi = r->second;
      }
    }
  }
  if (lo || hi) s += "set " + n + "range [" + (lo ? num(*lo) : "*") + ":" + (hi ? num(*hi) : "*") + "]\n";
}

std::string rgb(const PlotSeries& s) {
  // gnuplot's #AARRGGBB: AA is the transparency (00 opaque).
  std::string c = s.color.size() == 7 && s.color[0] == '#' ? s.color.substr(1) : std::string("000000");
  const double op = std::clamp(s.opacity, 0.0, 1.0);
  if (op >= 1.0) return "'#" + c + "'";
  char aa[3];
  std::snprintf(aa, sizeof aa, "%02x", static_cast<unsigned>(std::lround((1.0 - op) * 255.0)));
  return "'#" + std::string(aa) + c + "'";
}

const char* dash_type(Dash d) {
  switch (d) {
    case Dash::solid: return "1";
    case Dash::dashed: return "(9,6)";
    case Dash::dotted: return "(2,4)";
    case Dash::dash_dot: return "(9,4,2,4)";
  }
  return "1";
}

const char* with_clause(Mark m) {
  switch (m) {
    case Mark::line: return "lines";
    case Mark::points: return "points";
    case Mark::errorlines: return "yerrorlines";
    case Mark::errorbars: return "yerrorbars";
    case Mark::band: return "filledcurves";
  }
  return "lines";
}

}  // namespace

std::string plot_data(const Plot& plot) {
  std::string s = comment(plot.title.empty() ? plot.name : plot.title);
  s += "# written by cubecal; one block per series, selected in " + plot.name + ".gp with `index K`\n";
  for (const auto& n : plot.notes) s += comment(n);
  std::size_t block = 0;
  for (const auto& ser : plot.series) {
    if (!has_data(ser)) continue;
    if (block > 0) s += "\n\n";
    s += "# index " + std::to_string(block) + ": " + describe(ser) + "\n";
    const bool bars = has_bars(ser);
    s += bars ? "# x y lo hi\n" : "# x y\n";
    for (std::size_t i = 0; i < ser.x.size(); ++i) {
      s += num(ser.x[i]);
      s += ' ';
      s += num(i < ser.y.size() ? ser.y[i] : NAN);
      if (bars) {
        s += ' ';
        s += num(i < ser.lo.size() ? ser.lo[i] : NAN);
        s += ' ';
        s += num(i < ser.hi.size() ? ser.hi[i] : NAN);
      }
      s += '\n';
    }
    ++block;
  }
  return s;
}

std::string gnuplot_script(const Plot& plot) {
  const std::string& n = plot.name;
  std::string s;
  s += comment(plot.title.empty() ? n : plot.title);
  s += "#\n";
  s += "# Written by cubecal. Restyle freely (line styles first, then labels, ranges\n";
  s += "# and the plot command) and re-render from this directory:\n";
  s += "#     gnuplot " + n + ".gp        writes " + n + ".svg and " + n + ".png\n";
  s += face_words("# To put the restyled plot into report.html: cubecal report DIR {force} {keep_scripts}\n");
  s += "# Data: " + n + ".dat, one block per series (index 0, 1, ...): x y [lo hi].\n";
  for (const auto& note : plot.notes) s += comment(note);
  s += "\nset encoding utf8\n";
  s += "\n# ---- line styles, one per series\n";
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const auto& ser = plot.series[k];
    char w[64];
    std::snprintf(w, sizeof w, " lw %.3g pt 7 ps %.3g", ser.width, ser.point_size);
    s += "set style line " + std::to_string(k + 1) + " lc rgb " + rgb(ser) + w + " dt " + dash_type(ser.dash) + "   " +
         comment(describe(ser));
  }
  s += "\n# ---- frame\n";
  s += "set title " + gp_quote(plot.title) + " noenhanced\n";
  axis_commands(s, plot, plot.x, "x");
  axis_commands(s, plot, plot.y, "y");
  s += "set grid xtics ytics mxtics mytics lt 1 lw 0.6 lc rgb '#d9d9d9', lt 1 lw 0.4 lc rgb '#eeeeee'\n";
  s += "set border lc rgb '#333333'\n";
  s += "set key " + plot.key + " spacing 1.1\n";
  s += "set bars small\n";
  s += "set clip two\n";
  s += "set datafile missing 'NaN'\n";
  if (plot.equal_axes) s += "set size ratio -1\n";
  if (plot.x_tics && *plot.x_tics > 0 && !plot.x.log) s += "set xtics " + num(*plot.x_tics) + "\n";

  std::string cmd = "plot";
  std::size_t block = 0;
  bool first = true;
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const auto& ser = plot.series[k];
    cmd += first ? " \\\n  " : ", \\\n  ";
    first = false;
    const std::string style = " ls " + std::to_string(k + 1);
    const std::string title =
        ser.label.empty() ? std::string(" notitle") : " title " + gp_quote(ser.label) + " noenhanced";
    // A band is filled in its line colour (whose alpha carries the opacity), without an outline.
    const std::string fill = ser.mark == Mark::band ? " fs solid 1.0 noborder" : "";
    if (!has_data(ser)) {
      cmd += std::string("keyentry with ") +
             (ser.mark == Mark::points ? "points"
              : ser.mark == Mark::band ? "filledcurves"
                                       : "lines") +
             style + fill + title;
      continue;
    }
    const char* columns = ser.mark == Mark::band ? "1:3:4" : has_bars(ser) ? "1:2:3:4" : "1:2";
    cmd += (block == 0 ? gp_quote(n + ".dat") : std::string("''")) + " index " + std::to_string(block) + " using " +
           columns + " with " + with_clause(ser.mark) + style + fill + title;
    ++block;
  }
  char size[48];
  std::snprintf(size, sizeof size, "size %d,%d", plot.width, plot.height);
  s += "\n# ---- SVG (embedded in report.html)\n";
  s += std::string("set terminal svg ") + size + " dynamic enhanced font 'sans,12' background rgb 'white'\n";
  s += "set output " + gp_quote(n + ".svg") + "\n";
  s += cmd + "\n";
  s += "set output\n";
  s += "\n# ---- PNG (cairo when this gnuplot has it)\n";
  s += "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n";
  s += std::string("  set terminal pngcairo ") + size + " enhanced font 'sans,11' background rgb 'white'\n";
  s += "} else {\n";
  s += std::string("  set terminal png ") + size + " enhanced background rgb 'white'\n";
  s += "}\n";
  s += "set output " + gp_quote(n + ".png") + "\n";
  s += "replot\n";
  s += "set output\n";
  return s;
}

std::optional<std::string> find_gnuplot(const std::string& explicit_path) {
  const std::string name = explicit_path.empty() ? std::string("gnuplot") : explicit_path;
  auto executable = [](const std::string& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
  };
  if (name.find('/') != std::string::npos) {
    if (executable(name)) return name;
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::string_view rest = path ? path : "/usr/local/bin:/usr/bin:/bin";
  while (true) {
    const auto colon = rest.find(':');
    const std::string_view d = rest.substr(0, colon);
    const std::string cand = (fs::path(d.empty() ? std::string_view(".") : d) / name).string();
    if (executable(cand)) return cand;
    if (colon == std::string_view::npos) break;
    rest.remove_prefix(colon + 1);
  }
  return std::nullopt;
}

std::string gnuplot_missing(const std::string& explicit_path) {
  if (explicit_path.empty()) return kGnuplotMissing;
  return "no executable gnuplot at " + explicit_path +
         " (give the path of the gnuplot program, or leave the option out to use gnuplot on PATH)";
}

void throw_gnuplot_missing(const std::string& explicit_path) {
  if (explicit_path.empty()) throw UsageError(kGnuplotMissing);
  throw UsageError(Field::gnuplot, gnuplot_missing(explicit_path));
}

void decimate_minmax(std::vector<double>& x, std::vector<double>& y, std::size_t max_points) {
  const std::size_t n = std::min(x.size(), y.size());
  if (max_points < 2 || n <= max_points) return;
  const std::size_t buckets = max_points / 2;
  std::vector<double> ox, oy;
  ox.reserve(max_points);
  oy.reserve(max_points);
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t i0 = b * n / buckets, i1 = (b + 1) * n / buckets;
    if (i0 >= i1) continue;
    std::size_t lo = i0, hi = i0;
    for (std::size_t i = i0; i < i1; ++i) {
      if (y[i] < y[lo]) lo = i;
      if (y[i] > y[hi]) hi = i;
    }
    const std::size_t a = std::min(lo, hi), c = std::max(lo, hi);
    ox.push_back(x[a]);
    oy.push_back(y[a]);
    if (c != a) {
      ox.push_back(x[c]);
      oy.push_back(y[c]);
    }
  }
  x = std::move(ox);
  y = std::move(oy);
}

namespace {

void write_text(const fs::path& p, const std::string& text) { io::write_file(p.string(), text); }

// A plot's files are replaced only when they are regular files: a link, a
// FIFO or a device of one of their names is refused, never removed.
void check_plot_file(const fs::path& p) {
  std::string why;
  const io::OutputTarget t = io::classify_output(p.string(), &why);
  if (t == io::OutputTarget::stream)
    why = p.string() + " is not a regular file: a plot's files are replaced only when they are; remove it";
  if (t == io::OutputTarget::refused || t == io::OutputTarget::stream) throw UsageError(why);
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The last two non-empty lines gnuplot wrote: where and what went wrong.
std::string gnuplot_complaint(const std::string& log) {
  std::vector<std::string> lines;
  std::istringstream in(log);
  for (std::string l; std::getline(in, l);) {
    while (!l.empty() && (l.back() == '\r' || l.back() == ' ' || l.back() == '^')) l.pop_back();
    const auto first = l.find_first_not_of(' ');
    if (first != std::string::npos) lines.push_back(l.substr(first));
  }
  if (lines.empty()) return "no message";
  std::string m = lines.back();
  if (lines.size() >= 2) m = lines[lines.size() - 2] + ": " + m;
  return m;
}

struct Job {
  std::size_t index;
  pid_t pid = -1;
};

pid_t spawn_gnuplot(const std::string& gnuplot, const fs::path& dir, const std::string& name) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  const std::string log = (dir / (name + ".log")).string();
  posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW, 0644);
  // cd first: the script names its files relative to its own directory, so
  // that `gnuplot NAME.gp` run there by a user does the same.
  const std::string cd = "cd " + gp_quote(dir.string());
  const std::string script = (dir / (name + ".gp")).string();
  std::vector<std::string> args{gnuplot, "-e", cd, script};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, gnuplot.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw UsageError("cannot run " + gnuplot + ": " + std::strerror(rc));
  return pid;
}

}  // namespace

std::vector<RenderedPlot> render_plots(const std::vector<Plot>& plots, const fs::path& dir_in,
                                       const RenderOptions& options) {
  const auto gnuplot = find_gnuplot(options.gnuplot);
  if (!gnuplot) throw_gnuplot_missing(options.gnuplot);
  std::error_code ec;
  fs::create_directories(dir_in, ec);
  if (ec) throw UsageError("cannot create " + dir_in.string() + ": " + ec.message());
  const fs::path dir = fs::absolute(dir_in);

  std::vector<RenderedPlot> out;
  for (const auto& p : plots) {
    if (!valid_name(p.name))
      throw std::invalid_argument("plot name '" + p.name + "' (letters, digits, '_' and '-' only)");
    for (const auto& r : out)
      if (r.name == p.name) throw std::invalid_argument("two plots named '" + p.name + "'");
    RenderedPlot r;
    r.name = p.name;
    r.title = p.title;
    r.dat = dir / (p.name + ".dat");
    r.gp = dir / (p.name + ".gp");
    r.svg = dir / (p.name + ".svg");
    r.png = dir / (p.name + ".png");
    r.width = p.width;
    r.height = p.height;
    const bool keep_gp = options.keep_scripts && fs::exists(r.gp);
    for (const fs::path& f : {r.dat, r.svg, r.png, dir / (p.name + ".log")}) check_plot_file(f);
    if (!keep_gp) check_plot_file(r.gp);
    write_text(r.dat, plot_data(p));
    if (!keep_gp) write_text(r.gp, gnuplot_script(p));
    fs::remove(r.svg, ec);
    fs::remove(r.png, ec);
    out.push_back(std::move(r));
  }

  // Run them, a few at a time.
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t jobs = std::max<std::size_t>(1, options.jobs ? options.jobs : hw);
  std::vector<std::string> failures;
  std::vector<Job> running;
  std::size_t next = 0;
  auto reap = [&](Job j) {
    int status = 0;
    while (::waitpid(j.pid, &status, 0) < 0 && errno == EINTR) {
    }
    const RenderedPlot& r = out[j.index];
    const fs::path log = dir / (r.name + ".log");
    const bool ran = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    const bool wrote = fs::exists(r.svg) && fs::file_size(r.svg) > 0 && fs::exists(r.png) && fs::file_size(r.png) > 0;
    if (ran && wrote) {
      fs::remove(log, ec);
    } else if (ran) {
      failures.push_back(r.gp.string() + " ran but did not write " + r.name + ".svg and " + r.name +
                         ".png (keep its `set output` lines)");
    } else {
      failures.push_back("gnuplot failed on " + r.gp.string() + ": " + gnuplot_complaint(read_text(log)) +
                         " (all of its output: " + log.string() + ")");
    }
  };
  while (next < out.size() || !running.empty()) {
    while (next < out.size() && running.size() < jobs) {
      try {
        running.push_back({next, spawn_gnuplot(*gnuplot, dir, out[next].name)});
      } catch (...) {
        for (const Job& j : running) reap(j);
        throw;
      }
      ++next;
    }
    Job j = running.front();
    running.erase(running.begin());
    reap(j);
  }
  if (!failures.empty()) throw UsageError(failures.front());
  for (auto& r : out) r.svg_text = read_text(r.svg);
  return out;
}

}  // namespace cubecal::report
