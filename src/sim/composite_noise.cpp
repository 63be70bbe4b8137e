// A composite noise model sampled a block at a time (sim/composite_noise.hpp).
#include "cubecal/sim/composite_noise.hpp"

#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

constexpr double kPi = std::numbers::pi;

std::string hz(double f) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", f);
  return b;
}

// splitmix64 of the seed and the process index: independent streams.
std::uint64_t process_seed(std::uint64_t seed, std::size_t i) noexcept {
  std::uint64_t z = seed ^ (0xA0761D6478BD642FULL * (i + 1));
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

void check(const Process& p, const CompositeModel& model) {
  const bool ok = p.kind == ProcessKind::dr ? std::isfinite(p.value)
                                            : (p.value >= 0.0 && std::isfinite(p.value) &&
                                               (p.kind != ProcessKind::gm || (p.phi >= 0.0 && p.phi < 1.0)) &&
                                               (p.kind != ProcessKind::ma1 || std::abs(p.theta) < 1.0) &&
                                               (p.kind != ProcessKind::sin || (p.omega > 0.0 && p.omega < kPi)));
  if (!ok)
    throw std::invalid_argument("composite model " + model_name(model) +
                                ": every variance must be finite and >= 0, every Gauss-Markov phi in [0, 1), every "
                                "MA1 theta in (-1, 1), every SIN omega in (0, pi) and the drift finite");
}

}  // namespace

CompositeNoise::CompositeNoise(const CompositeModel& model, std::uint64_t seed) {
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t i = 0; i < model.processes.size(); ++i) {
    const Process& p = model.processes[i];
    check(p, model);
    State s{p, std::mt19937_64(process_seed(seed, i)), 0.0, 0.0};
    if (p.kind != ProcessKind::dr) s.scale = std::sqrt(p.value);
    if (p.kind == ProcessKind::qn || p.kind == ProcessKind::ma1) s.x = normal(s.engine);  // u_0, e_{-1}
    if (p.kind == ProcessKind::gm) s.x = std::sqrt(p.value / (1.0 - p.phi * p.phi)) * normal(s.engine);
    if (p.kind == ProcessKind::sin) s.x = 2.0 * kPi * std::uniform_real_distribution<double>(0.0, 1.0)(s.engine);
    states_.push_back(std::move(s));
  }
}

void CompositeNoise::add_next(std::span<double> out) {
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  for (State& s : states_) {
    switch (s.process.kind) {
      case ProcessKind::wn:
        for (double& v : out) v += s.scale * normal(s.engine);
        break;
      case ProcessKind::qn:
        for (double& v : out) {
          const double next = normal(s.engine);
          v += s.scale * (next - s.x);
          s.x = next;
        }
        break;
      case ProcessKind::rw:
        for (double& v : out) {
          s.x += s.scale * normal(s.engine);
          v += s.x;
        }
        break;
      case ProcessKind::dr:
        for (std::size_t j = 0; j < out.size(); ++j) out[j] += s.process.value * static_cast<double>(k_ + j);
        break;
      case ProcessKind::gm:
        for (double& v : out) {
          s.x = s.process.phi * s.x + s.scale * normal(s.engine);
          v += s.x;
        }
        break;
      case ProcessKind::ma1:
        for (double& v : out) {
          const double e = normal(s.engine);
          v += s.scale * (e + s.process.theta * s.x);
          s.x = e;
        }
        break;
      case ProcessKind::sin:
        // The phase from the sample count, so that no rounding accumulates
        // over a long record: omega k + U reduced modulo 2 pi as a whole.
        for (std::size_t j = 0; j < out.size(); ++j)
          out[j] += s.scale * std::sin(std::fmod(s.process.omega * static_cast<double>(k_ + j), 2.0 * kPi) + s.x);
        break;
    }
  }
  k_ += out.size();
}

CompositeModel composite_at_period(const CompositeModel& model, double from_dt, double to_dt) {
  if (!(from_dt > 0.0) || !std::isfinite(from_dt) || !(to_dt > 0.0) || !std::isfinite(to_dt))
    throw std::invalid_argument("composite_at_period: the sample periods must be positive and finite");
  const double r = to_dt / from_dt;
  CompositeModel out = model;
  for (Process& p : out.processes) {
    switch (p.kind) {
      case ProcessKind::wn: p.value /= r; break;      // N^2 = sigma2 dt
      case ProcessKind::qn: p.value /= r * r; break;  // Q = sqrt(Q2) dt
      case ProcessKind::rw: p.value *= r; break;      // K^2 = gamma2 / dt
      case ProcessKind::dr: p.value *= r; break;      // R = omega / dt
      case ProcessKind::gm: {
        if (!(p.phi > 0.0 && p.phi < 1.0) || !(p.value >= 0.0))
          throw std::invalid_argument("composite_at_period: a Gauss-Markov term needs 0 < phi < 1 and a variance >= 0");
        // T_c = -dt / ln(phi) and sigma_b^2 = sigma2 / (1 - phi^2) are kept:
        // ln(phi') = r ln(phi), sigma2' = sigma_b^2 (1 - phi'^2).
        const double log_phi = r * std::log(p.phi);
        const double sigma_b2 = p.value / -std::expm1(2.0 * std::log(p.phi));
        p.phi = std::exp(log_phi);
        p.value = sigma_b2 * -std::expm1(2.0 * log_phi);
        break;
      }
      case ProcessKind::ma1:
        // N^2 = sigma2 (1 + theta)^2 dt is kept, and theta: the filter that
        // makes the moving average is taken to run at the new period.
        p.value /= r;
        break;
      case ProcessKind::sin:
        // The amplitude and the frequency in Hz are kept; a line at or above
        // the new Nyquist frequency has no place in the new record.
        p.omega *= r;
        if (!(p.omega > 0.0 && p.omega < kPi))
          throw UsageError(Field::rate, "a SIN line of the model at " + hz(p.omega / (2.0 * kPi * to_dt)) +
                                            " Hz lies at or above the Nyquist frequency " + hz(0.5 / to_dt) +
                                            " Hz of the simulated rate: simulate at a rate above twice the line");
        break;
    }
  }
  return out;
}

}  // namespace cubecal
