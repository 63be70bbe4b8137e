#include "cubecal/noise/streaming_temperature.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "cubecal/error.hpp"
#include "detail/temperature_regressor.hpp"
#include "detail/temperature_solution.hpp"

namespace cubecal {

namespace {

constexpr std::size_t kMaxBlocks = 1280;

// sum u^k from sum v^j, u = (v - a) / h: the binomial expansion.
void rescale(const double* mv, std::size_t kmax, double a, double h, double* mu) {
  for (std::size_t k = 0; k <= kmax; ++k) {
    double s = 0.0, binom = 1.0;  // C(k, j)
    for (std::size_t j = 0; j <= k; ++j) {
      s += binom * std::pow(-a, static_cast<double>(k - j)) * mv[j];
      binom = binom * static_cast<double>(k - j) / static_cast<double>(j + 1);
    }
    mu[k] = s / std::pow(h, static_cast<double>(k));
  }
}

}  // namespace

void StreamingTemperatureFit::Sums::merge(const Sums& o) noexcept {
  n += o.n;
  for (std::size_t j = 0; j < 11; ++j) m[j] += o.m[j];
  for (std::size_t j = 0; j < 6; ++j) yv[j] += o.yv[j];
  yy += o.yy;
}

StreamingTemperatureFit::StreamingTemperatureFit(std::size_t order) : order_(order) {
  if (order < 1 || order > 5) throw CalibrationError(CalibrationReason::bad_option, "temperature order must be 1 to 5");
}

void StreamingTemperatureFit::close_block() {
  blocks_.push_back(current_);
  current_ = Sums{};
  if (blocks_.size() == kMaxBlocks) {
    for (std::size_t b = 0; b < kMaxBlocks / 2; ++b) {
      Sums s = blocks_[2 * b];
      s.merge(blocks_[2 * b + 1]);
      blocks_[b] = s;
    }
    blocks_.resize(kMaxBlocks / 2);
    block_len_ *= 2;
  }
}

void StreamingTemperatureFit::add(std::span<const double> y, std::span<const double> temp) {
  if (y.size() != temp.size())
    throw CalibrationError(CalibrationReason::bad_data, "temperature and data lengths differ");
  if (y.empty()) return;
  if (!started_) {
    t0_ = tmin_ = tmax_ = temp[0];
    y0_ = y[0];
    started_ = true;
  }
  const std::size_t p = order_ + 1;
  const std::size_t mmax = 2 * order_;
  std::size_t i = 0;
  while (i < y.size()) {
    const std::size_t take = std::min(block_len_ - current_.n, y.size() - i);
    Sums& s = current_;
    for (std::size_t j = i; j < i + take; ++j) {
      const double t = temp[j];
      tmin_ = std::min(tmin_, t);
      tmax_ = std::max(tmax_, t);
      if (distinct_.size() < p && std::find(distinct_.begin(), distinct_.end(), t) == distinct_.end())
        distinct_.push_back(t);
      const double v = t - t0_;
      const double yc = y[j] - y0_;
      double pw = 1.0;
      for (std::size_t k = 0; k <= mmax; ++k, pw *= v) {
        s.m[k] += pw;
        if (k < p) s.yv[k] += pw * yc;
      }
      s.yy += yc * yc;
    }
    s.n += take;
    n_ += take;
    i += take;
    if (current_.n == block_len_) close_block();
  }
}

TemperatureFit StreamingTemperatureFit::finish() const {
  const std::size_t p = order_ + 1;
  const std::size_t mmax = 2 * order_;
  if (n_ <= p)
    throw CalibrationError(CalibrationReason::too_few_points,
                           "too few samples for a temperature fit of order " + std::to_string(order_));
  noise::detail::TemperatureRegressor reg;
  Sums all;
  for (const Sums& b : blocks_) all.merge(b);
  all.merge(current_);
  const double nd = static_cast<double>(n_);
  reg.t_ref = t0_ + all.m[1] / nd;
  reg.half_span = 0.5 * (tmax_ - tmin_);
  if (!(reg.half_span > 0.0))
    throw CalibrationError(CalibrationReason::degenerate,
                           "temperature is constant over the record: no coefficient can be estimated");
  if (distinct_.size() < p) noise::detail::throw_too_few_distinct(order_);
  const double a = reg.t_ref - t0_;
  const double dy = all.yv[0] / nd;  // mean y - y0
  const double ymean = y0_ + dy;
  // A set of sums in u, with y about its mean: sum u^k and sum u^k (y - mean).
  const auto in_u = [&](const Sums& s, double* mu, double* yu) {
    rescale(s.m, mmax, a, reg.half_span, mu);
    rescale(s.yv, order_, a, reg.half_span, yu);
    for (std::size_t k = 0; k < p; ++k) yu[k] -= dy * mu[k];
  };
  const auto pe = static_cast<Eigen::Index>(p);
  double mu[11], yu[6];
  in_u(all, mu, yu);
  Eigen::MatrixXd ata(pe, pe);
  Eigen::VectorXd aty(pe);
  for (Eigen::Index r = 0; r < pe; ++r) {
    aty(r) = yu[r];
    for (Eigen::Index c = 0; c < pe; ++c) ata(r, c) = mu[r + c];
  }
  const noise::detail::TemperatureSolution sol = noise::detail::solve_temperature(ata, aty, order_);
  const double ss_tot = all.yy - nd * dy * dy;
  const double ss_res = std::max(0.0, ss_tot - 2.0 * sol.cu.dot(aty) + sol.cu.dot(ata * sol.cu));
  // Score sums per batch: each block goes to the batch of its middle sample.
  const std::size_t batches = noise::detail::temperature_batches(n_, p);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(pe, static_cast<Eigen::Index>(batches));
  std::size_t start = 0;
  const auto add_block = [&](const Sums& s) {
    if (s.n == 0) return;
    double bm[11], by[6];
    in_u(s, bm, by);
    const auto b = static_cast<Eigen::Index>((start + s.n / 2) * batches / n_);
    for (std::size_t k = 0; k < p; ++k) {
      double e = by[k];
      for (std::size_t j = 0; j < p; ++j) e -= sol.cu(static_cast<Eigen::Index>(j)) * bm[k + j];
      g(static_cast<Eigen::Index>(k), b) += e;
    }
    start += s.n;
  };
  for (const Sums& s : blocks_) add_block(s);
  add_block(current_);
  return noise::detail::temperature_fit_from(sol, ymean, g, ss_res, ss_tot, n_, reg, order_);
}

}  // namespace cubecal
