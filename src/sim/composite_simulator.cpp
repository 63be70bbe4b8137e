// Samples of a composite noise model (sim/composite_simulator.hpp).
#include "cubecal/sim/composite_simulator.hpp"

#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {
constexpr double kPi = std::numbers::pi;
}  // namespace

std::vector<double> simulate_composite(const CompositeModel& model, std::size_t samples, std::uint64_t seed) {
  for (const Process& p : model.processes) {
    const bool ok = p.kind == ProcessKind::dr ? std::isfinite(p.value)
                                              : (p.value >= 0.0 && std::isfinite(p.value) &&
                                                 (p.kind != ProcessKind::gm || (p.phi > 0.0 && p.phi < 1.0)) &&
                                                 (p.kind != ProcessKind::ma1 || std::abs(p.theta) < 1.0) &&
                                                 (p.kind != ProcessKind::sin || (p.omega > 0.0 && p.omega < kPi)));
    if (!ok)
      throw UsageError(Field::model, "model " + model_name(model) +
                                         ": every variance must be finite and >= 0, every Gauss-Markov phi in (0, 1), "
                                         "every MA1 theta in (-1, 1) and every SIN omega in (0, pi)");
  }
  std::vector<double> y(samples, 0.0);
  std::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  for (const Process& p : model.processes) {
    switch (p.kind) {
      case ProcessKind::wn: {
        const double s = std::sqrt(p.value);
        for (double& v : y) v += s * normal(engine);
        break;
      }
      case ProcessKind::qn: {
        const double s = std::sqrt(p.value);
        double prev = normal(engine);
        for (double& v : y) {
          const double next = normal(engine);
          v += s * (next - prev);
          prev = next;
        }
        break;
      }
      case ProcessKind::rw: {
        const double s = std::sqrt(p.value);
        double walk = 0.0;
        for (double& v : y) {
          walk += s * normal(engine);
          v += walk;
        }
        break;
      }
      case ProcessKind::dr:
        for (std::size_t t = 0; t < samples; ++t) y[t] += p.value * static_cast<double>(t);
        break;
      case ProcessKind::gm: {
        const double s = std::sqrt(p.value);
        double x = std::sqrt(p.value / (1.0 - p.phi * p.phi)) * normal(engine);  // stationary start
        for (double& v : y) {
          x = p.phi * x + s * normal(engine);
          v += x;
        }
        break;
      }
      case ProcessKind::ma1: {
        const double s = std::sqrt(p.value);
        double prev = normal(engine);  // e_{-1}
        for (double& v : y) {
          const double e = normal(engine);
          v += s * (e + p.theta * prev);
          prev = e;
        }
        break;
      }
      case ProcessKind::sin: {
        const double a = std::sqrt(p.value);
        const double u = 2.0 * kPi * std::uniform_real_distribution<double>(0.0, 1.0)(engine);
        for (std::size_t t = 0; t < samples; ++t) y[t] += a * std::sin(p.omega * static_cast<double>(t) + u);
        break;
      }
    }
  }
  return y;
}

}  // namespace cubecal
