/// @file
/// `cubecal davar` as a library call: the dynamic Allan deviation
/// (stats/davar.hpp) of every channel of a record, with the window and the
/// step given as durations or sample counts, and its JSON.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cubecal/field.hpp"
#include "cubecal/io/series.hpp"
#include "cubecal/stats/davar.hpp"
#include "cubecal/stats/tau_exclusions.hpp"
#include "cubecal/stats/tau_grid.hpp"

namespace cubecal::pipeline {

/// A window or a step as the user gives it: a duration ("1h", "30m", "30min",
/// "90s", "2d", "0.5h") or a whole number of samples ("36000").
struct DavarSpan {
  double seconds = 0.0;     ///< > 0 for a duration
  std::size_t samples = 0;  ///< > 0 for a count
  std::string text;         ///< as given
};

/// Throws UsageError(option) naming the text when it is neither.
DavarSpan parse_davar_span(const std::string& text, Field option);

/// The span in samples at `rate_hz` (a duration rounded to the nearest
/// sample); UsageError(option) when that is no sample at all.
std::size_t span_samples(const DavarSpan& span, double rate_hz, Field option);

/// What `cubecal davar` is asked to do with a record (the data already read).
struct DavarRequest {
  /// Frequency or phase data.
  DataType type = DataType::freq;
  std::optional<DavarSpan> window;  ///< not set: a tenth of the record (the whole record if that is too short)
  std::optional<DavarSpan> step;    ///< not set: a tenth of the window (at least one sample)
  /// The averaging factors (default log:10).
  TauGrid grid = [] {
    TauGrid g;
    g.kind = TauGrid::Kind::log;
    g.per_decade = 10;
    return g;
  }();
  /// Confidence intervals per cell, if any.
  DavarIntervals intervals;
  /// Fast (block sums) or direct.
  DavarMethod method = DavarMethod::fast;
  unsigned threads = 0;  ///< channels at once; 0: all cores
};

/// The dynamic Allan deviation of one channel.
struct DavarChannel {
  /// The channel's name.
  std::string name;
  /// Its tau x time matrix.
  DavarMatrix matrix;
};

/// The result of `cubecal davar`: one matrix per channel and how the windows were chosen.
struct DavarResult {
  std::string file;  ///< the record's file (empty for arrays)
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  /// Samples per channel.
  std::size_t samples = 0;
  /// Frequency or phase data.
  DataType type = DataType::freq;
  std::size_t window = 0;  ///< samples
  std::size_t step = 0;    ///< samples
  /// as asked ("1h"), or how the default was chosen
  ///@{
  std::string window_text, step_text;
  ///@}
  /// The tau grid asked for.
  TauGrid grid;
  /// Listed taus a window cannot evaluate, and listed taus merged on one
  /// factor (empty for generated grids).
  TauListOutcome tau_list;
  /// One per channel, in the record's order.
  std::vector<DavarChannel> channels;
};

/// Throws UsageError(Field::gaps) for a record cut at gaps (one window slides along
/// one contiguous record), and the errors of davar() (UsageError "window",
/// "step", "taus", "alpha", "ci"). A record read with io::GapPolicy::skip has
/// its missing samples (NaN) left out of each window's terms
/// (DavarOptions::skip_missing, `davar --gaps skip`).
DavarResult run_davar(const io::Series& series, const DavarRequest& request);

/// {"command": "davar", "file", "rate_hz", "type", "samples", "missing_samples",
/// "window": {samples, seconds, asked}, "step": {...}, "windows", "intervals":
/// {...}, "channels": [{"name", "t_start": [...], "t": [...] (centres), "m",
/// "tau", "n" (terms of a window without a missing sample), "missing_samples",
/// "dev": [[...] one array per tau, over the windows], with missing samples
/// "terms" (the whole terms of each cell), and with intervals "lo", "hi",
/// "edf", "alpha" in the same layout}]}. A cell without a whole term has no
/// value: null in dev, lo, hi, edf and alpha.
nlohmann::json to_json(const DavarResult& r);

}  // namespace cubecal::pipeline
