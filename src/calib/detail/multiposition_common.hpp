// Shared by the multi-position accelerometer and gyroscope calibrations
// (src/calib/multiposition_*.cpp). Not an installed header.
#pragma once
#include <Eigen/Dense>
#include <cstddef>
#include <string>
#include <vector>

#include "cubecal/calib/multiposition.hpp"
#include "cubecal/error.hpp"

namespace cubecal::multipos::detail {

// "%.4g"
std::string fmt_g(double v);

[[noreturn]] void fail(CalibrationReason reason, const std::string& what);

inline Eigen::Index ei(std::size_t i) { return static_cast<Eigen::Index>(i); }

// The time of every sample: the stamps, checked, or i / rate_hz. Throws
// CalibrationError: too_few_points (no samples), bad_data (non-finite
// values or stamps, stamps of the wrong count or not increasing), bad_option
// (neither stamps nor a positive rate). `what` names the triad in messages.
std::vector<double> sample_times(const TriadSeries& s, const char* what);

// Samples with t < t_0 + init_static_s.
std::size_t init_count(const std::vector<double>& t, double init_static_s);

// Throws CalibrationError (bad_option) for an option out of range.
void check_options(const Options& o);

Residuals residual_stats(const Eigen::VectorXd& r);

// Parameters mis_yz, mis_zy, mis_zx, s_x, s_y, s_z, b_x, b_y, b_z.
TriadCalibration acc_model(const Eigen::VectorXd& p);
Eigen::VectorXd acc_params(const TriadCalibration& m);

}  // namespace cubecal::multipos::detail
