// Non-negative least squares for the five-term noise fit. Not an installed
// header.
#pragma once
#include <Eigen/Dense>
#include <vector>

namespace cubecal::noise::detail {

// Lawson & Hanson (1974), "Solving Least Squares Problems", ch. 23:
// min ||A x - b|| subject to x >= 0, by an active set. `passive` returns
// which unknowns are free (strictly positive) at the solution.
Eigen::VectorXd nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, std::vector<bool>& passive);

}  // namespace cubecal::noise::detail
