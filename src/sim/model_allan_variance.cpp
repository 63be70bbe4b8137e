// The Allan variance of a simulated axis (model_allan_variance.hpp).
#include "cubecal/sim/model_allan_variance.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "cubecal/noise/sensor_noise_model.hpp"

namespace cubecal {

namespace {

void check(const TriadModel& triad, std::size_t axis, double dt) {
  if (axis > 2) throw std::invalid_argument("model_avar: axis must be 0, 1 or 2");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::invalid_argument("model_avar: dt must be positive");
  for (const PowerLawNoise& p : triad.axes[axis].power_law)
    if (p.alpha != 0.0 && p.alpha != -1.0 && p.alpha != -2.0)
      throw std::invalid_argument("model_avar: a power-law term of alpha " + std::to_string(p.alpha) +
                                  " has no closed-form Allan variance here (0, -1 and -2 have)");
}

// NIST SP 1065 Table 2, continuous time: white FM h / (2 tau), flicker FM
// 2 ln2 h, random-walk FM (2 pi^2 / 3) h tau.
double power_law_part(const PowerLawNoise& p, double tau) {
  if (p.alpha == 0.0) return p.h / (2.0 * tau);
  if (p.alpha == -1.0) return 2.0 * std::numbers::ln2 * p.h;
  return 2.0 * std::numbers::pi * std::numbers::pi / 3.0 * p.h * tau;
}

double unchecked_avar(const TriadModel& triad, std::size_t axis, double dt, std::size_t m) {
  const AxisModel& a = triad.axes[axis];
  double v = 0.0;
  switch (a.bias) {
    case BiasProcess::gauss_markov:
      v = avar(GaussMarkovModel{a.white_sigma, a.bias_sigma, a.tau_c, dt, triad.lsb}, m);
      break;
    case BiasProcess::random_walk: v = avar(RandomWalkModel{a.white_sigma, a.bias_sigma, dt, triad.lsb}, m); break;
    case BiasProcess::none: v = avar(RandomWalkModel{a.white_sigma, 0.0, dt, triad.lsb}, m); break;
  }
  const double tau = static_cast<double>(m) * dt;
  for (const PowerLawNoise& p : a.power_law) v += power_law_part(p, tau);
  if (!a.composite.processes.empty()) v += avar(a.composite, m);
  return v;
}

}  // namespace

double model_avar(const TriadModel& triad, std::size_t axis, double dt, std::size_t m) {
  check(triad, axis, dt);
  return unchecked_avar(triad, axis, dt, m);
}

PlanModel plan_model(const TriadModel& triad, std::size_t axis, double dt) {
  check(triad, axis, dt);
  return {dt, [triad, axis, dt](std::size_t m) { return unchecked_avar(triad, axis, dt, m); }};
}

}  // namespace cubecal
