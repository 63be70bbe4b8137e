/// @file
/// Dynamic Allan deviation: the overlapping Allan deviation (OADEV) of a
/// window sliding along the record, W samples long and moved S samples at a
/// time, on a grid of averaging factors: a tau x time matrix that shows how a
/// sensor's noise changes over a run (Galleani & Tavella's dynamic Allan
/// variance; the fast recursion of Wang et al., Sensors 16, 2078, 2016, the
/// paper's ref. [9]). Definition, recursion and precision argument:
/// docs/formulas/davar.md.
///
///   cubecal::DavarOptions o;
///   o.window = 36000;                         // 1 h at 10 Hz
///   o.step = 600;                             // 60 s
///   o.grid = cubecal::parse_tau_grid("log:10");
///   const auto r = cubecal::davar(y, cubecal::DataType::freq, 0.1, o);
///   r.dev_at(j, k);                           // tau r.tau[j], window centred at r.centre[k]
///
/// Spans in, a result out; no I/O, no threads.
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal {

/// fast: the window sums slide over per-step block sums (docs/formulas/davar.md
/// §3), O(N) per averaging factor for the whole record. direct: the OADEV
/// kernel (stats/kernels.hpp) run on every window anew, O(N W / S) per factor:
/// the definition, kept as the reference the fast method is tested and timed
/// against.
enum class DavarMethod { fast, direct };

/// Confidence intervals per cell (docs/formulas/davar.md §5): the EDF of the
/// window's OADEV at the cell's averaging factor (stats/edf.hpp) for a noise
/// type, and the chi-squared interval (stats/confidence.hpp).
struct DavarIntervals {
  /// True to compute the intervals (and the EDF and noise type of every cell).
  bool enabled = false;
  /// Confidence factor of the intervals (0.683: 1 sigma).
  double ci = 0.683;
  /// How the EDF is computed.
  EdfMethod edf = EdfMethod::greenhall;
  /// The noise type (+2 WPM ... -2 RWFM) of every cell. Not set: identified
  /// in each cell on the window's own data as `dev` identifies it on a record
  /// (stats/noise_id.hpp, with the run rule beyond half the largest factor),
  /// since the noise the dynamic deviation is meant to follow may change type
  /// along the record.
  std::optional<int> alpha;
};

/// What a dynamic Allan deviation is asked for: window and step (input samples), averaging factors, method, intervals.
struct DavarOptions {
  std::size_t window = 0;  ///< W: input samples per window (frequency: W + 1 phase points; phase: W)
  std::size_t step = 0;    ///< S: input samples the window moves each time (>= 1)
  TauGrid grid;            ///< averaging factors up to the OADEV limit of one window
  /// Fast (block sums) or direct (the definition).
  DavarMethod method = DavarMethod::fast;
  /// The intervals per cell, if any.
  DavarIntervals intervals;
  /// A NaN sample is a missing sample (`davar --gaps skip`): each cell is the
  /// OADEV of its window with the terms that need a missing sample left out,
  /// as `dev --gaps skip` computes it on the window's samples
  /// (stats/gap_deviation.hpp, docs/formulas/stability.md §7a). false: a NaN
  /// is refused. A record without a NaN takes the same path either way.
  bool skip_missing = false;
};

/// The dynamic Allan deviation: OADEV per (averaging factor, window) cell, in the data's unit, with the windows' times
/// (s) and the factors' taus (s).
struct DavarMatrix {
  /// The sample period (s).
  double tau0 = 0.0;
  /// Frequency or phase data.
  DataType type = DataType::freq;
  std::size_t samples = 0;        ///< input samples of the record
  std::size_t window = 0;         ///< W, input samples
  std::size_t step = 0;           ///< S, input samples
  std::size_t window_points = 0;  ///< phase points of one window (W + 1 for frequency, W for phase)
  /// Per window k: the time of its first phase point and of its centre, in
  /// seconds from the record's first phase point (the start of the first
  /// frequency sample).
  std::vector<double> start;
  /// Per window k: the time of its centre (s from the record's first phase point).
  std::vector<double> centre;
  /// Per averaging factor j (ascending).
  std::vector<std::size_t> m;
  /// Per averaging factor j: tau = m[j] tau0 (s).
  std::vector<double> tau;
  /// Terms of each cell of row j: window_points - 2 m[j]. Every window has the
  /// same length, so the count of a cell depends on its row only, unless
  /// samples are missing (then `terms`).
  std::vector<std::size_t> n;
  /// Missing samples of the record (skip_missing; 0 otherwise).
  std::size_t missing = 0;
  /// With missing samples (empty without): the whole terms of each cell, in
  /// the layout of dev. A cell without a whole term has no value: its dev,
  /// lo, hi and edf are NaN (its alpha 0).
  std::vector<std::size_t> terms;
  /// The matrix, row-major by tau: dev[j * windows() + k].
  std::vector<double> dev;
  /// With intervals (empty without): the same layout.
  ///@{
  std::vector<double> lo, hi, edf;
  ///@}
  /// With intervals (empty without): the noise type alpha of each cell, in the layout of dev.
  std::vector<int> alpha;
  /// Per cell: the noise type is the previous factor's in the window's run
  /// (the run rule of docs/formulas/stability.md §4.5), not identified at m.
  std::vector<bool> alpha_carried;
  /// True when lo, hi, edf and alpha are filled.
  bool intervals = false;
  /// Confidence factor of the intervals.
  double ci = 0.0;
  /// How the EDF was computed.
  EdfMethod edf_method = EdfMethod::greenhall;
  /// The noise type given for every cell, when it was not identified.
  std::optional<int> fixed_alpha;

  /// Windows (columns of the matrix). Throws nothing.
  std::size_t windows() const noexcept { return start.size(); }
  /// Averaging factors (rows of the matrix). Throws nothing.
  std::size_t taus() const noexcept { return m.size(); }
  /// The index of cell (row j, window k) in dev, lo, hi, edf, alpha. Throws nothing.
  std::size_t cell(std::size_t j, std::size_t k) const noexcept { return j * start.size() + k; }
  /// The deviation of cell (j, k), in the data's unit. Throws nothing.
  double dev_at(std::size_t j, std::size_t k) const noexcept { return dev[cell(j, k)]; }
  /// The terms of cell (j, k): n[j], or fewer where samples are missing.
  std::size_t terms_at(std::size_t j, std::size_t k) const noexcept { return terms.empty() ? n[j] : terms[cell(j, k)]; }
};

/// The phase points of a window of `window` input samples of `type`.
std::size_t davar_window_points(std::size_t window, DataType type) noexcept;

/// The windows of a record of `samples` input samples: (samples - W) / S + 1,
/// 0 when W exceeds the record.
std::size_t davar_window_count(std::size_t samples, std::size_t window, std::size_t step) noexcept;

/// The dynamic OADEV of `data` (frequency or phase samples every tau0 s).
/// Throws UsageError(Field::window) for a window shorter than OADEV needs for
/// m = 1 (4 frequency or 5 phase samples) or longer than the record,
/// UsageError(Field::step) for a zero step, UsageError(Field::taus) when no factor of
/// the grid fits a window, UsageError(Field::alpha) for a fixed noise type outside
/// -2..2, UsageError(Field::ci) for a confidence outside (0, 1), and
/// std::invalid_argument for an infinite sample, a NaN one (unless
/// options.skip_missing) or a tau0 that is not a positive finite number.
///
/// With missing samples the fast method slides the sums of the whole terms
/// and their counts as it slides the sums of a record without gaps (the same
/// cost); the direct method sums every window's whole terms anew. The
/// noise type of a cell of a window with a missing sample is identified as
/// `dev --gaps skip` identifies it (on the window's longest whole stretch),
/// and its EDF is that of a window without gaps giving as many terms.
DavarMatrix davar(std::span<const double> data, DataType type, double tau0, const DavarOptions& options);

}  // namespace cubecal
