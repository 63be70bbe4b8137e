// Simulate a gyro, compute its overlapping Allan deviation, fit its angle
// random walk N and rate random walk K, and check them against the truth.
// Built against an installed cubecal with find_package(cubecal COMPONENTS core).
#include <cmath>
#include <cstdio>
#include <cubecal/cubecal.hpp>
#include <vector>

int main() {
  cubecal::TriadModel model;  // every axis: white noise + a random-walk bias
  for (auto& axis : model.axes) {
    axis.white_sigma = 0.02;  // deg/s per sample
    axis.bias = cubecal::BiasProcess::random_walk;
    axis.bias_sigma = 1e-3;  // sigma_mu, deg/s/s: the bias moves sigma_mu dt n_k per sample
  }
  const double rate = 100.0;                            // Hz
  const std::size_t n = 2 * 3600 * 100;                 // 2 h
  cubecal::TriadSimulator gyro(model, 1.0 / rate, 42);  // seed 42
  std::vector<double> xyz(3 * n), x(n);
  gyro.run(n, {}, {}, xyz);
  for (std::size_t i = 0; i < n; ++i) x[i] = xyz[3 * i];

  const auto adev = cubecal::oadev(x, rate, cubecal::DataType::freq, cubecal::parse_tau_grid("log:10"));
  const auto fit = cubecal::fit_noise_terms(cubecal::to_allan_curve(adev));

  const double dt = 1.0 / rate;  // N = sigma_n sqrt(dt), K = sigma_mu sqrt(dt) (docs/formulas/noise-terms.md)
  const double n_true = 0.02 * std::sqrt(dt), k_true = 1e-3 * std::sqrt(dt);
  std::printf("N = %.6f ± %.6f deg/sqrt(s)  (true %.6f)\n", fit.N.value, fit.N.sigma, n_true);
  std::printf("K = %.6f ± %.6f deg/s/sqrt(s) (true %.6f)\n", fit.K.value, fit.K.sigma, k_true);
  const bool ok = fit.N.valid && fit.K.valid && std::abs(fit.N.value - n_true) < 4 * fit.N.sigma &&
                  std::abs(fit.K.value - k_true) < 4 * fit.K.sigma;
  return ok ? 0 : 1;
}
