// Simulated sensor triads (simulator.hpp): the paper's measurement model
// (eq. 1-3 gyro, 14-16 magnetometer: docs/paper.md §2.2;
// docs/formulas/simulator.md) with turn-on bias, temperature, scale factor /
// misalignment and saturation.
//
// Random-number stream (kept stable so a seed reproduces a run across
// versions; changing any of this changes every simulated record):
//   engine  std::mt19937_64 seeded with `seed` (std::mt19937_64(seed)), one
//           engine per simulator;
//   normal  boost::random::normal_distribution<double>(0, 1), Boost.Random's
//           ziggurat (Boost >= 1.56; one 64-bit engine output per attempt,
//           a few more on the rare rejections and tail draws);
//   order   at construction, 6 normals: the turn-on biases of x, y, z, then
//           the Gauss-Markov initial states of x, y, z;
//           per sample k, 6 normals in axis order x, y, z, two per axis:
//           first the white-noise normal n_k[i], then the bias-process normal
//           n'_k[i] (which moves b_k[i] to b_{k+1}[i]).
// Every normal is drawn whether or not its term is enabled (a zero sigma, no
// bias process, no Gauss-Markov state): the stream does not depend on the
// model, so two models run with the same seed see the same normals (common
// random numbers) -- e.g. the white noise of "white + random walk" equals
// that of "white only" sample for sample.
//
// Per sample and axis, in this floating-point order:
//   w      = (((u + (fixed_bias + turn_on)) + b_k) + temp_coeff (T - temp_ref)) + white n_k
//   b_k+1  = phi b_k + gain n'_k    random walk: phi = 1, gain = sigma_mu dt
//                                   Gauss-Markov: phi = exp(-dt/T_c),
//                                     gain = sigma_b sqrt(1 - phi^2)
//                                   none: phi = 1, gain = 0 (b stays 0)
//   w     += the power-law terms' sample and the composite model's (when
//            the axis has any; their own streams, power_law_generator.hpp
//            and composite_noise.hpp)
//   out    = clamp(Q(w), -saturation, saturation)
// with u = M * true (row-major) and Q(w) = trunc(w lsb)/lsb (the paper's
// eq. 3; docs/formulas/simulator.md §1.2) or round(w lsb)/lsb, Q = identity
// for lsb == 0. The random walk starts at
// b_0 = 0 (the paper's model: the starting level is the fixed + turn-on
// bias), the Gauss-Markov process at b_0 = sigma_b n, its stationary law.
// step() and run() evaluate the same inlined kernel, so they produce the same
// bytes for the same seed and inputs.
#include "cubecal/sim/simulator.hpp"

#include "cubecal/sim/composite_noise.hpp"

#include <algorithm>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

namespace cubecal {

namespace {

using Engine = std::mt19937_64;

enum class QuantMode { none, truncate, round };

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("TriadSimulator: " + what);
}

// Parameters and state the per-sample kernel reads. run() works on a local
// copy so that the compiler can keep it in registers (the output span could
// otherwise alias it) and writes the state back at the end.
struct Kernel {
  std::array<double, 9> m{};       // scale factor / misalignment, row-major
  std::array<double, 3> offset{};  // fixed_bias + turn_on
  std::array<double, 3> white{};   // sigma_n
  std::array<double, 3> phi{};     // bias-process recursion
  std::array<double, 3> gain{};
  std::array<double, 3> tc{};  // temperature coefficients
  std::array<double, 3> b{};   // bias state b_k
  double lsb = 0.0;
  double saturation = 0.0;
  double temp_ref = 0.0;

  template <QuantMode Q>
  double finish(double w) const noexcept {
    if constexpr (Q == QuantMode::truncate) {
      w = std::trunc(w * lsb) / lsb;
    } else if constexpr (Q == QuantMode::round) {
      w = std::round(w * lsb) / lsb;
    }
    return std::clamp(w, -saturation, saturation);
  }

  // One triad. `in` is the true input (3 values) when kInput, ignored (zero
  // input) otherwise. For a zero input both paths give the same bytes:
  // M * 0 is +-0 and adding a signed zero to the offset leaves it unchanged.
  template <QuantMode Q, bool kInput, bool kExtra = false>
  void sample(Engine& eng, const double* in, double temperature, double* out, const double* extra = nullptr) noexcept {
    boost::random::normal_distribution<double> normal;  // N(0, 1), stateless
    const double dtemp = temperature - temp_ref;
    for (std::size_t i = 0; i < 3; ++i) {
      double u = 0.0;
      if constexpr (kInput) u = m[3 * i] * in[0] + m[3 * i + 1] * in[1] + m[3 * i + 2] * in[2];
      const double n_white = normal(eng);
      const double n_bias = normal(eng);
      double w = (((u + offset[i]) + b[i]) + tc[i] * dtemp) + white[i] * n_white;
      if constexpr (kExtra) w += extra[i];
      b[i] = phi[i] * b[i] + gain[i] * n_bias;
      out[i] = finish<Q>(w);
    }
  }

  template <QuantMode Q, bool kInput, bool kTemp, bool kExtra>
  void run(Engine& eng, std::size_t n, const double* in, const double* temp, double* out,
           const double* extra) noexcept {
    for (std::size_t k = 0; k < n; ++k) {
      const double t = kTemp ? temp[k] : temp_ref;
      sample<Q, kInput, kExtra>(eng, kInput ? in + 3 * k : nullptr, t, out + 3 * k, kExtra ? extra + 3 * k : nullptr);
    }
  }
};

template <QuantMode Q, bool kExtra>
void dispatch_run(Kernel& kern, Engine& eng, std::size_t n, const double* in, const double* temp, double* out,
                  const double* extra) noexcept {
  if (in != nullptr) {
    if (temp != nullptr)
      kern.run<Q, true, true, kExtra>(eng, n, in, temp, out, extra);
    else
      kern.run<Q, true, false, kExtra>(eng, n, in, temp, out, extra);
  } else {
    if (temp != nullptr)
      kern.run<Q, false, true, kExtra>(eng, n, in, temp, out, extra);
    else
      kern.run<Q, false, false, kExtra>(eng, n, in, temp, out, extra);
  }
}

template <QuantMode Q>
void dispatch_run(Kernel& kern, Engine& eng, std::size_t n, const double* in, const double* temp, double* out,
                  const double* extra) noexcept {
  if (extra != nullptr)
    dispatch_run<Q, true>(kern, eng, n, in, temp, out, extra);
  else
    dispatch_run<Q, false>(kern, eng, n, in, temp, out, nullptr);
}

// The seed of power-law term `term` of axis `axis`: splitmix64 of the
// simulator's seed, apart from the main stream's engine.
std::uint64_t power_law_seed(std::uint64_t seed, std::size_t axis, std::size_t term) noexcept {
  std::uint64_t z = seed ^ (0xD1B54A32D192ED03ULL * (axis * 64 + term + 1));
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// The seed of axis `axis`'s composite model (composite_noise.hpp draws one
// stream per process from it), apart from the main stream and the power-law
// terms'.
std::uint64_t composite_seed(std::uint64_t seed, std::size_t axis) noexcept {
  std::uint64_t z = seed ^ (0x8EBC6AF09C88C6E3ULL * (axis + 1));
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

bool finite(double v) noexcept { return std::isfinite(v); }

void validate(const TriadModel& model, double dt) {
  require(finite(dt) && dt > 0.0, "the sample period dt must be positive and finite");
  for (std::size_t i = 0; i < 3; ++i) {
    const AxisModel& a = model.axes[i];
    const std::string ax = "axis " + std::to_string(i) + ": ";
    require(finite(a.fixed_bias), ax + "fixed_bias must be finite");
    require(finite(a.turn_on_sigma) && a.turn_on_sigma >= 0.0, ax + "turn_on_sigma must be finite and >= 0");
    require(finite(a.white_sigma) && a.white_sigma >= 0.0, ax + "white_sigma must be finite and >= 0");
    require(finite(a.bias_sigma) && a.bias_sigma >= 0.0, ax + "bias_sigma must be finite and >= 0");
    require(finite(a.temp_coeff), ax + "temp_coeff must be finite");
    for (const PowerLawNoise& t : a.power_law)
      require(finite(t.alpha) && finite(t.h) && t.h >= 0.0,
              ax + "a power-law term needs a finite alpha and a finite h >= 0");
    if (a.bias == BiasProcess::gauss_markov)
      require(finite(a.tau_c) && a.tau_c > 0.0,
              ax + "a Gauss-Markov bias needs a positive, finite correlation time tau_c");
    for (const Process& p : a.composite.processes)
      require(p.kind == ProcessKind::dr
                  ? finite(p.value)
                  : finite(p.value) && p.value >= 0.0 && (p.kind != ProcessKind::gm || (p.phi >= 0.0 && p.phi < 1.0)),
              ax + "a composite model needs finite variances >= 0, Gauss-Markov phi in [0, 1) and a finite drift");
  }
  for (double v : model.scale_misalignment) require(finite(v), "scale_misalignment entries must be finite");
  require(finite(model.lsb) && model.lsb >= 0.0, "lsb (counts per unit) must be finite and >= 0 (0: no quantization)");
  require(model.saturation > 0.0, "saturation must be > 0 (infinity: none)");
  require(finite(model.temp_ref), "temp_ref must be finite");
}

}  // namespace

double TemperatureProfile::at(std::size_t k, double dt) const noexcept {
  switch (kind) {
    case Kind::constant: return mean;
    case Kind::sinusoid: {
      if (!(period_s > 0.0)) return mean;
      // fmod keeps the phase accurate for long records (k dt >> period).
      const double cycles = std::fmod(static_cast<double>(k) * dt, period_s) / period_s;
      return mean + amplitude * std::sin(2.0 * std::numbers::pi * cycles + phase_rad);
    }
    case Kind::series:
      if (values.empty()) return mean;
      return values[std::min(k, values.size() - 1)];
  }
  return mean;
}

struct TriadSimulator::Impl {
  TriadModel model;
  double dt = 0.0;
  Engine eng;
  QuantMode quant = QuantMode::none;
  std::array<double, 3> turn_on{};
  Kernel kern;
  std::array<std::vector<PowerLawGenerator>, 3> power_law;        // per axis
  std::vector<std::pair<std::size_t, CompositeNoise>> composite;  // (axis, its model's samples)
  bool has_extra = false;                                         // any power-law or composite term
  std::vector<double> extra, term;                                // run()'s scratch

  // The power-law and composite noise of the next n samples, n x 3
  // row-major, into extra.
  void extra_noise(std::size_t n) {
    extra.assign(3 * n, 0.0);
    term.resize(n);
    for (std::size_t i = 0; i < 3; ++i)
      for (PowerLawGenerator& g : power_law[i]) {
        g.next(term);
        for (std::size_t k = 0; k < n; ++k) extra[3 * k + i] += term[k];
      }
    for (auto& [i, g] : composite) {
      std::fill(term.begin(), term.end(), 0.0);
      g.add_next(term);
      for (std::size_t k = 0; k < n; ++k) extra[3 * k + i] += term[k];
    }
  }
};

TriadSimulator::TriadSimulator(const TriadModel& model, double dt, std::uint64_t seed, std::size_t record_samples) {
  validate(model, dt);
  auto p = std::make_unique<Impl>();
  p->model = model;
  p->dt = dt;
  p->eng.seed(seed);
  p->quant = model.lsb > 0.0 ? (model.quantizer == Quantizer::round ? QuantMode::round : QuantMode::truncate)
                             : QuantMode::none;
  Kernel& k = p->kern;
  k.m = model.scale_misalignment;
  k.lsb = model.lsb;
  k.saturation = model.saturation;
  k.temp_ref = model.temp_ref;

  boost::random::normal_distribution<double> normal;
  // Construction draws: turn-on x, y, z; then Gauss-Markov initial x, y, z.
  std::array<double, 3> n_turn_on{}, n_initial{};
  for (double& v : n_turn_on) v = normal(p->eng);
  for (double& v : n_initial) v = normal(p->eng);

  for (std::size_t i = 0; i < 3; ++i) {
    const AxisModel& a = model.axes[i];
    p->turn_on[i] = a.turn_on_sigma * n_turn_on[i];
    k.offset[i] = a.fixed_bias + p->turn_on[i];
    k.white[i] = a.white_sigma;
    k.tc[i] = a.temp_coeff;
    switch (a.bias) {
      case BiasProcess::none:
        k.phi[i] = 1.0;
        k.gain[i] = 0.0;
        k.b[i] = 0.0;
        break;
      case BiasProcess::random_walk:
        k.phi[i] = 1.0;
        // Euler step of db/dt = mu (the paper's eq. 2/15; docs/formulas/simulator.md §2.1).
        k.gain[i] = a.bias_sigma * dt;
        k.b[i] = 0.0;
        break;
      case BiasProcess::gauss_markov:
        k.phi[i] = std::exp(-dt / a.tau_c);
        // sqrt(1 - phi^2) without cancellation when dt << tau_c.
        k.gain[i] = a.bias_sigma * std::sqrt(-std::expm1(-2.0 * dt / a.tau_c));
        k.b[i] = a.bias_sigma * n_initial[i];  // stationary N(0, sigma_b^2)
        break;
    }
    for (std::size_t t = 0; t < a.power_law.size(); ++t) {
      p->power_law[i].emplace_back(a.power_law[t], dt, PowerLawGenerator::filter_length_for(record_samples),
                                   power_law_seed(seed, i, t));
      p->has_extra = true;
    }
    if (!a.composite.processes.empty()) {
      p->composite.emplace_back(i, CompositeNoise(a.composite, composite_seed(seed, i)));
      p->has_extra = true;
    }
  }
  impl_ = std::move(p);
}

TriadSimulator::~TriadSimulator() = default;
TriadSimulator::TriadSimulator(TriadSimulator&&) noexcept = default;
TriadSimulator& TriadSimulator::operator=(TriadSimulator&&) noexcept = default;

std::array<double, 3> TriadSimulator::step(const std::array<double, 3>& true_input, double temperature) noexcept {
  std::array<double, 3> out{};
  Impl& s = *impl_;
  if (s.has_extra) {
    s.extra_noise(1);
    const double* e = s.extra.data();
    switch (s.quant) {
      case QuantMode::none:
        s.kern.sample<QuantMode::none, true, true>(s.eng, true_input.data(), temperature, out.data(), e);
        break;
      case QuantMode::truncate:
        s.kern.sample<QuantMode::truncate, true, true>(s.eng, true_input.data(), temperature, out.data(), e);
        break;
      case QuantMode::round:
        s.kern.sample<QuantMode::round, true, true>(s.eng, true_input.data(), temperature, out.data(), e);
        break;
    }
    return out;
  }
  switch (s.quant) {
    case QuantMode::none:
      s.kern.sample<QuantMode::none, true>(s.eng, true_input.data(), temperature, out.data());
      break;
    case QuantMode::truncate:
      s.kern.sample<QuantMode::truncate, true>(s.eng, true_input.data(), temperature, out.data());
      break;
    case QuantMode::round:
      s.kern.sample<QuantMode::round, true>(s.eng, true_input.data(), temperature, out.data());
      break;
  }
  return out;
}

void TriadSimulator::run(std::size_t n, std::span<const double> true_input, std::span<const double> temperature,
                         std::span<double> out) {
  require(n <= out.size() / 3 && out.size() == 3 * n, "out has " + std::to_string(out.size()) + " values; " +
                                                          std::to_string(n) + " samples need " + std::to_string(3 * n) +
                                                          " (n x 3)");
  require(true_input.empty() || true_input.size() == 3 * n,
          "true_input has " + std::to_string(true_input.size()) +
              " values; it must be empty or n x 3 = " + std::to_string(3 * n));
  require(temperature.empty() || temperature.size() == n, "temperature has " + std::to_string(temperature.size()) +
                                                              " values; it must be empty or n = " + std::to_string(n));
  if (n == 0) return;
  Impl& s = *impl_;
  Kernel kern = s.kern;  // local copy: registers, no aliasing with out
  const double* in = true_input.empty() ? nullptr : true_input.data();
  const double* temp = temperature.empty() ? nullptr : temperature.data();
  const double* extra = nullptr;
  if (s.has_extra) {
    s.extra_noise(n);
    extra = s.extra.data();
  }
  switch (s.quant) {
    case QuantMode::none: dispatch_run<QuantMode::none>(kern, s.eng, n, in, temp, out.data(), extra); break;
    case QuantMode::truncate: dispatch_run<QuantMode::truncate>(kern, s.eng, n, in, temp, out.data(), extra); break;
    case QuantMode::round: dispatch_run<QuantMode::round>(kern, s.eng, n, in, temp, out.data(), extra); break;
  }
  s.kern.b = kern.b;
}

const TriadModel& TriadSimulator::model() const noexcept { return impl_->model; }
double TriadSimulator::dt() const noexcept { return impl_->dt; }
std::array<double, 3> TriadSimulator::turn_on() const noexcept { return impl_->turn_on; }
std::array<double, 3> TriadSimulator::bias_state() const noexcept { return impl_->kern.b; }

}  // namespace cubecal
