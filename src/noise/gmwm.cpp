// The GMWM fit of a composite noise model (noise/gmwm.hpp;
// docs/formulas/noise-terms.md §8b).
#include "cubecal/noise/gmwm.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>

#include "../detail/levenberg_marquardt.hpp"
#include "cubecal/error.hpp"

namespace cubecal {

namespace {

using Eigen::VectorXd;

// a = -ln(phi) above this is a white sequence to the last digit (phi < 1e-21);
// below this (a correlation time beyond 1e12 samples) a random walk on any
// record, and phi = exp(-a) must stay below 1 in double precision.
constexpr double kMaxLogA = 3.9;
constexpr double kMinLogA = -27.6;  // ln(1e-12)
// An MA1's theta = tanh(z): |z| <= 18 keeps |theta| below 1 in double
// precision (1 - theta = 4.6e-16 there).
constexpr double kMaxAtanh = 18.0;

double ma_theta(double z) { return std::tanh(std::clamp(z, -kMaxAtanh, kMaxAtanh)); }

// A SIN term's omega = pi / (1 + e^-z) stays inside (0, pi); |z| <= 36
// keeps it off both ends in double precision.
constexpr double kPi = std::numbers::pi;
constexpr double kMaxLogit = 36.0;
double sin_omega(double z) { return kPi / (1.0 + std::exp(-std::clamp(z, -kMaxLogit, kMaxLogit))); }
double sin_logit(double omega) { return std::log(omega / (kPi - omega)); }

// One process's wavelet variance at tau, its log-parameters from th[0]
// (and th[1] for GM, MA1, SIN).
double process_wv(ProcessKind kind, const double* th, double tau) {
  const double v = std::exp(th[0]);
  switch (kind) {
    case ProcessKind::gm: return gauss_markov_wavelet_variance(std::exp(std::clamp(th[1], kMinLogA, kMaxLogA)), v, tau);
    case ProcessKind::ma1: return haar_wavelet_variance(Process{ProcessKind::ma1, v, 0.0, ma_theta(th[1])}, tau);
    case ProcessKind::sin: return haar_wavelet_variance(Process{ProcessKind::sin, v, 0.0, 0.0, sin_omega(th[1])}, tau);
    case ProcessKind::dr: return haar_wavelet_variance(Process{kind, std::sqrt(v), 0.0}, tau);  // omega^2's logarithm
    case ProcessKind::wn:
    case ProcessKind::qn:
    case ProcessKind::rw: return haar_wavelet_variance(Process{kind, v, 0.0}, tau);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

Eigen::Index parameters_of(ProcessKind kind) {
  return kind == ProcessKind::gm || kind == ProcessKind::ma1 || kind == ProcessKind::sin ? 2 : 1;
}

// The wavelet variance of the model with log-parameters theta at tau.
double model_wv(const CompositeModel& structure, const VectorXd& theta, double tau) {
  double sum = 0.0;
  Eigen::Index k = 0;
  for (const Process& p : structure.processes) {
    sum += process_wv(p.kind, theta.data() + k, tau);
    k += parameters_of(p.kind);
  }
  return sum;
}

CompositeModel to_model(const CompositeModel& structure, const VectorXd& theta) {
  CompositeModel m = structure;
  Eigen::Index k = 0;
  for (Process& p : m.processes) {
    const double v = std::exp(theta(k++));
    if (p.kind == ProcessKind::gm) {
      p.value = v;
      p.phi = std::exp(-std::exp(std::clamp(theta(k++), kMinLogA, kMaxLogA)));
    } else if (p.kind == ProcessKind::ma1) {
      p.value = v;
      p.theta = ma_theta(theta(k++));
    } else if (p.kind == ProcessKind::sin) {
      p.value = v;
      p.omega = sin_omega(theta(k++));
    } else {
      p.value = p.kind == ProcessKind::dr ? std::sqrt(v) : v;
    }
  }
  // Gauss-Markov terms by correlation time, shortest first (phi ascending):
  // any order fits alike, and one order makes fits comparable.
  std::vector<std::size_t> at;
  for (std::size_t i = 0; i < m.processes.size(); ++i)
    if (m.processes[i].kind == ProcessKind::gm) at.push_back(i);
  std::vector<Process> gms;
  for (std::size_t i : at) gms.push_back(m.processes[i]);
  std::sort(gms.begin(), gms.end(), [](const Process& a, const Process& b) { return a.phi < b.phi; });
  for (std::size_t i = 0; i < at.size(); ++i) m.processes[at[i]] = gms[i];
  return m;
}

// The log-parameters of a model (to_model's inverse, before its sorting).
VectorXd theta_of(const CompositeModel& structure, const CompositeModel& m) {
  if (model_name(m) != model_name(structure) || m.processes.size() != structure.processes.size())
    throw UsageError(Field::model, "the start " + model_name(m) + " is not a model " + model_name(structure));
  VectorXd theta(static_cast<Eigen::Index>(parameter_count(structure)));
  Eigen::Index k = 0;
  for (const Process& p : m.processes) {
    // A term a fit drove to zero (its log-parameter underflowed) starts at
    // the smallest one: a bootstrap replicate from such a fit is a fit too.
    const bool ok = p.kind == ProcessKind::dr ? std::isfinite(p.value)
                                              : p.value >= 0.0 && std::isfinite(p.value) &&
                                                    (p.kind != ProcessKind::gm || (p.phi > 0.0 && p.phi < 1.0)) &&
                                                    (p.kind != ProcessKind::ma1 || std::abs(p.theta) < 1.0) &&
                                                    (p.kind != ProcessKind::sin || (p.omega > 0.0 && p.omega < kPi));
    if (!ok) throw UsageError(Field::model, "the start " + model_name(m) + " has a parameter beyond its range");
    constexpr double kSmallest = 1e-300;
    theta(k++) = std::log(std::max(p.kind == ProcessKind::dr ? p.value * p.value : p.value, kSmallest));
    if (p.kind == ProcessKind::gm) theta(k++) = std::log(-std::log(p.phi));
    if (p.kind == ProcessKind::ma1) theta(k++) = std::atanh(p.theta);
    if (p.kind == ProcessKind::sin) theta(k++) = sin_logit(p.omega);
  }
  return theta;
}

// Starting log-parameters read off the curve: `spread` in [0, 1) places the
// Gauss-Markov terms along the scales, `share` scales each term's size,
// `ma` is an MA1 term's theta. A SIN term starts at the frequency and
// amplitude its structure carries (a line found in the spectrum), or,
// without one, at `line` in [0, 1) of the log-frequencies the scales see and
// the size of the curve there.
VectorXd start_from(const CompositeModel& structure, const WaveletVariance& wv, const std::vector<double>& place,
                    const std::vector<double>& share, double ma, const std::vector<double>& line) {
  const std::size_t J = wv.size();
  const double t1 = wv.tau.front(), n1 = wv.nu2.front();
  const double tJ = wv.tau.back(), nJ = wv.nu2.back();
  VectorXd theta(static_cast<Eigen::Index>(parameter_count(structure)));
  Eigen::Index k = 0;
  std::size_t g = 0, l = 0;
  for (std::size_t i = 0; i < structure.processes.size(); ++i) {
    const double f = share[i];
    switch (structure.processes[i].kind) {
      case ProcessKind::wn: theta(k++) = std::log(f * n1 * t1); break;
      case ProcessKind::qn: theta(k++) = std::log(f * n1 * t1 * t1 / 6.0); break;
      case ProcessKind::rw: theta(k++) = std::log(f * nJ * 12.0 * tJ / (tJ * tJ + 2.0)); break;
      case ProcessKind::dr: theta(k++) = std::log(f * 16.0 * nJ / (tJ * tJ)); break;
      case ProcessKind::gm: {
        // A Gauss-Markov term's wavelet variance peaks near tau = 3.8 T_c at
        // about 0.22 of its stationary variance.
        const auto j = std::min(J - 1, static_cast<std::size_t>(place[g++] * static_cast<double>(J)));
        const double tc = std::max(wv.tau[j] / 3.8, 0.5);
        const double a = 1.0 / tc;
        const double sb2 = f * wv.nu2[j] / 0.22;
        theta(k++) = std::log(sb2 * -std::expm1(-2.0 * a));
        theta(k++) = std::log(a);
        break;
      }
      case ProcessKind::ma1:
        // The white level tau nu2 of the first scale is sigma2 ((1 + theta)^2 - 6 theta / tau).
        theta(k++) = std::log(f * n1 * t1 / ((1.0 + ma) * (1.0 + ma) - 6.0 * ma / t1));
        theta(k++) = std::atanh(ma);
        break;
      case ProcessKind::sin: {
        const Process& hint = structure.processes[i];
        double omega = hint.omega, a2 = hint.value;
        if (!(omega > 0.0 && omega < kPi)) {
          // 4 / tau_J .. 2.6 rad per sample: the lines whose WV peaks inside the scales.
          const double lo = std::log(4.0 / tJ), hi = std::log(2.6);
          omega = std::exp(lo + line[l] * (hi - lo));
        }
        if (!(a2 > 0.0)) {
          // The line's WV peaks near tau = 4.66 / omega at 0.26 A^2 (omega << 1).
          std::size_t j = 0;
          while (j + 1 < J && wv.tau[j] < 4.66 / omega) ++j;
          a2 = wv.nu2[j] / 0.26;
        }
        ++l;
        theta(k++) = std::log(f * a2);
        theta(k++) = sin_logit(omega);
        break;
      }
    }
  }
  return theta;
}

struct Run {
  VectorXd theta;
  double cost = std::numeric_limits<double>::infinity();
  bool converged = false;
};

Run minimise(const CompositeModel& structure, const WaveletVariance& wv, const std::vector<double>& sd, VectorXd theta,
             std::size_t max_iterations) {
  // Residuals from each process's curve, and the Jacobian by central
  // differences of step 1e-6 max(|theta_k|, 1) (as with_numeric_jacobian),
  // each column from the one process its parameter moves: the others'
  // curves cancel in the difference, so a model of P processes costs two
  // process curves per parameter, not two whole models.
  const auto J_rows = static_cast<Eigen::Index>(wv.size());
  const std::size_t P = structure.processes.size();
  std::vector<Eigen::Index> at(P);
  for (std::size_t i = 0, k = 0; i < P; ++i) {
    at[i] = static_cast<Eigen::Index>(k);
    k += static_cast<std::size_t>(parameters_of(structure.processes[i].kind));
  }
  const auto curve_of = [&](std::size_t i, const double* th, Eigen::Ref<VectorXd> out) {
    for (Eigen::Index j = 0; j < J_rows; ++j)
      out(j) = process_wv(structure.processes[i].kind, th, wv.tau[static_cast<std::size_t>(j)]);
  };
  const detail::EvalFn eval = [&](const VectorXd& th, VectorXd& r, Eigen::MatrixXd* J) {
    r = VectorXd::Zero(J_rows);
    VectorXd c(J_rows);
    for (std::size_t i = 0; i < P; ++i) {
      curve_of(i, th.data() + at[i], c);
      r += c;
    }
    for (Eigen::Index j = 0; j < J_rows; ++j)
      r(j) = (wv.nu2[static_cast<std::size_t>(j)] - r(j)) / sd[static_cast<std::size_t>(j)];
    if (!r.allFinite()) return false;
    if (!J) return true;
    J->resize(J_rows, th.size());
    VectorXd cp(J_rows), cm(J_rows);
    for (std::size_t i = 0; i < P; ++i) {
      for (Eigen::Index q = 0; q < parameters_of(structure.processes[i].kind); ++q) {
        const Eigen::Index k = at[i] + q;
        const double h = 1e-6 * std::max(std::abs(th(k)), 1.0);
        double local[2] = {th(at[i]), parameters_of(structure.processes[i].kind) == 2 ? th(at[i] + 1) : 0.0};
        const double centre = local[q];
        local[q] = centre + h;
        const double up = local[q];
        curve_of(i, local, cp);
        local[q] = centre - h;
        const double down = local[q];
        curve_of(i, local, cm);
        for (Eigen::Index j = 0; j < J_rows; ++j)
          (*J)(j, k) = -(cp(j) - cm(j)) / (up - down) / sd[static_cast<std::size_t>(j)];
      }
    }
    return J->allFinite();
  };
  Run run;
  try {
    const detail::LmOutcome lm = detail::levenberg_marquardt(eval, std::move(theta), max_iterations);
    if (!lm.initial_finite || !std::isfinite(lm.cost)) return run;
    run.theta = lm.p;
    run.cost = lm.cost;
    run.converged = lm.converged;
  } catch (const CalibrationError&) {
    // A start that leads where the model is not finite: the others decide.
  }
  return run;
}

// sd_j = ref_j sqrt(2 / edf_j): the chi-square spread of nu2_j about ref_j.
std::vector<double> weights_at(const WaveletVariance& wv, const std::vector<double>& ref) {
  std::vector<double> sd(wv.size());
  for (std::size_t j = 0; j < wv.size(); ++j) sd[j] = ref[j] * std::sqrt(2.0 / wv.edf[j]);
  return sd;
}

}  // namespace

GmwmFit fit_gmwm(const WaveletVariance& wv, const CompositeModel& structure, const GmwmOptions& options) {
  if (structure.processes.empty()) throw UsageError(Field::model, "the model has no process");
  const std::size_t np = parameter_count(structure);
  if (wv.size() < np + 1)
    throw UsageError(Field::model, "model " + model_name(structure) + " has " + std::to_string(np) +
                                       " parameters, more than the " + std::to_string(wv.size()) +
                                       " scales of the wavelet variance allow (at least one more): a longer record or "
                                       "a smaller model");
  for (std::size_t j = 0; j < wv.size(); ++j)
    if (!(wv.nu2[j] > 0.0) || !std::isfinite(wv.nu2[j]) || !(wv.edf[j] > 0.0))
      throw UsageError(Field::model, "the wavelet variance is zero or not finite at scale " +
                                         std::to_string(static_cast<long long>(wv.tau[j])) +
                                         ": a constant or damaged record");

  const std::size_t ng =
      static_cast<std::size_t>(std::count_if(structure.processes.begin(), structure.processes.end(),
                                             [](const Process& p) { return p.kind == ProcessKind::gm; }));
  const std::size_t terms = structure.processes.size();
  const bool has_ma = std::any_of(structure.processes.begin(), structure.processes.end(),
                                  [](const Process& p) { return p.kind == ProcessKind::ma1; });
  const std::size_t nl =
      static_cast<std::size_t>(std::count_if(structure.processes.begin(), structure.processes.end(),
                                             [](const Process& p) { return p.kind == ProcessKind::sin; }));
  std::mt19937_64 engine(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // Every start is judged with the same weights (from the curve itself,
  // or the fixed ones asked for).
  const bool fixed = !options.fixed_sd.empty();
  if (fixed &&
      (options.fixed_sd.size() != wv.size() || !std::all_of(options.fixed_sd.begin(), options.fixed_sd.end(),
                                                            [](double s) { return s > 0.0 && std::isfinite(s); })))
    throw std::invalid_argument("fit_gmwm: fixed_sd needs one positive, finite value per scale");
  const std::vector<double> sd0 = fixed ? options.fixed_sd : weights_at(wv, wv.nu2);
  Run best;
  const std::size_t starts = options.start ? 0 : std::max<std::size_t>(options.starts, 1);
  if (options.start) best = minimise(structure, wv, sd0, theta_of(structure, *options.start), options.max_iterations);
  for (const CompositeModel& warm : options.warm_starts) {
    Run run = minimise(structure, wv, sd0, theta_of(structure, warm), options.max_iterations);
    if (run.cost < best.cost) best = std::move(run);
  }
  for (std::size_t s = 0; s < starts; ++s) {
    std::vector<double> place(ng), share(terms, 1.0), line(nl);
    for (std::size_t g = 0; g < ng; ++g) place[g] = (static_cast<double>(g) + 1.0) / (static_cast<double>(ng) + 1.0);
    for (std::size_t i = 0; i < nl; ++i) line[i] = (static_cast<double>(i) + 0.5) / static_cast<double>(nl);
    double ma = 0.2;  // a sensor's averaging filter correlates neighbours positively
    if (s > 0) {
      for (double& p : place) p = unit(engine);
      std::sort(place.begin(), place.end());
      for (double& p : line) p = unit(engine);
      for (double& f : share) f = std::pow(10.0, -2.0 * unit(engine));  // 0.01 .. 1
      if (has_ma) ma = 1.6 * unit(engine) - 0.8;                        // -0.8 .. 0.8
    }
    Run run = minimise(structure, wv, sd0, start_from(structure, wv, place, share, ma, line), options.max_iterations);
    if (run.cost < best.cost) best = std::move(run);
  }
  if (!std::isfinite(best.cost))
    throw CalibrationError(CalibrationReason::degenerate,
                           "GMWM: no starting point gave a finite fit of " + model_name(structure));

  // Reweighting: the spread of each scale at the model's value, not at the
  // measured one (which would favour the points that came out low).
  std::vector<double> ref(wv.size());
  std::vector<double> sd = sd0;
  for (std::size_t pass = 0; pass < (fixed ? 0 : options.reweightings); ++pass) {
    for (std::size_t j = 0; j < wv.size(); ++j) ref[j] = model_wv(structure, best.theta, wv.tau[j]);
    sd = weights_at(wv, ref);
    Run run = minimise(structure, wv, sd, best.theta, options.max_iterations);
    if (!std::isfinite(run.cost)) break;
    const double moved = (run.theta - best.theta).cwiseAbs().maxCoeff();
    best = std::move(run);
    if (moved < 1e-9) break;
  }

  GmwmFit fit;
  fit.model = to_model(structure, best.theta);
  fit.sd = sd;
  fit.converged = best.converged;
  for (std::size_t j = 0; j < wv.size(); ++j) fit.nu2_model.push_back(model_wv(structure, best.theta, wv.tau[j]));
  fit.objective = 0.0;
  for (std::size_t j = 0; j < wv.size(); ++j) fit.objective += std::pow((wv.nu2[j] - fit.nu2_model[j]) / sd[j], 2);
  return fit;
}

}  // namespace cubecal
