/// @file
/// Simulated sensor triads: the paper's measurement model (eq. 1-3 for the
/// gyro, 14-16 for the magnetometer; docs/paper.md §2.2) and its extensions,
/// for ADCS simulators and for checking the analysis on data with known
/// parameters. The model: docs/formulas/simulator.md §1-2.
///
/// Per axis i, sample k (period dt):
///   u_k      = M * true_k                      (scale factor and misalignment)
///   w_k[i]   = u_k[i] + fixed_bias[i] + turn_on[i] + b_k[i]
///              + temp_coeff[i] * (T_k - temp_ref) + white[i] * n_k
///   out_k[i] = clamp(Q(w_k[i]), -saturation, +saturation)
/// with Q(w) = int(w * lsb) / lsb (truncation toward zero, the paper's eq. 3;
/// docs/formulas/simulator.md §1.2) or rounding, none when lsb == 0; turn_on
/// drawn once per run (N(0, turn_on_sigma^2)); and the bias process b either a
/// random walk b_{k+1} = b_k + sigma_mu dt n'_k (the paper's eq. 2/15;
/// docs/formulas/simulator.md §2.1) or a first-order Gauss-Markov
/// b_{k+1} = phi b_k + sigma_b sqrt(1 - phi^2) n'_k, phi = exp(-dt/T_c),
/// started in its stationary state.
/// Beside them, per axis, power-law terms and the processes of a composite
/// noise model (AxisModel::power_law, AxisModel::composite), on streams of their own.
/// Deterministic for a seed; no allocation per sample.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cubecal/noise/composite_model.hpp"
#include "cubecal/sim/power_law_generator.hpp"

namespace cubecal {

/// The bias process of a simulated axis: none, a random walk, or a first-order Gauss-Markov process.
enum class BiasProcess { none, random_walk, gauss_markov };
/// How the simulated output is quantized to the LSB: truncated toward zero, or rounded.
enum class Quantizer { truncate, round };

/// The measurement model of one simulated axis, in its unit u (per sample where it says so).
struct AxisModel {
  double fixed_bias = 0.0;     ///< u
  double turn_on_sigma = 0.0;  ///< u, drawn once per run
  double white_sigma = 0.0;    ///< u per sample (sigma_n)
  /// The bias process.
  BiasProcess bias = BiasProcess::none;
  double bias_sigma = 0.0;  ///< random walk: sigma_mu (u/s); Gauss-Markov: sigma_b (u)
  double tau_c = 0.0;       ///< Gauss-Markov correlation time, s
  double temp_coeff = 0.0;  ///< u per degC
  /// Further power-law noise of the output, S_y(f) = h f^alpha each (e.g.
  /// flicker_term(B): the flicker floor of bias instability B), from
  /// Kasdin & Walter's generator (power_law_generator.hpp), on streams of
  /// their own: the model's other terms see the same normals with or without.
  std::vector<PowerLawNoise> power_law;
  /// A composite noise model of the output (noise/composite_model.hpp), its
  /// parameters per sample at the simulator's dt (composite_at_period
  /// converts them from another rate), each process in its discrete-time form
  /// (composite_noise.hpp) on streams of its own, added as the power-law
  /// terms are: `simulate --bias composite` puts a fitted model here, with
  /// no white noise, bias process or quantizer besides.
  CompositeModel composite;
};

/// A simulated sensor triad: the three axes' models, their scale and misalignment, quantization and saturation.
struct TriadModel {
  std::string name;  ///< e.g. "sport-gyro"
  std::string unit;  ///< e.g. "deg/s"
  /// The axes' names, in output order.
  std::array<std::string, 3> axis_names{"x", "y", "z"};
  /// The axes' models, in output order.
  std::array<AxisModel, 3> axes;
  /// Row-major 3x3: u = M * true. Identity: no scale-factor or misalignment error.
  std::array<double, 9> scale_misalignment{1, 0, 0, 0, 1, 0, 0, 0, 1};
  double lsb = 0.0;  ///< counts per unit; 0: no quantization
  /// How the output is quantized when lsb > 0.
  Quantizer quantizer = Quantizer::truncate;
  double saturation = std::numeric_limits<double>::infinity();  ///< |out| limit, u
  double temp_ref = 25.0;                                       ///< degC at which the temperature term is zero
};

/// Temperature profile: constant, daily sinusoid, or a given series.
struct TemperatureProfile {
  /// Constant, sinusoid or series.
  enum class Kind { constant, sinusoid, series } kind = Kind::constant;  ///< the profile's kind
  double mean = 25.0;                                                    ///< degC
  double amplitude = 0.0;                                                ///< degC (sinusoid)
  double period_s = 86400.0;                                             ///< sinusoid
  /// Phase of the sinusoid at t = 0 (rad).
  double phase_rad = 0.0;
  std::vector<double> values;  ///< series, one per sample (held at the last value beyond)
  /// The temperature at sample k of period dt (s), degC. Throws nothing.
  double at(std::size_t k, double dt) const noexcept;
};

/// Simulates a sensor triad sample by sample from its TriadModel, with a seed (the same seed gives the same samples on
/// every platform).
class TriadSimulator {
 public:
  /// `record_samples`: the length of the record to be simulated, when known
  /// (0: not), for the power-law terms' filter (the whole record up to
  /// PowerLawGenerator::kMaxFilter samples).
  TriadSimulator(const TriadModel& model, double dt, std::uint64_t seed, std::size_t record_samples = 0);
  ~TriadSimulator();
  /// Moves a simulator and its random state.
  TriadSimulator(TriadSimulator&&) noexcept;
  /// Moves a simulator and its random state.
  TriadSimulator& operator=(TriadSimulator&&) noexcept;

  /// One sample: true input (u) and temperature (degC) in, measurement out.
  std::array<double, 3> step(const std::array<double, 3>& true_input, double temperature) noexcept;

  /// n samples into out (row-major n x 3). true_input: n x 3 row-major, or
  /// empty for a static sensor. temperature: n values, or empty for temp_ref.
  void run(std::size_t n, std::span<const double> true_input, std::span<const double> temperature,
           std::span<double> out);

  /// The model simulated. Throws nothing.
  const TriadModel& model() const noexcept;
  /// The sample period (s). Throws nothing.
  double dt() const noexcept;
  /// The turn-on bias drawn for this run.
  std::array<double, 3> turn_on() const noexcept;
  /// Current bias process state b_k (without fixed, turn-on and temperature terms).
  std::array<double, 3> bias_state() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cubecal
