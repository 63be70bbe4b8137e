// Eigen's Levenberg-Marquardt (unsupported module, MINPACK lmder) behind the
// EvalFn interface of the multi-position calibrations and the GMWM fit.
#include "levenberg_marquardt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unsupported/Eigen/LevenbergMarquardt>
#include <utility>

#include "cubecal/error.hpp"

namespace cubecal::detail {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// The functor Eigen's solver calls. Non-finite residuals at a trial point are
// reported as +infinity: the step is rejected and the trust region shrinks.
struct Functor {
  using Scalar = double;
  using InputType = VectorXd;
  using ValueType = VectorXd;
  using JacobianType = MatrixXd;
  using QRSolver = Eigen::ColPivHouseholderQR<MatrixXd>;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const EvalFn* eval = nullptr;
  Eigen::Index n_inputs = 0;
  Eigen::Index n_values = 0;
  bool jacobian_failed = false;

  Eigen::Index inputs() const { return n_inputs; }
  Eigen::Index values() const { return n_values; }

  int operator()(const VectorXd& p, VectorXd& r) const {
    if (!(*eval)(p, r, nullptr) || r.size() != n_values)
      r.setConstant(n_values, std::numeric_limits<double>::infinity());
    return 0;
  }
  int df(const VectorXd& p, MatrixXd& J) {
    VectorXd r;
    if (!(*eval)(p, r, &J) || !J.allFinite()) {
      jacobian_failed = true;
      return -1;
    }
    return 0;
  }
};

// Column norms of J (1 for a zero column), the Jacobi scaling.
VectorXd column_scale(const MatrixXd& J) {
  VectorXd d(J.cols());
  for (Eigen::Index j = 0; j < J.cols(); ++j) {
    const double n = J.col(j).norm();
    d(j) = n > 0.0 && std::isfinite(n) ? n : 1.0;
  }
  return d;
}

// The statuses of a convergence test that held (MINPACK's info 1-8 but 5).
bool converged(Eigen::LevenbergMarquardtSpace::Status s) {
  using namespace Eigen::LevenbergMarquardtSpace;
  return s == RelativeReductionTooSmall || s == RelativeErrorTooSmall || s == RelativeErrorAndReductionTooSmall ||
         s == CosinusTooSmall || s == FtolTooSmall || s == XtolTooSmall || s == GtolTooSmall;
}

}  // namespace

LmOutcome levenberg_marquardt(const EvalFn& eval, VectorXd p, std::size_t max_iterations) {
  LmOutcome out;
  VectorXd r;
  MatrixXd J0;
  if (!eval(p, r, &J0)) {
    out.initial_finite = false;
    return out;
  }
  out.cost0 = r.squaredNorm();

  Functor f;
  f.eval = &eval;
  f.n_inputs = p.size();
  f.n_values = r.size();
  Eigen::LevenbergMarquardt<Functor> lm(f);
  // Relative reduction of the cost and relative step: 1e-12 (the solution to
  // the digits a double cost resolves); the gradient test: cosine 1e-15.
  lm.setFtol(1e-12);
  lm.setXtol(1e-12);
  lm.setGtol(1e-15);
  lm.setMaxfev(static_cast<Eigen::Index>(100 * (max_iterations + 1)));
  Eigen::LevenbergMarquardtSpace::Status status = Eigen::LevenbergMarquardtSpace::Running;
  std::size_t steps = 0;
  // Fewer residuals than parameters: nothing to iterate, and the parameters
  // are not determined (J^T J singular below).
  if (r.size() >= p.size()) {
    status = lm.minimizeInit(p);  // NotStarted, or ImproperInputParameters
    if (status == Eigen::LevenbergMarquardtSpace::NotStarted) {
      do {
        status = lm.minimizeOneStep(p);
        ++steps;
      } while (status == Eigen::LevenbergMarquardtSpace::Running && steps < max_iterations);
    }
  }
  if (f.jacobian_failed) throw CalibrationError(CalibrationReason::degenerate, "non-finite Jacobian during the fit");
  out.iterations = steps;
  out.converged = steps > 0 && converged(status);

  out.p = p;
  MatrixXd J;
  if (!eval(p, out.r, &J) || !J.allFinite())
    throw CalibrationError(CalibrationReason::degenerate, "non-finite Jacobian during the fit");
  out.cost = out.r.squaredNorm();
  out.J = J;
  // (J^T J)^-1 through the scaled normal matrix.
  const VectorXd d = column_scale(J);
  const MatrixXd Js = J * d.cwiseInverse().asDiagonal();
  const MatrixXd A = Js.transpose() * Js;
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(A);
  const double emax = es.eigenvalues().maxCoeff();
  const double emin = es.eigenvalues().minCoeff();
  out.determined = es.info() == Eigen::Success && emax > 0.0 && emin > 1e-12 * emax;
  if (out.determined) {
    const MatrixXd Ainv =
        es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    out.inv_jtj = d.cwiseInverse().asDiagonal() * Ainv * d.cwiseInverse().asDiagonal();
  }
  return out;
}

EvalFn with_numeric_jacobian(std::function<bool(const VectorXd&, VectorXd&)> f, VectorXd typical) {
  return [f = std::move(f), typical = std::move(typical)](const VectorXd& p, VectorXd& r, MatrixXd* J) {
    if (!f(p, r)) return false;
    if (!J) return true;
    J->resize(r.size(), p.size());
    VectorXd rp, rm;
    for (Eigen::Index j = 0; j < p.size(); ++j) {
      const double h = 1e-6 * std::max(std::abs(p(j)), typical(j));
      VectorXd pp = p, pm = p;
      pp(j) += h;
      pm(j) -= h;
      if (!f(pp, rp) || !f(pm, rm)) return false;
      J->col(j) = (rp - rm) / (pp(j) - pm(j));
    }
    return J->allFinite();
  };
}

}  // namespace cubecal::detail
