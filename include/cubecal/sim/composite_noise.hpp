/// @file
/// A composite noise model (noise/composite_model.hpp) sampled a block at a
/// time, for records of any length: the composite terms of the sensor
/// simulator (simulator.hpp, AxisModel::composite; `simulate --bias
/// composite`). simulate_composite (composite_simulator.hpp) draws a whole
/// record in memory, for the GMWM's bootstrap.
///
/// Each process in its discrete-time form at one sample per step, k = 0, 1, ...
/// (the forms of simulate_composite):
///   WN  sqrt(sigma2) z_k
///   QN  sqrt(Q2) (u_{k+1} - u_k), u white N(0, 1)
///   RW  sum_{s<=k} sqrt(gamma2) z_s
///   DR  omega k
///   GM  x_k = phi x_{k-1} + sqrt(sigma2) z_k, x_{-1} drawn from the stationary law
///   MA1 sqrt(sigma2) (z_k + theta z_{k-1})
///   SIN A sin(omega k + U), U uniform on [0, 2 pi) drawn once
/// Process i draws from its own std::mt19937_64 (seeded by a splitmix64 of
/// the seed and i) through Boost.Random's normal distribution, so the same
/// seed gives the same samples on every platform and for any block sizes.
#pragma once
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "cubecal/noise/composite_model.hpp"

namespace cubecal {

/// Samples of a composite noise model drawn block by block (the sensor simulator's composite term), each process on a
/// random stream of its own.
class CompositeNoise {
 public:
  /// Throws std::invalid_argument for a parameter outside its range (a
  /// negative or non-finite variance, phi outside (0, 1), a non-finite drift).
  CompositeNoise(const CompositeModel& model, std::uint64_t seed);

  /// Adds the next out.size() samples of the model to out.
  void add_next(std::span<double> out);

 private:
  struct State {
    Process process;
    std::mt19937_64 engine;
    double scale = 0.0;  ///< sqrt of the variance: WN, QN, RW, GM, MA1
    double x = 0.0;      ///< QN: u_k; RW: the walk; GM: x_{k-1}; MA1: e_{k-1}; SIN: the phase U
  };
  std::vector<State> states_;
  std::uint64_t k_ = 0;  ///< samples drawn
};

/// The same processes sampled at the period to_dt, their per-sample
/// parameters given at from_dt: the physical quantities of
/// composite_model.hpp kept,
///   WN sigma2 = N^2 / dt     QN Q2 = (Q / dt)^2     RW gamma2 = K^2 dt
///   DR omega = R dt          GM phi = exp(-dt / T_c), sigma2 = sigma_b^2 (1 - phi^2)
///   MA1 sigma2 = N^2 / ((1 + theta)^2 dt), theta kept (a filter correlating
///       neighbouring samples at either period).
///   SIN A and the frequency in Hz kept: omega = 2 pi f dt.
/// Throws std::invalid_argument for a period that is not positive and finite,
/// UsageError(Field::rate) for a SIN line at or above the Nyquist frequency of to_dt.
CompositeModel composite_at_period(const CompositeModel& model, double from_dt, double to_dt);

}  // namespace cubecal
