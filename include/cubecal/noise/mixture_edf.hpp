/// @file
/// The EDF of an overlapping Allan variance point when the noise is a
/// mixture of power laws (docs/formulas/planning.md §2): Greenhall's EDF is
/// exact for one noise type, but where two types share the variance (the
/// minimum of a white-noise plus random-walk curve) the estimate averages
/// two partly independent parts: steadier than the flicker FM type its slope
/// (0 at the minimum) suggests, and than the steeper part alone.
///
/// With the variance at tau = m tau0 split into the shares s_k of the terms
/// of sigma^2(tau) = sum_k C_k tau^k (k = -2 white PM, -1 white FM, 0
/// flicker FM, +1 random-walk FM, +2 rate ramp, deterministic: no variance
/// of its own), each share with Greenhall's relative variance
/// v_k = 2 / edf(alpha_k, m, N), and the parts correlated as their spectra
/// overlap under the Allan filter,
///   v = sum_jk s_j s_k sqrt(v_j v_k) rho_jk,
///   rho_jk = int S_j S_k g^2 df / sqrt(int S_j^2 g^2 df int S_k^2 g^2 df),
/// g(f tau) = 2 sin^4(pi f tau) / (pi f tau)^2, and edf = 2 / v. One type
/// alone gives Greenhall's EDF exactly.
#pragma once
#include <array>
#include <cstddef>

namespace cubecal {

/// The EDF of the OADEV point at factor m (tau = m tau0, s) of a record of
/// n_phase phase points (samples + 1) whose Allan variance is
/// sum_k c[k + 2] tau^k (k = -2..2, data unit^2, each c >= 0). 0 when no
/// share has an EDF (all c zero, or m too large for the record). Throws nothing.
double oadev_mixture_edf(const std::array<double, 5>& c, std::size_t m, double tau0, std::size_t n_phase) noexcept;

}  // namespace cubecal
