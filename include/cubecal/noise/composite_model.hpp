/// @file
/// Composite noise models: a sum of independent latent processes, the model
/// class of the Generalized Method of Wavelet Moments (GMWM: Guerrier,
/// Skaloud, Stebler, Victoria-Feser, JASA 2013; the gmwm/simts packages), and
/// the Haar wavelet variance each process has in theory
/// (docs/formulas/noise-terms.md §8a).
///
/// Parameters are per sample, as the GMWM literature states them:
///   WN  white noise, variance sigma2                 nu^2(tau) = sigma2 / tau
///   QN  quantization noise Q2 (X_t = U_{t+1} - U_t,
///       U white of variance Q2)                       nu^2(tau) = 6 Q2 / tau^2
///   RW  random walk, innovation variance gamma2      nu^2(tau) = gamma2 (tau^2 + 2) / (12 tau)
///   DR  drift, omega per sample (X_t = omega t)       nu^2(tau) = omega^2 tau^2 / 16
///   GM  Gauss-Markov (AR(1) with 0 < phi < 1),
///       innovation variance sigma2                   nu^2(tau) = AVAR_AR1(tau / 2) / 2
///   MA1 first-order moving average X_t = e_t + theta e_{t-1}, |theta| < 1,
///       e white of variance sigma2                   nu^2(tau) = sigma2 ((1 + theta)^2 tau - 6 theta) / tau^2
///   SIN a periodic line X_t = A sin(omega t + U), U uniform on [0, 2 pi),
///       0 < omega < pi rad per sample, value A^2      nu^2(tau) = (A^2 / 2) 4 sin^4(omega tau / 4)
///                                                                 / (tau^2 sin^2(omega / 2))
/// with tau = 2^j the dyadic scale in samples. The Haar wavelet variance is
/// half the Allan variance at m = tau / 2 (the MODWT Haar coefficient is half
/// the difference of two adjacent m-sample means), so every form above is the
/// exact discrete AVAR of sensor_noise_model.hpp halved. An MA1's
/// autocovariance is that of a WN of variance sigma2 (1 + theta)^2 plus a QN
/// of Q2 = -theta sigma2, hence its form; it replaces WN (theta = 0 is WN) and
/// is refused beside WN or QN, whose sum with it is again an MA(1) that the
/// wavelet variance cannot split. A SIN term (simts' SIN(); Voirol et al.
/// 2023, arXiv:2303.18167) is the vibration line a real MEMS sensor shows (a
/// rotor, a fan, a tone of the acquisition); several may be given, each its
/// own frequency.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal {

/// The processes of a composite model: white noise, quantization noise, random walk, drift, Gauss-Markov, first-order
/// moving average, periodic line.
enum class ProcessKind { wn, qn, rw, dr, gm, ma1, sin };

/// One latent process of a composite model, its parameters per sample (see the table above).
struct Process {
  /// Which process.
  ProcessKind kind = ProcessKind::wn;
  /// wn: sigma2; qn: Q2; rw: gamma2; gm, ma1: the innovation variance sigma2;
  /// dr: omega (per sample, any sign); sin: the squared amplitude A^2.
  double value = 0.0;
  double phi = 0.0;    ///< gm only: the lag-one correlation, 0 < phi < 1
  double theta = 0.0;  ///< ma1 only: the moving-average coefficient, -1 < theta < 1
  double omega = 0.0;  ///< sin only: the angular frequency, rad per sample, 0 < omega < pi
};

/// A composite noise model: the sum of independent processes.
struct CompositeModel {
  /// The processes, in the order parsed or fitted.
  std::vector<Process> processes;
};

/// "WN+QN+RW+DR+2*GM", "MA1+RW+2*GM", "MA1+RW+GM+2*SIN" (case-insensitive;
/// AR1 is a synonym of GM; spaces allowed; k*TERM repeats a GM or SIN term):
/// the processes with zero parameters. Throws UsageError(Field::model) naming what it could not read and
/// the terms it knows; each of WN, QN, RW, DR and MA1 may appear once, and
/// MA1 not beside WN or QN.
CompositeModel parse_composite_model(const std::string& text);

/// "WN+QN+RW+2*GM": the model's terms in the order of parse_composite_model.
std::string model_name(const CompositeModel& model);
std::string_view to_string(ProcessKind kind) noexcept;  ///< "WN", "QN", "RW", "DR", "GM", "MA1", "SIN"
/// The parameters a fit estimates: one per process, two per Gauss-Markov, MA1 or SIN term.
std::size_t parameter_count(const CompositeModel& model) noexcept;

/// Theoretical Haar wavelet variance at the scale of tau samples (tau >= 2,
/// even): exact for the sampled processes. NaN for a parameter outside its
/// range (a negative variance, phi outside (0, 1), |theta| >= 1, omega
/// outside (0, pi)).
double haar_wavelet_variance(const Process& process, double tau) noexcept;
/// The model's: the sum of its processes'. NaN for a parameter outside its range; throws nothing.
double haar_wavelet_variance(const CompositeModel& model, double tau) noexcept;

/// A Gauss-Markov term's from a = -ln(phi) itself, which phi near 1 holds to
/// fewer digits (the form the GMWM fit works in).
double gauss_markov_wavelet_variance(double a, double sigma2, double tau) noexcept;

/// Physical forms for a sample period dt (s), in the data unit u:
///   WN: N = sqrt(sigma2 dt)            (u sqrt(s), the angle random walk for a gyro)
///   RW: K = sqrt(gamma2 / dt)          (u / sqrt(s), the rate random walk)
///   QN: Q = sqrt(Q2) dt                (u s: IEEE 952's quantization Q, AVAR 3 Q^2 / tau^2)
///   DR: R = omega / dt                 (u / s)
///   GM: correlation time T = -dt / ln(phi), stationary sigma_b = sqrt(sigma2 / (1 - phi^2))
///   MA1: N = sqrt(sigma2 dt) |1 + theta|, the white noise it is beyond the
///        first scales (its spectral density at frequency 0, the WV's
///        N^2 / (tau dt) term), and theta; its lag-one correlation is
///        theta / (1 + theta^2)
///   SIN: amplitude A = sqrt(value) (u), frequency f = omega / (2 pi dt) (Hz)
struct GaussMarkovTerm {
  double tau_c = 0.0;    ///< s
  double sigma_b = 0.0;  ///< u
};
/// A Gauss-Markov process's correlation time (s) and stationary sigma_b (u) for a sample period dt (s). Throws
/// UsageError("model") for phi outside (0, 1), a negative variance or dt not positive.
GaussMarkovTerm gauss_markov_term(const Process& gm, double dt);
/// The Gauss-Markov process (per sample) of correlation time tau_c (s) and stationary sigma_b (u) at period dt (s).
/// Throws UsageError("model") for a correlation time not positive and finite or sigma_b negative.
Process gm_process(double tau_c, double sigma_b, double dt);

/// An MA1 term in physical units.
struct MovingAverageTerm {
  double n = 0.0;  ///< u sqrt(s)
  /// The moving-average coefficient (-1 < theta < 1, dimensionless).
  double theta = 0.0;
};
/// An MA1 process's N (u sqrt(s)) and theta for a sample period dt (s). Throws UsageError("model") for |theta| >= 1, a
/// negative variance or dt not positive.
MovingAverageTerm moving_average_term(const Process& ma1, double dt);
/// The MA1 process (per sample) of white noise N (u sqrt(s)) and coefficient theta at period dt (s). Throws
/// UsageError("model") for N negative or not finite or |theta| >= 1.
Process ma1_process(double n, double theta, double dt);

/// A SIN term in physical units.
struct SineTerm {
  double amplitude = 0.0;     ///< u
  double frequency_hz = 0.0;  ///< Hz
};
/// A SIN process's amplitude (u) and frequency (Hz) for a sample period dt (s). Throws UsageError("model") for A^2
/// negative, omega outside (0, pi) or dt not positive.
SineTerm sine_term(const Process& sin, double dt);
/// Throws UsageError(Field::model) for a negative amplitude or a frequency not
/// strictly between 0 and the Nyquist frequency 1 / (2 dt).
Process sin_process(double amplitude, double frequency_hz, double dt);

}  // namespace cubecal
