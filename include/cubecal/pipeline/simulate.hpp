/// @file
/// `cubecal simulate` as a library call: records from sensor models (presets
/// or an `analyze` result) at a rate and duration, with a temperature profile
/// and an optional true-rate profile, in memory or streamed to CSV.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "cubecal/sim/simulator.hpp"
#include "cubecal/io/csv_writer.hpp"
#include "cubecal/pipeline/analyze.hpp"
#include "cubecal/pipeline/model_fit.hpp"

namespace cubecal::pipeline {

/// A true input rate profile: piecewise constant rates per axis over time.
struct RateProfile {
  std::vector<double> t;                 ///< s, ascending
  std::array<std::vector<double>, 3> w;  ///< true input per axis at t (zero-order hold)
  /// True when no profile was given. Throws nothing.
  bool empty() const noexcept { return t.empty(); }
};

/// What `cubecal simulate` is asked to do.
struct SimulateRequest {
  /// The sensors, each a triad of channels.
  std::vector<TriadModel> triads;
  /// Sampling rate (Hz).
  double rate_hz = 10.0;
  /// Duration of the record (s).
  double duration_s = 3600.0;
  /// Seed of every random stream.
  std::uint64_t seed = 1;
  /// The temperature during the record (degC).
  TemperatureProfile temperature;
  /// True to write the temperature as the last column.
  bool temperature_column = true;
  RateProfile true_input;                ///< applied to the first rate (deg/s or rad/s) triad
  std::function<void(double)> progress;  ///< called with the fraction done, per block (optional)
};

/// A simulated record held in memory.
struct SimulatedRecord {
  /// Sampling rate (Hz).
  double rate_hz = 0.0;
  std::vector<std::string> names;             ///< t excluded; temp last when present
  std::vector<std::vector<double>> channels;  ///< one per name
};

/// round(duration x rate); UsageError(Field::duration) past kMaxSimulatedSamples.
inline constexpr double kMaxSimulatedSamples = 1e15;
/// round(duration_s x rate_hz). Throws UsageError("duration") past kMaxSimulatedSamples.
std::size_t sample_count(const SimulateRequest& r);

/// Channel names in output order (axis names of each triad, then "temp").
std::vector<std::string> channel_names(const SimulateRequest& r);

/// The whole record in memory. Throws UsageError ("duration", "rate") as sample_count does.
SimulatedRecord simulate(const SimulateRequest& r);

/// Streams the record to `out` (header t,<axes...>,temp) in blocks, so days
/// of data need no more memory than one block.
void write_simulation(const SimulateRequest& r, io::CsvWriter& out);

/// The record in blocks of consecutive samples, for writers of any format:
/// `frames` holds len x channel_names(r).size() values, row-major (one frame
/// per sample, in channel_names order), for samples k0 .. k0 + len. The
/// values are simulate()'s, in the same memory as one block.
void simulate_blocks(const SimulateRequest& r,
                     const std::function<void(std::size_t k0, std::span<const double> frames)>& sink);

/// A record already in memory to `out`, in write_simulation's layout
/// (t, <names...>): the same file write_simulation writes for its request.
void write_record(const SimulatedRecord& rec, io::CsvWriter& out);

/// Sensor models from an `analyze` result (e.g. analysis_result_from_json of an
/// analysis.json; `label` names it in messages): consecutive
/// channels form triads (a last partial triad keeps only its channels); the
/// fixed bias is the measured mean, white noise and bias process come from
/// the fitted random-walk model, or the Gauss-Markov model when asked (the
/// one fitted to the temperature-compensated series when the channel has a
/// temperature analysis with that model: the twin adds the temperature term
/// itself); the quantizer is the model's LSB. Throws UsageError for a result without
/// channels, and UsageError(Field::bias, ...) for a channel without the fitted model asked for.
std::vector<TriadModel> models_from_analysis(const AnalysisResult& analysis, const std::string& label,
                                             bool gauss_markov);

/// The same sensors sampled at `rate_hz`: an analysis.json carries its
/// rate (rate_hz) and each channel's unit; its sigma_n and sigma_mu are per
/// sample at that rate (noise-terms.md §4), so they are rescaled to keep the
/// sensor's N, K (and hence B) whatever rate is asked (model_at_rate).
/// Throws UsageError(Field::rate, ...) for a rate that is not positive.
std::vector<TriadModel> models_from_analysis(const AnalysisResult& analysis, const std::string& label,
                                             bool gauss_markov, double rate_hz);

/// Sensor models from composite noise models (`analyze --composite`, each
/// channel's model.composite; or a `cubecal model` result), sampled at
/// `rate_hz`: consecutive channels form triads as above, and each axis's
/// output is its channel's composite model, each process in its
/// discrete-time form at 1 / rate_hz (composite_at_period from the fit's
/// rate: N, Q, K, R, sigma_b and T_c kept), plus, from an analysis, the
/// measured mean as the fixed bias. No white noise, bias process, quantizer
/// or temperature term besides: the model was fitted to the record as
/// measured. Throws UsageError(Field::bias) for an analysis without composite
/// models, UsageError(Field::rate) for a rate that is not positive, and
/// UsageError for a result without channels.
std::vector<TriadModel> models_from_composite(const AnalysisResult& analysis, const std::string& label, double rate_hz);
/// The same from a `cubecal model` result. Throws UsageError("rate") for a rate that is not positive, and UsageError
/// for a result without channels.
std::vector<TriadModel> models_from_composite(const ModelResult& model, const std::string& label, double rate_hz);

/// A model whose per-sample parameters hold at `from_hz`, for sampling at
/// `to_hz`: white_sigma and the random walk's bias_sigma (sigma_mu) scale by
/// sqrt(to_hz / from_hz), which keeps N = sigma_n sqrt(dt) and
/// K = sigma_mu sqrt(dt); a Gauss-Markov sigma_b and tau_c are kept. The
/// quantizer (lsb) is per sample and kept as it is; a composite model
/// (AxisModel::composite) is converted by composite_at_period.
TriadModel model_at_rate(const TriadModel& model, double from_hz, double to_hz);

/// "72h", "30m", "90s", "2d" or a number of seconds.
double parse_duration(const std::string& s);

}  // namespace cubecal::pipeline
