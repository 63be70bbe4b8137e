/// @file
/// Samples of a composite noise model (noise/composite_model.hpp), each
/// process in its discrete-time form at one sample per step:
///   WN  sqrt(sigma2) z_t
///   QN  sqrt(Q2) (u_{t+1} - u_t), u white N(0, 1)
///   RW  sum_{s<=t} sqrt(gamma2) z_s, from 0 before the first sample
///   DR  omega t
///   GM  x_t = phi x_{t-1} + sqrt(sigma2) z_t, started from its stationary law
///   MA1 sqrt(sigma2) (z_t + theta z_{t-1}), z_{-1} drawn before the first sample
///   SIN A sin(omega t + U), the phase U uniform on [0, 2 pi), drawn first
/// for the GMWM's parametric bootstrap and its Monte Carlo validation.
/// Innovations: std::mt19937_64(seed) and Boost.Random's normal
/// distribution (as the sensor simulator), the processes drawn one after the
/// other, so the same seed gives the same samples on every platform.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cubecal/noise/composite_model.hpp"

namespace cubecal {

/// Throws UsageError(Field::model) for a parameter outside its range (a negative
/// variance, phi outside (0, 1)).
std::vector<double> simulate_composite(const CompositeModel& model, std::size_t samples, std::uint64_t seed);

}  // namespace cubecal
