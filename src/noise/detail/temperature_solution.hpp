// The steps the in-memory and the streamed least-squares temperature fits
// share (temperature.cpp, streaming_temperature.cpp): solving the normal
// equations of the scaled regressor, and the coefficient covariance (batch
// means of the scores, never below the white-residual one) with the
// coefficients back in powers of (T - t_ref). Not an installed header.
#pragma once
#include <Eigen/Dense>
#include <cstddef>

#include "cubecal/noise/temperature.hpp"
#include "temperature_regressor.hpp"

namespace cubecal::noise::detail {

// The batches of the covariance for n samples and p coefficients.
std::size_t temperature_batches(std::size_t n, std::size_t p) noexcept;

// ata: V^T V (p x p, full); aty: V^T (y - mean y). Throws the degenerate
// CalibrationError when the matrix is singular for the order.
struct TemperatureSolution {
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  Eigen::VectorXd cu;  // coefficients in u, cu(0) without the mean of y
};
TemperatureSolution solve_temperature(const Eigen::MatrixXd& ata, const Eigen::VectorXd& aty, std::size_t order);

// g: the score sums per batch (p x batches, g(k, b) = sum over batch b of
// u^k e); ss_res, ss_tot: residual and total sums of squares; ymean: the
// mean of y (added to cu(0)).
TemperatureFit temperature_fit_from(const TemperatureSolution& s, double ymean, const Eigen::MatrixXd& g, double ss_res,
                                    double ss_tot, std::size_t n, const TemperatureRegressor& reg, std::size_t order);

}  // namespace cubecal::noise::detail
