// cubecal's numeric core in one include: statistics, noise terms and sensor
// models, the simulator and the calibrations. No I/O, no threads; link
// cubecal::core. Readers (cubecal/io/), multi-channel pipelines
// (cubecal/pipeline/) and reports (cubecal/report/) are separate layers with
// their own targets (docs/architecture.md).
#pragma once

#include "cubecal/error.hpp"
#include "cubecal/math/index_range.hpp"
#include "cubecal/math/matrix.hpp"
#include "cubecal/math/vec3.hpp"

// stats: the Allan and Hadamard families with noise identification, EDF and
// confidence intervals; oadev(data, rate) and friends are the front door.
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/deviation.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/tau_exclusions.hpp"
#include "cubecal/stats/tau_grid.hpp"

// noise: IEEE 952 terms, the paper's sensor models, units, drift, covariance,
// temperature dependence.
#include "cubecal/noise/covariance.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/noise/temperature_random_walk.hpp"
#include "cubecal/noise/units.hpp"

// sim: sensor triads with the paper's measurement model, and its sensors.
#include "cubecal/sim/power_law_noise.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/sim/simulator.hpp"

// calib: rate table, magnetometer (TWOSTEP, ellipsoid), multi-position.
#include "cubecal/calib/ellipsoid_fit.hpp"
#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/calib/multiposition.hpp"
#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/rate_table.hpp"
#include "cubecal/calib/static_detection.hpp"
#include "cubecal/calib/twostep.hpp"
