/// @file
/// Sensor presets: the paper's gyro and magnetometer as simulator models.
#pragma once
#include <string>
#include <vector>

#include "cubecal/sim/simulator.hpp"

namespace cubecal {

/// The paper's sensors (docs/paper.md §3 and §5.1): "sport-gyro" (MPU-3300 adjusted model,
/// 145.6 LSB/(deg/s), turn-on bias std of the five power cycles) and
/// "sport-mag" (HMC5843, 1.30 LSB/mGauss, 0.7 mGauss/degC). Throws
/// std::invalid_argument for an unknown name. The per-sample parameters hold
/// at the paper's rate, kPresetRateHz (pipeline::model_at_rate rescales them
/// for another rate, keeping the sensor's N and K).
inline constexpr double kPresetRateHz = 10.0;
/// The preset named `name` ("sport-gyro", "sport-mag"), its parameters per sample at kPresetRateHz. Throws
/// std::invalid_argument for an unknown name.
TriadModel preset(const std::string& name);
/// The names preset() knows. Throws nothing beyond std::bad_alloc.
std::vector<std::string> preset_names();

}  // namespace cubecal
