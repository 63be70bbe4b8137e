/// @file
/// One statistic over a grid of averaging factors, with noise identification,
/// EDF and confidence intervals: the engine behind `cubecal dev`.
#pragma once
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stage_times.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// Which total deviations are divided by their bias for the noise type.
enum class BiasCorrection {
  /// As Stable32 runs them: TOTDEV and HTOTDEV corrected, MTOT and TTOT not
  /// (docs/formulas/stability.md, "Bias"). A point without a noise type (no
  /// intervals and no fixed alpha) is not corrected.
  stable32,
  on,   ///< TOTDEV, MTOT, TTOT and HTOT corrected
  off,  ///< none corrected: the plain estimators (as AllanTools computes them)
};

/// How the noise type, EDF and confidence interval of each point are obtained.
struct StabilityOptions {
  double ci = 0.683;  ///< confidence factor, as Stable32's default
  /// How the EDF is computed.
  EdfMethod edf = EdfMethod::greenhall;
  bool intervals = true;     ///< noise id + EDF + CI
  std::optional<int> alpha;  ///< fixed noise type instead of identification
  /// Below 30 averages the type comes from the B1 ratio, whose scatter
  /// spans the neighbouring types: true takes the smallest EDF (the widest
  /// interval) of the identified type and its two neighbours, so that a
  /// misidentification cannot make the interval falsely narrow. false (the
  /// default) keeps the identified type's EDF, as Stable32 does.
  bool conservative_short = false;
  /// TOTDEV (flicker and random-walk FM, by tau over the record length),
  /// MTOT, TTOT and HTOT are biased low for most noise types: the variance of
  /// the statistics this selects is divided by the bias of the noise type
  /// (identified, or `alpha`), as Stable32 does (docs/formulas/stability.md).
  BiasCorrection bias_correction = BiasCorrection::stable32;
};

/// One point of a stability curve.
struct StabilityPoint {
  /// Averaging factor.
  std::size_t m = 0;
  /// Tau (s).
  double tau = 0.0;
  /// The deviation, in the data's unit (frequency data) or per second (phase data: s/s for clocks).
  double dev = 0.0;
  /// Terms averaged (Stable32's "#").
  std::size_t n = 0;
  Interval interval;  ///< of dev, at StabilityOptions::ci ({0, 0} without intervals)
  double edf = 0.0;   ///< equivalent degrees of freedom behind interval (0 without intervals)
  /// The noise type: exponent of the frequency PSD (+2 WPM ... -2 RWFM).
  int alpha = 0;
  /// The noise type is the previous factor's in the run (carry_types), not
  /// identified at this m.
  bool type_carried = false;
};

/// Prepared record: phase points for the kernels plus what the statistic
/// needs (the reflected extension for TOTDEV, the phase differences for HTOT,
/// TheoBR's bias ratio). TIE rms and MTIE of frequency data integrate it with
/// its mean (a frequency offset is a time error); every other statistic
/// removes it first. Build once per channel and
/// statistic; evaluate() is const and safe to call from several threads.
class StabilityRecord {
 public:
  /// TheoBR's bias ratio costs about N^3/65 terms (a second or two at 5000
  /// points, about ten at 10000): records of more phase points are refused.
  static constexpr std::size_t kTheobrMaxPoints = 10000;
  /// Throws std::invalid_argument for a NaN or infinite sample (and for
  /// TheoBR beyond kTheobrMaxPoints). The data are
  /// scaled by an exact power of two internally, so values anywhere in the
  /// double range (1e-150 or 1e+150) give correct deviations.
  StabilityRecord(std::span<const double> data, DataType type, double tau0, Stat stat);

  /// Phase points of the prepared record. Throws nothing.
  std::size_t phase_points() const noexcept { return x_.size(); }
  /// The sample period (s). Throws nothing.
  double tau0() const noexcept { return tau0_; }
  /// Frequency or phase data. Throws nothing.
  DataType type() const noexcept { return type_; }
  /// Phase points, divided by scale().
  std::span<const double> phase() const noexcept { return x_; }
  /// The power of two the data were divided by. Throws nothing.
  double scale() const noexcept { return scale_; }
  /// The statistic. Throws nothing.
  Stat stat() const noexcept { return stat_; }
  /// Largest m Stable32 would evaluate on this record.
  std::size_t max_m() const noexcept;

  /// Deviation, n, and (if opt.intervals) noise id, EDF and interval at m.
  /// n == 0 when m is beyond what the record supports.
  StabilityPoint evaluate(std::size_t m, const StabilityOptions& opt) const;
  /// The same for every m of `ms`, in order. Close factors share their passes
  /// over the record (stats/kernels.hpp): the way to evaluate a dense grid.
  /// A grid evaluation applies carry_types to its points.
  /// `times` (optional) gets the thread's time in the kernels, the noise
  /// identification and the intervals.
  std::vector<StabilityPoint> evaluate(std::span<const std::size_t> ms, const StabilityOptions& opt,
                                       StageTimes* times = nullptr) const;

  /// Stable32's run rule: beyond half the largest averaging factor the noise
  /// is not identified anew; each factor keeps the type of the one before it
  /// in the run (an octave run carries its last identified octave, an
  /// all-tau run the factor just below half). `run`: one run's points in
  /// ascending m (points with n == 0 are skipped); their EDF and interval
  /// follow the carried type. Nothing changes with a fixed alpha. A single
  /// evaluate(m) has no run: beyond half it is identified at m itself.
  void carry_types(std::span<StabilityPoint> run, const StabilityOptions& opt) const;

 private:
  VarianceTerm variance(std::size_t m) const;
  /// The deviation of p from its variance, without noise type or interval.
  StabilityPoint point(std::size_t m, VarianceTerm v) const;
  void identify(StabilityPoint& p, const StabilityOptions& opt) const;
  /// EDF and interval of p for p.alpha (conservative_short applied).
  void set_interval(StabilityPoint& p, const StabilityOptions& opt) const;
  /// Noise type, bias correction and interval of p, as `opt` asks.
  void describe(StabilityPoint& p, const StabilityOptions& opt) const;
  bool needs_type(const StabilityOptions& opt) const noexcept;

  double scale_;
  std::vector<double> x_;
  DataType type_;
  double tau0_;
  Stat stat_;
  TotvarExtension ext_;        ///< only for TOTDEV
  std::vector<double> d_;      ///< only for HTOT: x[k+1] - x[k]
  double theobr_ratio_ = 0.0;  ///< only for TheoBR and TheoH
};

/// Convenience: every m in `ms` (single-threaded; the pipeline layer runs
/// channels and taus in parallel).
std::vector<StabilityPoint> stability(std::span<const double> data, DataType type, double tau0, Stat stat,
                                      std::span<const std::size_t> ms, const StabilityOptions& opt = {});

}  // namespace cubecal
