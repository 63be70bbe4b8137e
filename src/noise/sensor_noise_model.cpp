// The paper's random-walk bias model and the bounded Gauss-Markov
// alternative: exact discrete Allan variances and fits to a measured curve.
//
// Both models are sampled processes, so their Allan variances are written
// for the averaging factor m (tau = m dt), not for continuous tau:
//   white (with quantization as white noise):  (sigma_n^2 + q^2) / m,  q^2 = 1/(12 lsb^2)
//   random-walk bias, step s = sigma_mu dt:    s^2 (2 m^2 + 1) / (6 m)      (docs/formulas/noise-terms.md §4.2)
//   AR(1) bias, phi = exp(-dt/T_c):            sigma_b^2 / (m^2 (1-phi)^2)
//                                              * [m (1-phi^2) - phi (1-phi^m)(3-phi^m)]  (§5.2)
#include "cubecal/noise/sensor_noise_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Variance of the quantization error of int(w * lsb) / lsb, taken as white
// noise uniform over one LSB (valid when the noise spans a few LSBs).
double quantization_variance(double lsb) noexcept { return lsb > 0.0 ? 1.0 / (12.0 * lsb * lsb) : 0.0; }

// (2 m^2 + 1) / (6 m): the exact discrete AVAR of a random walk with unit
// increment variance, written so that it cannot overflow for large m.
double rw_factor(double m) noexcept { return m / 3.0 + 1.0 / (6.0 * m); }

// Exact discrete AVAR of a stationary AR(1) sequence of unit variance,
// phi = exp(-a), at averaging factor m. The closed form
//   B / (m^2 (1-phi)^2),  B = m (1-phi^2) - phi (1-phi^m)(3-phi^m)
// cancels catastrophically when m*a is small (B ~ a^3 m^3 while its terms
// are ~ 2 m a): a correlation time of 1e6 samples leaves no digit. There the
// Taylor series of B = m - m e^{-2a} - 3 e^{-a} + 4 e^{-(m+1)a} - e^{-(2m+1)a}
// is used; its a^0, a^1 and a^2 coefficients vanish identically and the a^3
// term is a^3 m (2 m^2 + 1) / 3 (the random-walk limit).
double ar1_avar_unit(double a, double m) noexcept {
  if (!(a >= 0.0) || !(m >= 1.0)) return kNaN;
  if (a == 0.0) return 0.0;  // T_c infinite: the bias is a constant
  const double one_minus_phi = -std::expm1(-a);
  const double denom = m * m * one_minus_phi * one_minus_phi;
  if (m * a < 0.25) {
    // B = sum_{k>=3} (-1)^k / k! [4((m+1)a)^k - ((2m+1)a)^k - m (2a)^k - 3 a^k]
    const double x1 = (m + 1.0) * a;
    const double x2 = (2.0 * m + 1.0) * a;
    const double x3 = 2.0 * a;
    double p1 = x1 * x1, p2 = x2 * x2, p3 = x3 * x3, p4 = a * a;  // k = 2 powers
    double fact = 2.0;
    double sum = 0.0;
    for (int k = 3; k < 80; ++k) {
      p1 *= x1;
      p2 *= x2;
      p3 *= x3;
      p4 *= a;
      fact *= k;
      const double term = (4.0 * p1 - p2 - m * p3 - 3.0 * p4) / fact;
      sum += (k % 2 == 0) ? term : -term;
      if (k > 4 && std::abs(term) <= 1e-18 * std::abs(sum)) break;
    }
    return sum / denom;
  }
  const double phi = std::exp(-a);
  const double one_minus_phi2 = -std::expm1(-2.0 * a);
  const double v = -std::expm1(-m * a);  // 1 - phi^m
  // 3 - phi^m = 2 + v
  const double b = m * one_minus_phi2 - phi * v * (2.0 + v);
  return std::max(b, 0.0) / denom;
}

void require(bool ok, CalibrationReason reason, const std::string& what) {
  if (!ok) throw CalibrationError(reason, what);
}

// Checks the parallel arrays the fits read (tau, dev, edf; lo/hi unused).
void validate_curve(const AllanCurve& c, const char* who, std::size_t min_points) {
  const std::string w(who);
  using R = CalibrationReason;
  require(c.dev.size() == c.tau.size(), R::bad_data,
          w + ": Allan curve has " + std::to_string(c.tau.size()) + " taus but " + std::to_string(c.dev.size()) +
              " deviations");
  require(c.edf.empty() || c.edf.size() == c.tau.size(), R::bad_data,
          w + ": Allan curve has " + std::to_string(c.tau.size()) + " taus but " + std::to_string(c.edf.size()) +
              " EDF values");
  require(c.size() >= min_points, R::too_few_points,
          w + ": Allan curve has " + std::to_string(c.size()) + " points; at least " + std::to_string(min_points) +
              " are needed");
  for (std::size_t i = 0; i < c.size(); ++i) {
    require(std::isfinite(c.tau[i]) && c.tau[i] > 0.0, R::bad_data,
            w + ": tau[" + std::to_string(i) + "] is not a positive finite number");
    require(std::isfinite(c.dev[i]) && c.dev[i] > 0.0, R::bad_data,
            w + ": deviation at tau[" + std::to_string(i) + "] is not a positive finite number");
    require(i == 0 || c.tau[i] > c.tau[i - 1], R::bad_data, w + ": taus are not strictly ascending");
    if (!c.edf.empty())
      require(std::isfinite(c.edf[i]) && c.edf[i] > 0.0, R::bad_data,
              w + ": EDF at tau[" + std::to_string(i) + "] is not a positive finite number");
  }
}

void validate_period(double dt, double lsb, const char* who) {
  const std::string w(who);
  require(std::isfinite(dt) && dt > 0.0, CalibrationReason::bad_option, w + ": the sample period must be positive");
  require(std::isfinite(lsb) && lsb >= 0.0, CalibrationReason::bad_option,
          w + ": the LSB (counts per unit) must be positive, or 0 for no quantization");
}

// Averaging factor of a curve point: round(tau/dt), at least 1.
double factor_of(double tau, double dt) noexcept { return std::max(1.0, std::round(tau / dt)); }

// Equivalent degrees of freedom of a point; 1 for every point when the curve
// carries none (equal relative weights).
double edf_of(const AllanCurve& c, std::size_t i) noexcept { return c.edf.empty() ? 1.0 : c.edf[i]; }

// Uncertainty band of a point for deciding whether the curve really rises:
// the curve's own interval when it has a usable one, else one sigma from the
// EDF (the relative standard deviation of a deviation estimate is about
// 1/sqrt(2 edf)), else the point itself.
struct Band {
  double lo, hi;
};
Band band_of(const AllanCurve& c, std::size_t i, bool use_interval) noexcept {
  if (use_interval) return {c.interval[i].lo, c.interval[i].hi};
  if (!c.edf.empty()) {
    const double r = 1.0 / std::sqrt(2.0 * c.edf[i]);
    return {c.dev[i] * std::max(0.0, 1.0 - r), c.dev[i] * (1.0 + r)};
  }
  return {c.dev[i], c.dev[i]};
}

// Bottom of the V: the running minimum of the curve at the first point that
// lies significantly above it (its band wholly above the minimum's band), or
// the global minimum when the curve never rises significantly. The tail of
// a measured curve has a few degrees of freedom only; a chance dip there
// (10 % of 42000-sample records of the paper's own y-axis model put their
// global minimum at the last tau) is not the V the paper adjusted to, and
// neither is the falling tail of a Gauss-Markov curve beyond its peak.
std::size_t v_bottom(const AllanCurve& c) {
  const std::size_t n = c.size();
  bool use_interval = c.interval.size() == n;
  for (std::size_t i = 0; use_interval && i < n; ++i)
    use_interval = std::isfinite(c.interval[i].lo) && std::isfinite(c.interval[i].hi) && c.interval[i].lo > 0.0 &&
                   c.interval[i].lo <= c.dev[i] && c.dev[i] <= c.interval[i].hi;
  std::size_t r = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (c.dev[i] < c.dev[r]) {
      r = i;
    } else if (band_of(c, i, use_interval).lo > band_of(c, r, use_interval).hi) {
      return r;
    }
  }
  return r;
}

template <class Model>
ModelResidual residual_impl(const Model& model, const AllanCurve& curve, const char* who) {
  validate_curve(curve, who, 1);
  validate_period(model.dt, model.lsb, who);
  ModelResidual r;
  double sum_log2 = 0.0;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const double var = avar(model, static_cast<std::size_t>(factor_of(curve.tau[i], model.dt)));
    const double meas = curve.dev[i] * curve.dev[i];
    if (!(var > 0.0)) {
      // A model with no noise cannot be compared in log: infinitely far.
      r.rms_log = std::numeric_limits<double>::infinity();
      r.chi2 = std::numeric_limits<double>::infinity();
      return r;
    }
    const double l = 0.5 * std::log(var / meas);
    sum_log2 += l * l;
    const double d = var / meas - 1.0;
    r.chi2 += 0.5 * edf_of(curve, i) * d * d;
  }
  r.rms_log = std::sqrt(sum_log2 / static_cast<double>(curve.size()));
  return r;
}

}  // namespace

double avar(const RandomWalkModel& model, std::size_t m) noexcept {
  if (m == 0 || !(model.dt > 0.0)) return kNaN;
  const double md = static_cast<double>(m);
  const double white = model.sigma_n * model.sigma_n + quantization_variance(model.lsb);
  const double s = model.sigma_mu * model.dt;  // bias increment per step
  return white / md + s * s * rw_factor(md);
}

double avar(const GaussMarkovModel& model, std::size_t m) noexcept {
  if (m == 0 || !(model.dt > 0.0) || !(model.tau_c >= 0.0)) return kNaN;
  const double md = static_cast<double>(m);
  const double white = model.sigma_n * model.sigma_n + quantization_variance(model.lsb);
  double gm = 0.0;
  if (model.sigma_b != 0.0) {
    // tau_c = 0: phi = 0, the "bias" is white with variance sigma_b^2.
    const double a = model.tau_c > 0.0 ? model.dt / model.tau_c : std::numeric_limits<double>::infinity();
    gm = std::isinf(a) ? 1.0 / md : ar1_avar_unit(a, md);
    gm *= model.sigma_b * model.sigma_b;
  }
  return white / md + gm;
}

// The paper's adjustment (docs/paper.md §2.4): "tangent to the left arm of AV and the
// same bias instability (minimum point of the AV)".
//
// Minimum point: the bottom of the V (v_bottom above), not blindly the
// lowest point of the whole curve.
//
// Tangent: the white line sigma(tau) = N / sqrt(tau) tangent from below to
// the well-measured points left of the minimum (allan_curve.hpp),
// N^2 = min_i dev_i^2 tau_i. We
// choose to make the model's WHITE PART equal that line, N^2 / dt =
// sigma_n^2 + q^2 (the quantization share comes off sigma_n). With the
// random-walk term added the model curve at small tau sits slightly above the
// line, by s^2 (2m^2+1)/(6m) over (sigma_n^2+q^2)/m: 3e-4 relative at m = 1 for
// the paper's x axis, far inside the scatter of a measured point.
//
// Same minimum: the continuous model gives sigma_min^2 = 2 sigma_w sigma_mu dt
// / sqrt(3) (sigma_w^2 = sigma_n^2 + q^2), i.e. sigma_mu = sqrt(3) sigma_min^2 /
// (2 sigma_w dt). We solve the exact discrete condition instead, on the
// curve's own averaging factors m_i = round(tau_i / dt) -- the model curve the
// paper overlaid on the measured one (Fig. 2) has the same lowest point as
// the measured curve on that tau grid. With S = (sigma_mu dt)^2 each model
// point is w/m_i + S r_i (r_i = (2 m_i^2 + 1)/(6 m_i)), so min_i is concave,
// piecewise linear and increasing in S, and
//   min_i (w/m_i + S r_i) = sigma_min^2   <=>   S = max_i (sigma_min^2 - w/m_i) / r_i
// exactly: no iteration, and no grid-resolution error (on a dense grid this
// is the continuous minimum; on an octave grid both curves are read the same
// way).
RandomWalkModel fit_random_walk_model(const AllanCurve& curve, double dt, double lsb) {
  constexpr const char* who = "random-walk model fit";
  validate_curve(curve, who, 3);
  validate_period(dt, lsb, who);
  const std::size_t n = curve.size();
  const std::size_t imin = v_bottom(curve);
  if (imin == 0)
    throw CalibrationError(CalibrationReason::degenerate,
                           "random-walk model fit: the Allan curve has no white-noise arm (it rises from the first "
                           "tau, " +
                               std::to_string(curve.tau.front()) +
                               " s); the model needs a falling left arm and a minimum");
  if (imin == n - 1)
    throw CalibrationError(CalibrationReason::degenerate,
                           "random-walk model fit: the Allan curve has no minimum inside its tau range (it still "
                           "falls at the last tau, " +
                               std::to_string(curve.tau.back()) + " s); use a longer record or a larger maximum tau");

  double n2 = std::numeric_limits<double>::infinity();
  for (const std::size_t i : well_measured(curve, 0, imin - 1))
    n2 = std::min(n2, curve.dev[i] * curve.dev[i] * curve.tau[i]);

  const double q2 = quantization_variance(lsb);
  const double white = n2 / dt;  // sigma_n^2 + q^2
  if (!(white > q2))
    throw CalibrationError(CalibrationReason::bad_option,
                           "random-walk model fit: the white noise of the curve (" + std::to_string(std::sqrt(white)) +
                               " per sample) is below the quantization step's own noise (" +
                               std::to_string(std::sqrt(q2)) +
                               "); check the LSB (counts per unit) and the sample period");

  const double smin2 = curve.dev[imin] * curve.dev[imin];
  double big_s = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double m = factor_of(curve.tau[i], dt);
    big_s = std::max(big_s, (smin2 - white / m) / rw_factor(m));
  }
  if (!(big_s > 0.0))
    throw CalibrationError(CalibrationReason::degenerate,
                           "random-walk model fit: the white-noise line alone lies above the curve's minimum at "
                           "every tau; the curve has no random-walk arm to fit");

  RandomWalkModel model;
  model.sigma_n = std::sqrt(white - q2);
  model.sigma_mu = std::sqrt(big_s) / dt;
  model.dt = dt;
  model.lsb = lsb;
  return model;
}

namespace {

// Weighted least squares of the variance, for a fixed T_c:
//   dev_i^2 - q^2/m_i  ~  x1 / m_i + x2 g_i(T_c),   x1 = sigma_n^2 >= 0, x2 = sigma_b^2 >= 0,
// weights edf_i / (2 dev_i^4) (the variance of an AVAR estimate is 2 avar^2 / edf).
struct GmProblem {
  std::vector<double> m;   // averaging factors
  std::vector<double> sw;  // sqrt(weight)
  std::vector<double> y;   // sqrt(weight) * target
  std::vector<double> a;   // sqrt(weight) / m
  double dt = 0.0;
  mutable std::vector<double> c;  // sqrt(weight) * g(T_c), scratch

  struct Solution {
    double x1 = 0.0, x2 = 0.0, cost = std::numeric_limits<double>::infinity();
  };

  double cost_of(double x1, double x2) const noexcept {
    double s = 0.0;
    for (std::size_t i = 0; i < y.size(); ++i) {
      const double r = x1 * a[i] + x2 * c[i] - y[i];
      s += r * r;
    }
    return s;
  }

  Solution solve(double tau_c) const {
    const double alpha = dt / tau_c;
    c.resize(m.size());
    double s11 = 0.0, s12 = 0.0, s22 = 0.0, b1 = 0.0, b2 = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i) {
      c[i] = sw[i] * ar1_avar_unit(alpha, m[i]);
      s11 += a[i] * a[i];
      s12 += a[i] * c[i];
      s22 += c[i] * c[i];
      b1 += a[i] * y[i];
      b2 += c[i] * y[i];
    }
    // Non-negative LS with two unknowns: the unconstrained optimum if it is
    // feasible, else the best of the faces x1 = 0, x2 = 0 and the origin.
    std::array<std::array<double, 2>, 4> cand{};
    std::size_t nc = 0;
    const double det = s11 * s22 - s12 * s12;
    if (det > 1e-12 * s11 * s22) {
      const double x1 = (b1 * s22 - b2 * s12) / det;
      const double x2 = (s11 * b2 - s12 * b1) / det;
      if (x1 >= 0.0 && x2 >= 0.0) cand[nc++] = {x1, x2};
    }
    if (nc == 0) {
      if (s11 > 0.0) cand[nc++] = {std::max(b1 / s11, 0.0), 0.0};
      if (s22 > 0.0) cand[nc++] = {0.0, std::max(b2 / s22, 0.0)};
      cand[nc++] = {0.0, 0.0};
    }
    Solution best;
    for (std::size_t k = 0; k < nc; ++k) {
      const double cost = cost_of(cand[k][0], cand[k][1]);
      if (cost < best.cost) best = {cand[k][0], cand[k][1], cost};
    }
    return best;
  }
};

}  // namespace

// Profiled weighted LS: for each T_c the two variances solve a 2-unknown
// non-negative LS in closed form; T_c is searched on 400 log-spaced values
// from dt to 10 * max tau, then refined by golden section on ln T_c between
// the neighbours of the best grid value.
GaussMarkovModel fit_gauss_markov_model(const AllanCurve& curve, double dt, double lsb) {
  constexpr const char* who = "Gauss-Markov model fit";
  validate_curve(curve, who, 3);
  validate_period(dt, lsb, who);
  const double q2 = quantization_variance(lsb);

  GmProblem p;
  p.dt = dt;
  for (std::size_t i = 0; i < curve.size(); ++i) {
    const double m = factor_of(curve.tau[i], dt);
    const double var = curve.dev[i] * curve.dev[i];
    const double sw = std::sqrt(0.5 * edf_of(curve, i)) / var;
    p.m.push_back(m);
    p.sw.push_back(sw);
    p.y.push_back(sw * (var - q2 / m));
    p.a.push_back(sw / m);
  }

  const double lo = std::log(dt);
  const double hi = std::log(10.0 * std::max(curve.tau.back(), dt));
  constexpr int kGrid = 400;
  const auto grid_u = [&](int j) { return lo + (hi - lo) * j / (kGrid - 1); };

  int best_j = 0;
  GmProblem::Solution best;
  double best_u = lo;
  for (int j = 0; j < kGrid; ++j) {
    const double u = grid_u(j);
    const auto s = p.solve(std::exp(u));
    if (s.cost < best.cost) {
      best = s;
      best_j = j;
      best_u = u;
    }
  }

  // Golden section on ln T_c in [u_{j-1}, u_{j+1}].
  double ua = grid_u(std::max(best_j - 1, 0));
  double ub = grid_u(std::min(best_j + 1, kGrid - 1));
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double uc = ub - g * (ub - ua);
  double ud = ua + g * (ub - ua);
  auto sc = p.solve(std::exp(uc));
  auto sd = p.solve(std::exp(ud));
  for (int it = 0; it < 100 && (ub - ua) > 1e-12; ++it) {
    if (sc.cost < sd.cost) {
      ub = ud;
      ud = uc;
      sd = sc;
      uc = ub - g * (ub - ua);
      sc = p.solve(std::exp(uc));
    } else {
      ua = uc;
      uc = ud;
      sc = sd;
      ud = ua + g * (ub - ua);
      sd = p.solve(std::exp(ud));
    }
  }
  for (const auto& [u, s] : {std::pair{uc, sc}, std::pair{ud, sd}}) {
    if (s.cost < best.cost) {
      best = s;
      best_u = u;
    }
  }

  GaussMarkovModel model;
  model.sigma_n = std::sqrt(best.x1);
  model.sigma_b = std::sqrt(best.x2);
  model.tau_c = std::exp(best_u);
  model.dt = dt;
  model.lsb = lsb;
  return model;
}

ModelResidual residual(const RandomWalkModel& model, const AllanCurve& curve) {
  return residual_impl(model, curve, "random-walk model residual");
}

ModelResidual residual(const GaussMarkovModel& model, const AllanCurve& curve) {
  return residual_impl(model, curve, "Gauss-Markov model residual");
}

double avar(const CompositeModel& model, std::size_t m) noexcept {
  return m == 0 ? kNaN : 2.0 * haar_wavelet_variance(model, 2.0 * static_cast<double>(m));
}

double avar(const Process& process, std::size_t m) noexcept {
  return m == 0 ? kNaN : 2.0 * haar_wavelet_variance(process, 2.0 * static_cast<double>(m));
}

namespace {

// A composite model at its period, as residual_impl reads a model.
struct CompositeAtPeriod {
  const CompositeModel& model;
  double dt = 0.0;
  double lsb = 0.0;  // none: quantization is a process of the model (QN)
};

double avar(const CompositeAtPeriod& c, std::size_t m) noexcept { return avar(c.model, m); }

}  // namespace

ModelResidual residual(const CompositeModel& model, double dt, const AllanCurve& curve) {
  return residual_impl(CompositeAtPeriod{model, dt}, curve, "composite model residual");
}

}  // namespace cubecal
