/// @file
/// Plots as data: a small description (title, axes, series with a style)
/// that cubecal renders with gnuplot. Every plot leaves three files a user can
/// keep working with, side by side in one directory:
///   NAME.dat   the numbers, one block per series (gnuplot `index K`)
///   NAME.gp    a readable gnuplot script: line styles first, then the plot;
///              `gnuplot NAME.gp` run in that directory writes the two images
///   NAME.svg   (for the HTML report) and NAME.png (for slides and papers)
/// Any command that wants a figure builds a Plot and calls render_plots().
#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cubecal::report {

/// The dash pattern of a line.
enum class Dash { solid, dashed, dotted, dash_dot };

/// How a series is drawn.
enum class Mark {
  line,        ///< x, y joined
  points,      ///< x, y as marks
  errorlines,  ///< x, y joined, with y error bars from lo..hi
  errorbars,   ///< x, y as marks, with y error bars from lo..hi
  band,        ///< the area between lo and hi over x, filled in the colour at `opacity` (y unused)
};

/// One series of a plot: its data and how it is drawn.
struct PlotSeries {
  /// Legend text (plain text: never interpreted as gnuplot markup); empty:
  /// not in the legend. A series without data is a legend entry only.
  std::string label;
  std::string id;  ///< names the series in the .gp and .dat comments (default: label)
  /// The points, in the axes' units.
  ///@{
  std::vector<double> x, y;
  ///@}
  /// error bar bounds (errorlines, errorbars), or the band's edges
  ///@{
  std::vector<double> lo, hi;
  ///@}
  /// How the series is drawn.
  Mark mark = Mark::line;
  /// The dash pattern of its line.
  Dash dash = Dash::solid;
  std::string color = "#1f77b4";  ///< `#RRGGBB`
  double opacity = 1.0;           ///< 0..1
  double width = 1.5;             ///< line width, gnuplot units
  /// Size of its marks, gnuplot units.
  double point_size = 0.4;
  bool scale = true;  ///< counts for the automatic range of a log axis
};

/// One axis of a plot.
struct PlotAxis {
  std::string label;  ///< plain text (UTF-8)
  /// True for a logarithmic axis.
  bool log = false;
  /// fixed range; autoscaled otherwise
  ///@{
  std::optional<double> min, max;
  ///@}
};

/// A plot as data: axes, series and size; rendered by gnuplot.
struct Plot {
  std::string name;   ///< file stem: letters, digits, '_', '-'
  std::string title;  ///< plain text
  /// The x and y axes.
  ///@{
  PlotAxis x, y;
  ///@}
  /// The series, drawn in order.
  std::vector<PlotSeries> series;
  std::string key = "outside right top";  ///< gnuplot `set key` arguments
  std::vector<std::string> notes;         ///< comment lines at the top of the .gp and .dat
  /// pixels
  ///@{
  int width = 900, height = 600;
  ///@}
  bool equal_axes = false;       ///< one unit as long on x as on y (`set size ratio -1`)
  std::optional<double> x_tics;  ///< spacing of the major x tics (linear x axis); automatic otherwise
};

/// The text of NAME.dat and NAME.gp for `plot` (deterministic).
std::string plot_data(const Plot& plot);
/// The text of NAME.gp for `plot` (deterministic). Throws nothing beyond std::bad_alloc.
std::string gnuplot_script(const Plot& plot);

/// How plots are rendered.
struct RenderOptions {
  std::string gnuplot;        ///< executable; empty: `gnuplot` on PATH
  bool keep_scripts = false;  ///< an existing NAME.gp is run as it is (a user's restyled script)
  unsigned jobs = 0;          ///< gnuplot processes at once (0: hardware threads)
};

/// A plot rendered to files.
struct RenderedPlot {
  /// The plot's file stem.
  std::string name;
  /// The plot's title.
  std::string title;
  /// The files written: data, script, SVG and PNG.
  ///@{
  std::filesystem::path dat, gp, svg, png;
  ///@}
  /// Size, pixels.
  ///@{
  int width = 900, height = 600;
  ///@}
  std::string svg_text;  ///< the SVG document gnuplot wrote
};

/// The gnuplot executable: `explicit_path` when it names an executable file,
/// else `gnuplot` on PATH; nullopt when there is none.
std::optional<std::string> find_gnuplot(const std::string& explicit_path = {});

/// The one-line message for a missing gnuplot.
inline constexpr const char* kGnuplotMissing = "gnuplot not found: install gnuplot-nox (scripts/install-deps.sh)";

/// The message when find_gnuplot(explicit_path) finds none: kGnuplotMissing
/// when no path was given, else one naming the path.
std::string gnuplot_missing(const std::string& explicit_path);
/// Throws UsageError(gnuplot_missing(explicit_path)), naming the option
/// "gnuplot" when a path was given.
[[noreturn]] void throw_gnuplot_missing(const std::string& explicit_path);

/// Writes NAME.dat and NAME.gp of every plot into `dir` (created), runs
/// gnuplot on the scripts (several at once, each in `dir`) and reads the SVGs
/// back. Throws UsageError when gnuplot is missing or a script fails (the
/// message quotes gnuplot's first error line and names the script).
std::vector<RenderedPlot> render_plots(const std::vector<Plot>& plots, const std::filesystem::path& dir,
                                       const RenderOptions& options = {});

/// At most about `max_points` points of (x, y) for drawing: the minimum and
/// maximum of each of max_points/2 consecutive buckets, in x order, so peaks
/// survive. Shorter series are returned unchanged.
void decimate_minmax(std::vector<double>& x, std::vector<double>& y, std::size_t max_points);

}  // namespace cubecal::report
