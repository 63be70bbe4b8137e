// The power-law fit of a Welch spectrum: docs/formulas/spectral.md §5.
#include "cubecal/spectral/power_law_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/special_functions/digamma.hpp>
#include <boost/math/special_functions/trigamma.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>

#include "../detail/nnls.hpp"
#include "cubecal/error.hpp"
#include "detail/bin_covariance.hpp"
#include "cubecal/spectral/log_bins.hpp"

namespace cubecal {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr int kMaxPasses = 50;
constexpr double kConverged = 1e-10;
constexpr double kDominanceGridPerDecade = 200.0;

// The log bands of [f_lo, f_hi] with their mean densities and the
// normalized covariance C_GH of the band means (§3, §5.2).
struct Bands {
  std::vector<BinRun> runs;
  VectorXd density;
  MatrixXd corr;
  double f_lo = 0.0;
  double f_hi = 0.0;
};

Bands bands_of(const Psd& raw, std::size_t bins_per_decade, double f_lo, double f_hi) {
  Bands b;
  b.runs = log_band_runs(raw, bins_per_decade, f_lo, f_hi);
  const auto g = static_cast<Index>(b.runs.size());
  if (g == 0) return b;
  const BinCovariance cov(raw);
  b.density.resize(g);
  b.corr.resize(g, g);
  for (Index i = 0; i < g; ++i) {
    const BinRun& r = b.runs[static_cast<std::size_t>(i)];
    double s = 0.0;
    for (std::size_t k = r.first; k < r.first + r.count; ++k) s += raw.density[k];
    b.density(i) = s / static_cast<double>(r.count);
    for (Index j = 0; j <= i; ++j) {
      const BinRun& q = b.runs[static_cast<std::size_t>(j)];
      // The shorter run in the outer loop of between().
      const double c = r.count <= q.count ? cov.between(r.first, r.count, q.first, q.count)
                                          : cov.between(q.first, q.count, r.first, r.count);
      b.corr(i, j) = c;
      b.corr(j, i) = c;
    }
  }
  b.f_lo = raw.frequency[b.runs.front().first];
  const BinRun& last = b.runs.back();
  b.f_hi = raw.frequency[last.first + last.count - 1];
  return b;
}

// Geometric mean of the raw frequencies of a run.
double geometric_frequency(const Psd& raw, const BinRun& r) {
  double s = 0.0;
  for (std::size_t k = r.first; k < r.first + r.count; ++k) s += std::log(raw.frequency[k]);
  return std::exp(s / static_cast<double>(r.count));
}

// Mean of (f_k / f_ref)^alpha over a run: E[band mean] of the term.
double mean_power(const Psd& raw, const BinRun& r, double f_ref, double alpha) {
  double s = 0.0;
  for (std::size_t k = r.first; k < r.first + r.count; ++k) s += std::pow(raw.frequency[k] / f_ref, alpha);
  return s / static_cast<double>(r.count);
}

// Cholesky factor of diag(s) C diag(s); a covariance of band means is
// positive definite, but a nearly singular one (wide runs of a
// rectangular window) gets a ridge of 1e-12 of its diagonal.
Eigen::LLT<MatrixXd> factor(const MatrixXd& corr, const VectorXd& s) {
  MatrixXd sigma = s.asDiagonal() * corr * s.asDiagonal();
  Eigen::LLT<MatrixXd> llt(sigma);
  double ridge = 1e-12;
  while (llt.info() != Eigen::Success && ridge < 1.0) {
    MatrixXd r = sigma;
    r.diagonal() *= 1.0 + ridge;
    llt.compute(r);
    ridge *= 100.0;
  }
  return llt;
}

void check_exponents(const std::vector<int>& exps) {
  if (exps.empty()) throw UsageError(Field::exponents, "give at least one power-law exponent");
  std::set<int> seen;
  for (const int a : exps) {
    if (a < -4 || a > 4)
      throw UsageError(Field::exponents, "power-law exponents lie within -4..4 (" + std::to_string(a) + ")");
    if (!seen.insert(a).second)
      throw UsageError(Field::exponents, "the exponent " + std::to_string(a) + " is given twice");
  }
}

// The band fitted by default starts at raw bin kFirstFitBin: below it a
// tapered window leaks enough of a steep (f^-2) spectrum into the bin to
// bias it by more than about 1.5 % (§5.1), and detrending reaches the
// lowest bins (main_lobe_half_width); it ends below Nyquist.
constexpr std::size_t kFirstFitBin = 10;

std::pair<double, double> default_band(const Psd& raw, double min_hz, double max_hz) {
  const std::size_t first = std::max(kFirstFitBin, 2 * main_lobe_half_width(raw.window));
  const double lo = min_hz > 0.0 ? min_hz : static_cast<double>(first) * raw.resolution_hz();
  const double hi = max_hz > 0.0 ? max_hz : 0.5 * raw.rate_hz;
  return {lo, hi};
}

std::string hz(double f) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", f);
  return buf;
}

}  // namespace

const PowerLawTerm* PowerLawFit::term(int alpha) const noexcept {
  for (const auto& t : terms)
    if (t.alpha == alpha) return &t;
  return nullptr;
}

double PowerLawFit::density(double f) const noexcept {
  double s = 0.0;
  for (const auto& t : terms) s += t.h * std::pow(f, t.alpha);
  return s;
}

namespace {

// The weighted NNLS solution h of the normalized problem, with its passive
// set and the whitened system (a_w, b_w) of the final model's weights.
struct WeightedSolution {
  VectorXd h;
  std::vector<bool> passive;
  MatrixXd a_w;
  VectorXd b_w;
};

// Iteratively reweighted: the covariance of the band means is the model's
// S_G S_H C_GH; the first pass takes the measured densities for S.
WeightedSolution reweighted_fit(const Bands& b, const MatrixXd& x, const VectorXd& d, double floor, Index p) {
  WeightedSolution w;
  VectorXd& h = w.h;
  std::vector<bool>& passive = w.passive;
  MatrixXd& a_w = w.a_w;
  VectorXd& b_w = w.b_w;
  VectorXd s = d.cwiseMax(floor);
  h = VectorXd::Zero(p);
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const Eigen::LLT<MatrixXd> llt = factor(b.corr, s);
    a_w = llt.matrixL().solve(x);
    b_w = llt.matrixL().solve(d);
    VectorXd norm = a_w.colwise().norm().transpose();
    for (Index a = 0; a < p; ++a)
      if (!(norm(a) > 0.0)) norm(a) = 1.0;
    const MatrixXd scaled = a_w * norm.cwiseInverse().asDiagonal();
    h = noise::detail::nnls(scaled, b_w, passive).cwiseQuotient(norm);
    const VectorXd next = (x * h).cwiseMax(floor);
    const double change = ((next - s).cwiseAbs().cwiseQuotient(s)).maxCoeff();
    s = next;
    if (change < kConverged) break;
  }
  // Weights of the final model.
  {
    const Eigen::LLT<MatrixXd> llt = factor(b.corr, s);
    a_w = llt.matrixL().solve(x);
    b_w = llt.matrixL().solve(d);
  }
  return w;
}

// The terms in the data's units, with the covariance of the free ones.
void terms_in_units(PowerLawFit& fit, const std::vector<int>& exponents, const VectorXd& h,
                    const std::vector<Index>& free, const MatrixXd& cov_free, double d_ref, double f_ref) {
  const auto p = static_cast<Index>(exponents.size());
  // Back to the data's units: h_alpha = h'_alpha d_ref / f_ref^alpha.
  std::vector<double> unit(static_cast<std::size_t>(p));
  for (Index a = 0; a < p; ++a)
    unit[static_cast<std::size_t>(a)] =
        d_ref / std::pow(f_ref, static_cast<double>(exponents[static_cast<std::size_t>(a)]));
  for (Index a = 0; a < p; ++a) {
    PowerLawTerm& t = fit.terms[static_cast<std::size_t>(a)];
    t.h = h(a) * unit[static_cast<std::size_t>(a)];
  }
  for (std::size_t i = 0; i < free.size(); ++i) {
    const auto ai = static_cast<std::size_t>(free[i]);
    fit.terms[ai].valid = true;
    fit.terms[ai].sigma = std::sqrt(cov_free(static_cast<Index>(i), static_cast<Index>(i))) * unit[ai];
    for (std::size_t j = 0; j < free.size(); ++j) {
      const auto aj = static_cast<std::size_t>(free[j]);
      fit.covariance(ai, aj) = cov_free(static_cast<Index>(i), static_cast<Index>(j)) * unit[ai] * unit[aj];
    }
  }
}

// Where each term is at least half of the model.
void dominance_bands(PowerLawFit& fit) {
  const double decades = std::log10(fit.f_hi / fit.f_lo);
  const auto points = static_cast<std::size_t>(std::ceil(decades * kDominanceGridPerDecade)) + 1;
  for (auto& t : fit.terms) {
    if (!t.valid) continue;
    for (std::size_t i = 0; i < points; ++i) {
      const double f =
          points == 1 ? fit.f_lo
                      : fit.f_lo * std::pow(10.0, decades * static_cast<double>(i) / static_cast<double>(points - 1));
      if (t.h * std::pow(f, t.alpha) >= 0.5 * fit.density(f)) {
        if (t.f_lo == 0.0) t.f_lo = f;
        t.f_hi = f;
      }
    }
  }
}

}  // namespace

PowerLawFit fit_power_law(const Psd& raw, const PowerLawFitOptions& options) {
  check_exponents(options.exponents);
  if (raw.bins_per_decade != 0) throw std::invalid_argument("fit_power_law: give the raw spectrum");
  const auto [lo, hi] = default_band(raw, options.min_frequency_hz, options.max_frequency_hz);
  const Bands b = bands_of(raw, options.bins_per_decade, lo, hi);
  const auto p = static_cast<Index>(options.exponents.size());
  const auto g = static_cast<Index>(b.runs.size());
  if (g < p + 1)
    throw UsageError(Field::fit_range, "the band " + hz(lo) + ".." + hz(hi) + " Hz holds " + std::to_string(g) +
                                           " log bands, fewer than the " + std::to_string(p + 1) + " a fit of " +
                                           std::to_string(p) + " terms needs (widen the band or use longer segments)");

  PowerLawFit fit;
  fit.f_lo = b.f_lo;
  fit.f_hi = b.f_hi;
  fit.bands = static_cast<std::size_t>(g);
  for (const int a : options.exponents) fit.terms.push_back({a, 0.0, 0.0, false, 0.0, 0.0});
  fit.covariance = Matrix(static_cast<std::size_t>(p), static_cast<std::size_t>(p));

  // Normalized: frequencies by the geometric mean of the bands', densities
  // by the geometric mean of the positive band densities.
  std::vector<double> fg(static_cast<std::size_t>(g));
  double log_f = 0.0;
  double log_d = 0.0;
  Index positive = 0;
  for (Index i = 0; i < g; ++i) {
    fg[static_cast<std::size_t>(i)] = geometric_frequency(raw, b.runs[static_cast<std::size_t>(i)]);
    log_f += std::log(fg[static_cast<std::size_t>(i)]);
    if (b.density(i) > 0.0) {
      log_d += std::log(b.density(i));
      ++positive;
    }
  }
  if (positive == 0) {
    fit.dof = fit.bands;
    return fit;  // a spectrum that is zero everywhere: no term
  }
  const double f_ref = std::exp(log_f / static_cast<double>(g));
  const double d_ref = std::exp(log_d / static_cast<double>(positive));
  MatrixXd x(g, p);
  for (Index i = 0; i < g; ++i)
    for (Index a = 0; a < p; ++a)
      x(i, a) = mean_power(raw, b.runs[static_cast<std::size_t>(i)], f_ref,
                           static_cast<double>(options.exponents[static_cast<std::size_t>(a)]));
  const VectorXd d = b.density / d_ref;
  const double floor = 1e-12 * d.maxCoeff();

  WeightedSolution w = reweighted_fit(b, x, d, floor, p);
  const VectorXd& h = w.h;
  const std::vector<bool>& passive = w.passive;
  const MatrixXd& a_w = w.a_w;
  const VectorXd& b_w = w.b_w;
  fit.chi2 = (a_w * h - b_w).squaredNorm();
  std::vector<Index> free;
  for (Index a = 0; a < p; ++a)
    if (passive[static_cast<std::size_t>(a)] && h(a) > 0.0) free.push_back(a);
  fit.dof = static_cast<std::size_t>(g) - free.size();
  fit.scale = fit.dof > 0 ? std::max(1.0, fit.chi2 / static_cast<double>(fit.dof)) : 1.0;
  MatrixXd cov_free;
  if (!free.empty()) {
    MatrixXd af(g, static_cast<Index>(free.size()));
    for (std::size_t c = 0; c < free.size(); ++c) af.col(static_cast<Index>(c)) = a_w.col(free[c]);
    cov_free = (af.transpose() * af).ldlt().solve(MatrixXd::Identity(af.cols(), af.cols())) * fit.scale;
  }
  terms_in_units(fit, options.exponents, h, free, cov_free, d_ref, f_ref);
  dominance_bands(fit);
  return fit;
}

SlopeFit fit_slope(const Psd& raw, double f_lo, double f_hi, std::size_t bins_per_decade) {
  if (raw.bins_per_decade != 0) throw std::invalid_argument("fit_slope: give the raw spectrum");
  const Bands b = bands_of(raw, bins_per_decade, f_lo, f_hi);
  const auto g = static_cast<Index>(b.runs.size());
  if (g < 3)
    throw UsageError(Field::fit_range, "the band " + hz(f_lo) + ".." + hz(f_hi) + " Hz holds " + std::to_string(g) +
                                           " log bands; a slope needs at least 3");
  SlopeFit out;
  out.bands = static_cast<std::size_t>(g);
  double log_f = 0.0;
  for (const BinRun& r : b.runs) log_f += std::log(geometric_frequency(raw, r));
  out.f_ref = std::exp(log_f / static_cast<double>(g));
  // ln D_G less its chi-squared bias; trigamma(nu/2) its variance, the
  // normalized covariance of the means between bands (delta method).
  VectorXd y(g);
  MatrixXd v = b.corr;
  for (Index i = 0; i < g; ++i) {
    if (!(b.density(i) > 0.0))
      throw UsageError(Field::fit_range, "the spectrum is zero near " +
                                             hz(raw.frequency[b.runs[static_cast<std::size_t>(i)].first]) + " Hz");
    const double half_nu = 1.0 / b.corr(i, i);  // nu / 2 = 1 / C_GG
    y(i) = std::log(b.density(i)) - (boost::math::digamma(half_nu) - std::log(half_nu));
    v(i, i) = boost::math::trigamma(half_nu);
  }
  const Eigen::LLT<MatrixXd> llt(v);
  double slope = 0.0;
  Eigen::Vector2d beta = Eigen::Vector2d::Zero();
  MatrixXd x(g, 2);
  // E[ln D_G] = ln A + ln mean_k (f_k / f_ref)^slope: the abscissa depends
  // on the slope; three passes settle it.
  for (int pass = 0; pass < 4; ++pass) {
    for (Index i = 0; i < g; ++i) {
      const BinRun& r = b.runs[static_cast<std::size_t>(i)];
      x(i, 0) = 1.0;
      x(i, 1) = std::abs(slope) > 1e-9 ? std::log(mean_power(raw, r, out.f_ref, slope)) / slope
                                       : std::log(geometric_frequency(raw, r) / out.f_ref);
    }
    const MatrixXd xw = llt.matrixL().solve(x);
    const VectorXd yw = llt.matrixL().solve(y);
    beta = (xw.transpose() * xw).ldlt().solve(xw.transpose() * yw);
    slope = beta(1);
  }
  const MatrixXd xw = llt.matrixL().solve(x);
  const VectorXd yw = llt.matrixL().solve(y);
  out.chi2 = (xw * beta - yw).squaredNorm();
  out.dof = static_cast<std::size_t>(g) - 2;
  const double scale = out.dof > 0 ? std::max(1.0, out.chi2 / static_cast<double>(out.dof)) : 1.0;
  const Eigen::Matrix2d cov = (xw.transpose() * xw).inverse() * scale;
  out.slope = beta(1);
  out.slope_sigma = std::sqrt(cov(1, 1));
  out.level = std::exp(beta(0));
  out.level_sigma = out.level * std::sqrt(cov(0, 0));
  return out;
}

}  // namespace cubecal
