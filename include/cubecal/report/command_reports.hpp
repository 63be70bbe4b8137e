/// @file
/// The report pages of the analysis commands other than `analyze`, built from
/// their result structs (core and pipeline; neither depends on this layer),
/// and the figures on them. Write a page with write_command_report
/// (command_report.hpp). Plot names:
///   turnon, compare     runs_allan_<channel>   OADEV of every run with its
///                                              interval, a colour per run
///   turnon              turnon_bias_<channel>  each run's bias, the mean over
///                                              the runs and mean ± the turn-on
///                                              standard deviation (a band)
///   calibrate rate-table  rate_residual_before, rate_residual_after
///                                              plateau residuals per axis, before
///                                              (identity, no bias) and after
///   calibrate mag       mag_xy, mag_xz, mag_yz raw and calibrated points with the
///                                              circle of radius F
///                       mag_norm_error         |h| − F per point, before and after
///                       mag_norm_error_after   the same after calibration alone
///   calibrate temperature, calibrate multiposition: tables only, no plots
///   psd                 psd_<channel>          density, fitted terms and their sum
/// `<channel>` is the channel's name reduced to letters, digits and '_'.
#pragma once
#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/rate_table.hpp"
#include "cubecal/pipeline/calibrate_mag.hpp"
#include "cubecal/pipeline/calibrate_multiposition.hpp"
#include "cubecal/pipeline/calibrate_rate_table.hpp"
#include "cubecal/pipeline/calibrate_temperature.hpp"
#include "cubecal/pipeline/davar_pipeline.hpp"
#include "cubecal/pipeline/psd.hpp"
#include "cubecal/pipeline/turnon.hpp"
#include "cubecal/report/command_report.hpp"

namespace cubecal::report {

// ---------------------------------------------------------------------------
// turnon, compare

/// What the turnon and compare pages show besides the runs.
struct RunsReportContext {
  std::string command;  ///< the command line as typed
  double ci = 0.683;    ///< confidence of the Allan intervals
  std::string taus;     ///< the tau grid (--taus), for the input summary
};

/// One plot per channel (channels matched by name and unit across the runs, in
/// first-seen order): every run's OADEV with its interval.
std::vector<ReportFigure> allan_overlay_figures(const std::vector<pipeline::RunSummary>& runs, double ci);

/// One plot per channel: the runs' biases, their mean and mean ± the turn-on
/// standard deviation.
std::vector<ReportFigure> turnon_bias_figures(const pipeline::TurnOnResult& t);

/// The turnon page: every run's Allan curve and bias, the turn-on bias per channel. Throws nothing beyond
/// std::bad_alloc.
CommandReport turnon_report(const pipeline::TurnOnResult& t, const RunsReportContext& ctx);
/// The compare page: the runs' Allan curves and biases side by side. Throws nothing beyond std::bad_alloc.
CommandReport compare_report(const std::vector<pipeline::RunSummary>& runs, const RunsReportContext& ctx);

// ---------------------------------------------------------------------------
// calibrate rate-table

/// What the rate-table page shows besides the calibration.
struct RateTableReportContext {
  /// The command line as typed.
  std::string command;
  /// The record's path.
  std::string file;
  std::string unit = "deg/s";          ///< of the gyro and the reference rates
  std::string source_text;             ///< where the plateaus came from ("the reference columns")
  std::array<double, 3> earth_rate{};  ///< added to every reference rate (RateTableOptions::earth_rate)
};

/// Residual of every plateau's mean per axis: before, w_g − (w + earth rate)
/// (identity, no bias); after, A w_g + β − (w + earth rate). Error bars: the
/// standard error of the plateau mean (std / √n).
std::vector<ReportFigure> rate_table_residual_figures(const PlateauDetection& found, const RateTableCalibration& cal,
                                                      const RateTableReportContext& ctx);

/// The rate-table page: plateaus, both model forms, residuals before and after. Throws nothing beyond std::bad_alloc.
CommandReport rate_table_report(const PlateauDetection& found, const RateTableCalibration& cal,
                                const RateTableReportContext& ctx);
/// The page of a pipeline result; `command` is the command line as typed.
CommandReport rate_table_report(const pipeline::RateTableResult& r, const std::string& command);

// ---------------------------------------------------------------------------
// calibrate mag

/// What the magnetometer page shows besides the calibration.
struct MagReportContext {
  /// The command line as typed.
  std::string command;
  /// The record's path.
  std::string file;
  std::string unit;                 ///< of the values after --lsb; empty: "input units"
  std::string field_source;         ///< "given", "mean_raw_norm" or "column"
  std::vector<double> field_norms;  ///< F per input point (--field-col); empty: Result::field_norm
  std::size_t first_data_line = 0;  ///< line of the first point in the file (rejected points' lines)
  std::size_t max_points = 1000;    ///< per series of a plot; beyond, every k-th point
};

/// mag_xy, mag_xz, mag_yz: `h` (every input point, as calibrate() got them)
/// and A^-1 (h − b) projected, with the circle of radius F.
std::vector<ReportFigure> mag_projection_figures(std::span<const Vec3> h, const mag::Result& r,
                                                 const MagReportContext& ctx);
/// mag_norm_error (before and after), mag_norm_error_after (after, ± its RMS).
std::vector<ReportFigure> mag_norm_error_figures(std::span<const Vec3> h, const mag::Result& r,
                                                 const MagReportContext& ctx);

/// The magnetometer page: points, calibration, norm errors, coverage. Throws nothing beyond std::bad_alloc.
CommandReport mag_report(std::span<const Vec3> h, const mag::Result& r, const MagReportContext& ctx);
/// The page of a pipeline result; `command` is the command line as typed.
CommandReport mag_report(const pipeline::MagResult& r, const std::string& command);

// ---------------------------------------------------------------------------
// calibrate temperature (tables only: the fit per channel, the coefficients)

/// The temperature calibration page; `command` is the command line as typed. Throws nothing beyond std::bad_alloc.
CommandReport temperature_report(const pipeline::TemperatureResult& r, const std::string& command);

// ---------------------------------------------------------------------------
// calibrate multiposition (tables only: the poses, each triad's parameters
// and residuals)

/// The multi-position calibration page; `command` is the command line as typed. Throws nothing beyond std::bad_alloc.
CommandReport multiposition_report(const pipeline::MultipositionResult& r, const std::string& command);

// ---------------------------------------------------------------------------
// davar: per channel a heat map of the dynamic Allan deviation (davar_map_<channel>:
// window centre on x, tau on a log y axis, colour log10 of the deviation) and
// the deviation over time at up to four taus (davar_time_<channel>), then per
// tau its spread over the windows

/// The davar page's figures (above). Throws nothing beyond std::bad_alloc.
std::vector<ReportFigure> davar_figures(const pipeline::DavarResult& r);
/// The davar page; `command` is the command line as typed. Throws nothing beyond std::bad_alloc.
CommandReport davar_report(const pipeline::DavarResult& r, const std::string& command);

// ---------------------------------------------------------------------------
// psd: per channel the one-sided density on log-log axes (psd_<channel>,
// averaged over logarithmic bands when the result holds the raw bins), the
// fitted power-law terms and their sum over the fitted band, then a table of
// the coefficients h_alpha and the IEEE 952 terms they stand for

/// The psd page's figures (above). Throws nothing beyond std::bad_alloc.
std::vector<ReportFigure> psd_figures(const pipeline::PsdResult& r);
/// The psd page; `command` is the command line as typed. Throws nothing beyond std::bad_alloc.
CommandReport psd_report(const pipeline::PsdResult& r, const std::string& command);

}  // namespace cubecal::report
