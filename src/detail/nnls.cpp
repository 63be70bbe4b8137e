// Lawson & Hanson's active-set NNLS (1974, ch. 23).
#include "nnls.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace cubecal::noise::detail {

using Eigen::Index;

Eigen::VectorXd nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, std::vector<bool>& passive) {
  const Eigen::Index n = a.cols();
  passive.assign(static_cast<std::size_t>(n), false);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  if (a.rows() == 0 || n == 0) return x;

  // Gradient components below this are round-off (scale-free: A's 1-norm
  // times b's size, as scipy's nnls).
  const double tol = 10.0 * std::numeric_limits<double>::epsilon() * static_cast<double>(std::max(a.rows(), n)) *
                     a.cwiseAbs().colwise().sum().maxCoeff() * b.norm();

  const auto solve_passive = [&]() {
    std::vector<Index> cols;
    for (Index j = 0; j < n; ++j)
      if (passive[static_cast<std::size_t>(j)]) cols.push_back(j);
    Eigen::MatrixXd ap(a.rows(), static_cast<Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k) ap.col(static_cast<Index>(k)) = a.col(cols[k]);
    const Eigen::VectorXd sp = ap.colPivHouseholderQr().solve(b);
    Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < cols.size(); ++k) s(cols[k]) = sp(static_cast<Index>(k));
    return s;
  };

  // An unknown whose unconstrained value comes out <= 0 the moment it is
  // freed is not retried until the free set changes otherwise: round-off in
  // its gradient would cycle forever.
  std::vector<bool> blocked(static_cast<std::size_t>(n), false);
  const int max_outer = 10 * static_cast<int>(n) + 10;
  for (int outer = 0; outer < max_outer; ++outer) {
    const Eigen::VectorXd w = a.transpose() * (b - a * x);
    Index t = -1;
    double w_max = tol;
    for (Index j = 0; j < n; ++j) {
      const auto uj = static_cast<std::size_t>(j);
      if (!passive[uj] && !blocked[uj] && w(j) > w_max) {
        w_max = w(j);
        t = j;
      }
    }
    if (t < 0) break;
    passive[static_cast<std::size_t>(t)] = true;

    Eigen::VectorXd s = solve_passive();
    bool changed_other = false;
    for (int inner = 0; inner < 10 * static_cast<int>(n) + 10; ++inner) {
      Index worst = -1;
      double alpha = 1.0;
      for (Index j = 0; j < n; ++j) {
        if (!passive[static_cast<std::size_t>(j)] || s(j) > 0.0) continue;
        const double den = x(j) - s(j);
        const double aj = den > 0.0 ? x(j) / den : 0.0;
        if (worst < 0 || aj < alpha) {
          alpha = aj;
          worst = j;
        }
      }
      if (worst < 0) break;
      x += alpha * (s - x);
      x(worst) = 0.0;
      for (Index j = 0; j < n; ++j) {
        const auto uj = static_cast<std::size_t>(j);
        if (passive[uj] && x(j) <= 0.0) {
          passive[uj] = false;
          x(j) = 0.0;
          if (j != t) changed_other = true;
        }
      }
      s = solve_passive();
    }
    const bool t_kept = passive[static_cast<std::size_t>(t)];
    if (t_kept || changed_other) std::fill(blocked.begin(), blocked.end(), false);
    if (!t_kept) blocked[static_cast<std::size_t>(t)] = true;
    x = s;
  }
  return x;
}

}  // namespace cubecal::noise::detail
