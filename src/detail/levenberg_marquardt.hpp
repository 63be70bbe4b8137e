// Nonlinear least squares, min sum r(p)^2, for the multi-position
// calibrations and the GMWM fit of composite noise models: Eigen's Levenberg-Marquardt (MINPACK's lmder: trust region,
// column scaling by the Jacobian's norms) driven one step at a time, and the
// covariance factor (J^T J)^-1 at the solution. Not an installed header.
#pragma once
#include <Eigen/Dense>
#include <cstddef>
#include <functional>

namespace cubecal::detail {

// Fills r (and J when given) at p; returns false when the residuals are not
// finite there (a trial step there is then rejected).
using EvalFn = std::function<bool(const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd* J)>;

struct LmOutcome {
  bool initial_finite = true;  // false: r or J not finite at the start (nothing else is set)
  Eigen::VectorXd p;
  double cost0 = 0.0;          // sum r^2 at the start
  double cost = 0.0;           // sum r^2 at the solution
  std::size_t iterations = 0;  // Jacobian evaluations (one per outer step)
  bool converged = false;      // a convergence test held before max_iterations
  bool determined = false;     // J^T J well conditioned at the solution
  Eigen::MatrixXd inv_jtj;     // (J^T J)^-1 at the solution (when determined)
  Eigen::MatrixXd J;           // Jacobian at the solution
  Eigen::VectorXd r;           // residuals at the solution
};

// Minimises sum r^2 from p0, at most max_iterations Jacobian evaluations.
// Residuals (or the Jacobian) not finite at p0: initial_finite = false.
// Throws CalibrationError (degenerate) when the Jacobian is not finite at an
// accepted point.
LmOutcome levenberg_marquardt(const EvalFn& eval, Eigen::VectorXd p0, std::size_t max_iterations);

// A central-difference Jacobian around a residual function: step
// 1e-6 max(|p_j|, typical_j).
EvalFn with_numeric_jacobian(std::function<bool(const Eigen::VectorXd&, Eigen::VectorXd&)> f, Eigen::VectorXd typical);

}  // namespace cubecal::detail
