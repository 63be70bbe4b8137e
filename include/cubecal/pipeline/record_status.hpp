/// @file
/// A recording that knows when it has enough (`cubecal record --target`,
/// docs/record.md): the Allan curve of each data channel of the incoming
/// samples, kept in constant memory (the streaming pyramid of
/// stats/streaming_deviation.hpp, on the grid, statistic, intervals and EDF
/// `analyze` uses), and on demand the noise terms read from it as `analyze`
/// reads them (read_off_noise_terms, fit_noise_terms, reported_terms), the
/// precision each target term has now, whether it is met, and the record
/// length the plan (noise/record_plan.hpp) gives for it from the terms
/// measured so far: what is still needed. The status is written to
/// DIR/status.json, replaced atomically (io/atomic_file.hpp).
///
/// Precision, as the plan defines it: the relative half-width of a term's
/// interval at the status's confidence. The curve's intervals are computed at
/// 68.3 % (as `analyze` does by default), so each term's uncertainty is its
/// 1-sigma, and the half-width at confidence ci is z(ci) sigma, z the
/// two-sided normal quantile (1.0006 at 68.3 %), as plan_precision makes
/// it. T, the tau of the curve's minimum: z(ci) times the relative sigma
/// `analyze` states for it (reported_terms.hpp: the spread of ln T over
/// records, minimum_spread.hpp).
#pragma once
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/noise/record_plan.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/stats/streaming_deviation.hpp"

namespace cubecal::pipeline {

/// The status file's name, in the recording directory.
inline constexpr std::string_view kStatusName = "status.json";
/// The status file's format name and version.
inline constexpr std::string_view kStatusFormat = "cubecal-record-status/1";

/// What a live status computes.
struct LiveStatusOptions {
  /// The targets (parse_plan_targets); empty: terms only.
  std::vector<PlanTarget> targets;
  /// The confidence of each precision and displayed interval (0 < ci < 1).
  double ci = 0.683;
  /// The pyramid's window bound (a power of two >= 16): factors whose
  /// terms span at most this many samples are exact, larger ones strided.
  std::size_t window_bound = std::size_t{1} << 16;
};

/// One term of one channel, now.
struct LiveTerm {
  /// The term.
  PlanTerm term = PlanTerm::N;
  /// True when the record resolves it: value, sigma and precision are known.
  bool resolved = false;
  /// Its value (Q u s, N u sqrt(s), B u, K u/sqrt(s), R u/s, T s; u the data
  /// unit); an upper bound when `bound`; NaN when the curve gives nothing.
  double value = 0.0;
  /// 1-sigma uncertainty (same unit); NaN when not resolved.
  double sigma = 0.0;
  /// The interval at the status's confidence (same unit); NaN when not resolved.
  double lo = 0.0;
  /// Upper end of that interval.
  double hi = 0.0;
  /// The taus it was read from (s); T: the taus around the minimum whose
  /// 68.3 % intervals reach sigma_min. 0 when the curve gives nothing.
  double tau_lo = 0.0;
  /// Upper end of those taus (s).
  double tau_hi = 0.0;
  /// "read-off", "fit", "UPPER BOUND" (reported_terms.hpp), "" for T.
  std::string source;
  /// True when value is only an upper bound.
  bool bound = false;
  /// Relative half-width at the status's confidence; NaN when not resolved.
  double precision = 0.0;
  /// The precision asked, when the term is a target.
  std::optional<double> target;
  /// The target holds: resolved and precision <= target.
  bool met = false;
  /// The record length (s) the plan gives for the target from the terms
  /// measured so far; NaN when met (no plan is made) or when it cannot be
  /// told (why says why).
  double needed_s = std::numeric_limits<double>::quiet_NaN();
  /// What is still needed (s): 0 when met, else needed_s less the record so
  /// far (at least 0); NaN when not known.
  double remaining_s = std::numeric_limits<double>::quiet_NaN();
  /// Why the term is not resolved, or why the time still needed is not
  /// known; empty otherwise.
  std::string why;
};

/// One data channel, now.
struct LiveChannel {
  /// Its column name.
  std::string name;
  /// N, K, B, T (and Q, R when they are targets), in that order.
  std::vector<LiveTerm> terms;
  /// Why the channel has no terms (too few samples yet); empty otherwise.
  std::string why;
};

/// The status of a recording with targets.
struct LiveStatus {
  /// Samples pushed (this run of the recorder).
  std::size_t samples = 0;
  /// The sample period (s); 0 while not known.
  double dt = 0.0;
  /// The record so far (s): samples times dt.
  double record_s = 0.0;
  /// The confidence of the precisions and intervals.
  double ci = 0.683;
  /// The data unit (the recording's, counts when none).
  Unit unit;
  /// The window bound of the pyramid.
  std::size_t window_bound = 0;
  /// The targets.
  std::vector<PlanTarget> targets;
  /// The data channels (the columns `analyze DIR` takes by default).
  std::vector<LiveChannel> channels;
  /// Every target of every channel holds (false without targets).
  bool all_met = false;
  /// Why there is nothing yet (no sample period); empty otherwise.
  std::string why;
};

/// The terms of a recording's samples as they arrive.
class LiveNoiseStatus {
 public:
  /// `columns`: every column of a sample as the recorder passes it;
  /// `time_column`: the device time (nullopt: none); `rate_hz`: the rate
  /// given (used without a time column); the data channels are the other
  /// columns less those named as a temperature, as `analyze DIR` takes them.
  /// Throws UsageError(Field::ci) for a confidence outside (0, 1) and
  /// std::invalid_argument for a window bound that is not a power of two >= 16.
  LiveNoiseStatus(const std::vector<std::string>& columns, const std::optional<std::string>& time_column,
                  std::optional<double> rate_hz, Unit unit, LiveStatusOptions options);

  /// One sample: a value per column, in the order of `columns`. A value that
  /// is not finite stops that channel's curve (its status says why).
  void push(std::span<const double> values);

  /// Samples pushed. Throws nothing.
  std::size_t samples() const noexcept { return samples_; }
  /// The sample period (s): 1 / rate without a time column, else from the
  /// median of the first 31 intervals of the time column (its rate rounded to
  /// nine significant digits, as a record's reader does); 0 while not known.
  double period() const noexcept { return dt_; }
  /// The record so far (s); 0 while the period is not known.
  double record_seconds() const noexcept { return static_cast<double>(samples_) * dt_; }
  /// The data channels' names.
  const std::vector<std::string>& channel_names() const noexcept { return names_; }

  /// The status now: each channel's terms (analyze's reading of the curve so
  /// far), their precision, the targets met and the time still needed. The
  /// accumulators go on (a copy of each pyramid is finished). Throws nothing
  /// of its own: a failure of a piece is said in the status.
  LiveStatus evaluate();

 private:
  void flush();
  LiveChannel channel_status(std::size_t c) const;

  LiveStatusOptions opt_;
  Unit unit_;
  std::vector<std::size_t> columns_;  ///< index of each channel in a sample
  std::vector<std::string> names_;
  std::vector<StreamingDeviation> devs_;
  std::vector<std::vector<double>> pending_;  ///< values not yet pushed, per channel
  std::vector<std::string> broken_;           ///< per channel: why its curve stopped
  int time_index_ = -1;
  double dt_ = 0.0;
  bool have_prev_ = false;
  double prev_t_ = 0.0;
  std::vector<double> intervals_;
  std::size_t samples_ = 0;
};

/// The status file's content: format, the record so far, the targets and
/// each channel's terms in the data unit and in display units
/// (noise/units.hpp); the recorder adds its own fields (segment, time
/// written, final). Throws nothing beyond std::bad_alloc.
nlohmann::json to_json(const LiveStatus& s);

/// DIR/status.json replaced by `content` atomically (io::replace_file_atomically:
/// a reader sees the old or the new file, never a part). Throws
/// std::system_error naming the file when it cannot be written.
void write_status_file(const std::string& dir, const nlohmann::json& content);

/// The two-sided normal quantile of confidence ci (1.0006 at 0.683); NaN outside (0, 1). Throws nothing.
double normal_half_width(double ci) noexcept;

}  // namespace cubecal::pipeline
