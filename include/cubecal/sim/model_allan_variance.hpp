/// @file
/// The Allan variance of a simulated axis (simulator.hpp's AxisModel) at every
/// averaging factor, exact for the sampled process where its parts allow:
/// the white noise and quantizer, the random-walk or Gauss-Markov bias
/// (sensor_noise_model.hpp), the power-law terms (their continuous-time
/// closed forms, NIST SP 1065 Table 2) and the composite model's processes
/// (composite_model.hpp). What `cubecal plan` plans a record of.
#pragma once
#include <cstddef>

#include "cubecal/noise/record_plan.hpp"
#include "cubecal/sim/simulator.hpp"

namespace cubecal {

/// The Allan variance of axis `axis` (0..2) of `triad` sampled every `dt` s at
/// factor m >= 1 (u^2): the sum of its independent parts. A scale factor,
/// misalignment, fixed or turn-on bias or temperature term adds nothing to a
/// static record's Allan variance at constant temperature. Throws
/// std::invalid_argument for a power-law term of an alpha other than 0, -1
/// or -2, an axis past 2, or dt not positive.
double model_avar(const TriadModel& triad, std::size_t axis, double dt, std::size_t m);

/// The plan model of that axis (record_plan.hpp). Throws as model_avar for the model (checked once, here).
PlanModel plan_model(const TriadModel& triad, std::size_t axis, double dt);

}  // namespace cubecal
