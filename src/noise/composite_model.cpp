// Composite noise models and their Haar wavelet variances
// (composite_model.hpp; docs/formulas/noise-terms.md §8a).
#include "cubecal/noise/composite_model.hpp"

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string_view>

#include "cubecal/error.hpp"
#include "cubecal/noise/sensor_noise_model.hpp"

namespace cubecal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;

struct Name {
  std::string_view text;
  ProcessKind kind;
};
constexpr std::array<Name, 8> kNames{{{"WN", ProcessKind::wn},
                                      {"QN", ProcessKind::qn},
                                      {"RW", ProcessKind::rw},
                                      {"DR", ProcessKind::dr},
                                      {"GM", ProcessKind::gm},
                                      {"AR1", ProcessKind::gm},
                                      {"MA1", ProcessKind::ma1},
                                      {"SIN", ProcessKind::sin}}};

std::string upper_trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

[[noreturn]] void bad_model(const std::string& text, const std::string& why) {
  throw UsageError(Field::model,
                   "model '" + text + "': " + why +
                       " (terms: WN, QN, RW, DR, GM or AR1, MA1, SIN, k*GM or k*SIN for k of them, joined by +; "
                       "e.g. WN+RW+2*GM, MA1+RW+2*GM+SIN)");
}

}  // namespace

CompositeModel parse_composite_model(const std::string& text) {
  CompositeModel model;
  std::array<bool, 7> once{};
  std::string_view rest(text);
  if (upper_trimmed(rest).empty()) bad_model(text, "no term");
  while (true) {
    const std::size_t plus = rest.find('+');
    const std::string term = upper_trimmed(rest.substr(0, plus));
    if (term.empty()) bad_model(text, "an empty term");
    std::size_t copies = 1;
    std::string name = term;
    if (const std::size_t star = term.find('*'); star != std::string::npos) {
      const std::string count = upper_trimmed(term.substr(0, star));
      name = upper_trimmed(term.substr(star + 1));
      if (count.empty() || count.size() > 2 || count.find_first_not_of("0123456789") != std::string::npos ||
          std::stoul(count) < 1)
        bad_model(text, "'" + term + "' is not k*TERM with k a whole number from 1 to 99");
      copies = std::stoul(count);
    }
    const Name* found = nullptr;
    for (const Name& n : kNames)
      if (n.text == name) found = &n;
    if (found == nullptr) bad_model(text, "unknown term '" + name + "'");
    if (found->kind != ProcessKind::gm && found->kind != ProcessKind::sin) {
      bool& seen = once[static_cast<std::size_t>(found->kind)];
      if (seen || copies > 1)
        bad_model(text, std::string(found->text) + " appears more than once (two of them cannot be told apart)");
      seen = true;
    }
    for (std::size_t k = 0; k < copies; ++k) model.processes.push_back(Process{found->kind, 0.0, 0.0});
    if (plus == std::string_view::npos) break;
    rest.remove_prefix(plus + 1);
  }
  // MA1 + WN or MA1 + QN is again an MA(1) (composite_model.hpp): its
  // parameters could not be told apart.
  const auto has = [&](ProcessKind k) { return once[static_cast<std::size_t>(k)]; };
  for (const ProcessKind k : {ProcessKind::wn, ProcessKind::qn})
    if (has(ProcessKind::ma1) && has(k))
      bad_model(text, "MA1 with " + std::string(to_string(k)) +
                          " (their sum is another MA1: MA1 replaces WN, and takes up a QN)");
  return model;
}

std::string_view to_string(ProcessKind k) noexcept {
  for (const Name& n : kNames)
    if (n.kind == k) return n.text;
  return "?";
}

std::size_t parameter_count(const CompositeModel& model) noexcept {
  std::size_t k = 0;
  for (const Process& p : model.processes)
    k += p.kind == ProcessKind::gm || p.kind == ProcessKind::ma1 || p.kind == ProcessKind::sin ? 2 : 1;
  return k;
}

std::string model_name(const CompositeModel& model) {
  std::string out;
  std::size_t i = 0;
  const auto& p = model.processes;
  while (i < p.size()) {
    std::size_t run = 1;
    while (i + run < p.size() && p[i + run].kind == p[i].kind) ++run;
    if (!out.empty()) out += '+';
    if (run > 1) out += std::to_string(run) + '*';
    out += to_string(p[i].kind);
    i += run;
  }
  return out;
}

double haar_wavelet_variance(const Process& p, double tau) noexcept {
  if (!(tau >= 2.0)) return kNaN;
  switch (p.kind) {
    case ProcessKind::wn: return p.value >= 0.0 ? p.value / tau : kNaN;
    case ProcessKind::qn:
      // AVAR of X_t = U_{t+1} - U_t: 3 Q2 / m^2; halved at m = tau / 2.
      return p.value >= 0.0 ? 6.0 * p.value / (tau * tau) : kNaN;
    case ProcessKind::rw:
      // AVAR gamma2 (2 m^2 + 1) / (6 m); halved at m = tau / 2.
      return p.value >= 0.0 ? p.value * (tau * tau + 2.0) / (12.0 * tau) : kNaN;
    case ProcessKind::dr: return p.value * p.value * tau * tau / 16.0;
    case ProcessKind::gm: {
      if (!(p.value >= 0.0) || !(p.phi > 0.0 && p.phi < 1.0)) return kNaN;
      return gauss_markov_wavelet_variance(-std::log(p.phi), p.value, tau);
    }
    case ProcessKind::ma1: {
      // WN of sigma2 (1 + theta)^2 plus QN of Q2 = -theta sigma2: the same
      // autocovariance (gamma0 = sigma2 (1 + theta^2), gamma1 = sigma2 theta).
      if (!(p.value >= 0.0) || !(std::abs(p.theta) < 1.0)) return kNaN;
      const double w = (1.0 + p.theta) * (1.0 + p.theta);
      return p.value * (w * tau - 6.0 * p.theta) / (tau * tau);
    }
    case ProcessKind::sin: {
      // The difference of two adjacent means of m = tau / 2 samples of
      // A sin(omega t + U) is a sinusoid of amplitude
      // 2 A sin^2(omega m / 2) / (m sin(omega / 2)); the Haar coefficient is
      // half of it, its mean square over U half the amplitude squared.
      if (!(p.value >= 0.0) || !(p.omega > 0.0 && p.omega < kPi)) return kNaN;
      const double s = std::sin(p.omega * tau / 4.0), S = std::sin(p.omega / 2.0);
      return 2.0 * p.value * s * s * s * s / (tau * tau * S * S);
    }
  }
  return kNaN;
}

double gauss_markov_wavelet_variance(double a, double sigma2, double tau) noexcept {
  const double m = tau / 2.0;
  if (!(tau >= 2.0) || std::floor(m) != m || !(a > 0.0) || !(sigma2 >= 0.0)) return kNaN;
  // The exact AR(1) AVAR of sensor_noise_model.cpp (careful near phi = 1),
  // stationary variance sigma2 / (1 - phi^2), unit sample period.
  GaussMarkovModel g;
  g.dt = 1.0;
  g.tau_c = 1.0 / a;
  g.sigma_b = std::sqrt(sigma2 / -std::expm1(-2.0 * a));
  return 0.5 * avar(g, static_cast<std::size_t>(m));
}

double haar_wavelet_variance(const CompositeModel& model, double tau) noexcept {
  double sum = 0.0;
  for (const Process& p : model.processes) sum += haar_wavelet_variance(p, tau);
  return sum;
}

GaussMarkovTerm gauss_markov_term(const Process& gm, double dt) {
  if (gm.kind != ProcessKind::gm || !(gm.phi > 0.0 && gm.phi < 1.0) || !(gm.value >= 0.0) || !(dt > 0.0))
    throw UsageError(Field::model,
                     "a Gauss-Markov term needs 0 < phi < 1, a variance >= 0 and a positive sample period");
  return {-dt / std::log(gm.phi), std::sqrt(gm.value / -std::expm1(2.0 * std::log(gm.phi)))};
}

Process gm_process(double tau_c, double sigma_b, double dt) {
  if (!(tau_c > 0.0) || !(sigma_b >= 0.0) || !(dt > 0.0) || !std::isfinite(tau_c))
    throw UsageError(Field::model, "a Gauss-Markov term needs a positive, finite correlation time and sigma_b >= 0");
  const double a = dt / tau_c;
  return {ProcessKind::gm, sigma_b * sigma_b * -std::expm1(-2.0 * a), std::exp(-a)};
}

MovingAverageTerm moving_average_term(const Process& ma1, double dt) {
  if (ma1.kind != ProcessKind::ma1 || !(std::abs(ma1.theta) < 1.0) || !(ma1.value >= 0.0) || !(dt > 0.0))
    throw UsageError(Field::model, "an MA1 term needs -1 < theta < 1, a variance >= 0 and a positive sample period");
  return {std::sqrt(ma1.value * dt) * (1.0 + ma1.theta), ma1.theta};
}

Process ma1_process(double n, double theta, double dt) {
  if (!(n >= 0.0) || !std::isfinite(n) || !(std::abs(theta) < 1.0) || !(dt > 0.0))
    throw UsageError(Field::model, "an MA1 term needs a finite N >= 0 and -1 < theta < 1");
  Process p{ProcessKind::ma1, n * n / (dt * (1.0 + theta) * (1.0 + theta)), 0.0, theta};
  return p;
}

SineTerm sine_term(const Process& sin, double dt) {
  if (sin.kind != ProcessKind::sin || !(sin.value >= 0.0) || !(sin.omega > 0.0 && sin.omega < kPi) || !(dt > 0.0))
    throw UsageError(Field::model, "a SIN term needs A^2 >= 0, 0 < omega < pi and a positive sample period");
  return {std::sqrt(sin.value), sin.omega / (2.0 * kPi * dt)};
}

Process sin_process(double amplitude, double frequency_hz, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw UsageError(Field::model, "a SIN term needs a positive, finite sample period");
  if (!(amplitude >= 0.0) || !std::isfinite(amplitude))
    throw UsageError(Field::model, "a SIN term needs a finite amplitude >= 0");
  const double nyquist = 0.5 / dt;
  if (!(frequency_hz > 0.0 && frequency_hz < nyquist)) {
    char b[96];
    std::snprintf(b, sizeof b, "a SIN line at %.6g Hz lies outside (0, %.6g) Hz", frequency_hz, nyquist);
    throw UsageError(Field::model, std::string(b) +
                                       ", the band a record at this rate can hold (the Nyquist frequency is "
                                       "half the rate)");
  }
  Process p{ProcessKind::sin, amplitude * amplitude, 0.0, 0.0, 2.0 * kPi * frequency_hz * dt};
  return p;
}

}  // namespace cubecal
