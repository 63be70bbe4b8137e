/// @file
/// cubecal's numeric core in one include: every installed header of the core
/// (statistics, noise terms and models, the simulator, spectra and the
/// calibrations). No I/O, no threads; link cubecal::core. Readers
/// (cubecal/io/), multi-channel pipelines (cubecal/pipeline/) and reports
/// (cubecal/report/) are separate layers with their own targets
/// (docs/architecture.md).
#pragma once

#include "cubecal/error.hpp"
#include "cubecal/field.hpp"
#include "cubecal/printable_text.hpp"
#include "cubecal/stage_times.hpp"
#include "cubecal/math/index_range.hpp"
#include "cubecal/math/matrix.hpp"
#include "cubecal/math/vec3.hpp"

// stats: the Allan and Hadamard families with noise identification, EDF and
// confidence intervals; oadev(data, rate) and friends are the front door.
// Also the streamed, gap-skipping and dynamic deviations, Theo1/TheoH and
// the (robust) Haar wavelet variance.
#include "cubecal/stats/allan_curve.hpp"
#include "cubecal/stats/confidence.hpp"
#include "cubecal/stats/davar.hpp"
#include "cubecal/stats/deviation.hpp"
#include "cubecal/stats/edf.hpp"
#include "cubecal/stats/gap_deviation.hpp"
#include "cubecal/stats/kernels.hpp"
#include "cubecal/stats/lag_sums.hpp"
#include "cubecal/stats/noise_id.hpp"
#include "cubecal/stats/phase.hpp"
#include "cubecal/stats/realtime_deviation.hpp"
#include "cubecal/stats/robust_wavelet_variance.hpp"
#include "cubecal/stats/sampling.hpp"
#include "cubecal/stats/stability.hpp"
#include "cubecal/stats/statistic.hpp"
#include "cubecal/stats/streaming_deviation.hpp"
#include "cubecal/stats/tau_exclusions.hpp"
#include "cubecal/stats/tau_grid.hpp"
#include "cubecal/stats/theo.hpp"
#include "cubecal/stats/wavelet_variance.hpp"

// noise: IEEE 952 terms, the paper's sensor models, units, drift, covariance,
// temperature dependence; composite models, their GMWM fit, the WIC and the
// twin of a channel.
#include "cubecal/noise/bias_verdict.hpp"
#include "cubecal/noise/composite_model.hpp"
#include "cubecal/noise/covariance.hpp"
#include "cubecal/noise/drift.hpp"
#include "cubecal/noise/gmwm.hpp"
#include "cubecal/noise/gmwm_asymptotics.hpp"
#include "cubecal/noise/minimum_spread.hpp"
#include "cubecal/noise/mixture_edf.hpp"
#include "cubecal/noise/noise_terms.hpp"
#include "cubecal/noise/record_plan.hpp"
#include "cubecal/noise/reported_terms.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"
#include "cubecal/noise/spectral_line.hpp"
#include "cubecal/noise/streaming_covariance.hpp"
#include "cubecal/noise/streaming_drift.hpp"
#include "cubecal/noise/streaming_temperature.hpp"
#include "cubecal/noise/temperature.hpp"
#include "cubecal/noise/temperature_random_walk.hpp"
#include "cubecal/noise/twin_error.hpp"
#include "cubecal/noise/twin_selection.hpp"
#include "cubecal/noise/unit_from_name.hpp"
#include "cubecal/noise/units.hpp"
#include "cubecal/noise/wic.hpp"

// sim: sensor triads with the paper's measurement model, its sensors,
// power-law noise, and samples of composite models.
#include "cubecal/sim/composite_noise.hpp"
#include "cubecal/sim/composite_simulator.hpp"
#include "cubecal/sim/model_allan_variance.hpp"
#include "cubecal/sim/power_law_generator.hpp"
#include "cubecal/sim/power_law_noise.hpp"
#include "cubecal/sim/presets.hpp"
#include "cubecal/sim/simulator.hpp"
#include "cubecal/sim/wic_replicate.hpp"

// spectral: what is built on a Welch spectrum: windows, detrending, the
// segment plan, log bins, the power-law fit, PSD <-> Allan variance, lines.
#include "cubecal/spectral/allan_conversion.hpp"
#include "cubecal/spectral/density_unit.hpp"
#include "cubecal/spectral/detrend.hpp"
#include "cubecal/spectral/log_bins.hpp"
#include "cubecal/spectral/power_law_fit.hpp"
#include "cubecal/spectral/psd.hpp"
#include "cubecal/spectral/spectral_lines.hpp"
#include "cubecal/spectral/welch_options.hpp"
#include "cubecal/spectral/window.hpp"

// calib: rate table, magnetometer (TWOSTEP, ellipsoid), multi-position.
#include "cubecal/calib/ellipsoid_fit.hpp"
#include "cubecal/calib/mag_calibration.hpp"
#include "cubecal/calib/multiposition.hpp"
#include "cubecal/calib/plateaus.hpp"
#include "cubecal/calib/rate_table.hpp"
#include "cubecal/calib/static_detection.hpp"
#include "cubecal/calib/twostep.hpp"
