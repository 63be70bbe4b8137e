/// @file
/// Equivalent degrees of freedom of stability variances.
#pragma once
#include <cstddef>

#include "cubecal/stats/statistic.hpp"

namespace cubecal {

/// Greenhall & Riley (PTTI 2003) EDF for a variance built on d-th phase
/// differences. alpha: noise exponent; m: averaging factor; n_phase: phase
/// points; overlapping: stride m (else stride 1 in units of tau); modified:
/// MVAR/TVAR filter. Returns 0 when the algorithm has no answer (alpha+2d<=1).
double edf_greenhall(int alpha, int d, std::size_t m, std::size_t n_phase, bool overlapping, bool modified);

/// The same for terms taken every `stride` phase points (a divisor of m):
/// Greenhall & Riley's stride factor S = m / stride, so stride 1 is the
/// overlapping estimator above and stride m the non-overlapping one. The
/// streamed deviations (stats/streaming_deviation.hpp) use strides between.
/// Returns 0 for a stride that does not divide m.
double edf_greenhall_stride(int alpha, int d, std::size_t m, std::size_t n_phase, std::size_t stride, bool modified);

/// Greenhall & Riley's EDF with the case of their algorithm that gave it:
/// "1.1" .. "1.3" (modified variances), "2.1a", "2.1b", "2.2", "2.3"
/// (unmodified, alpha <= 0), "3.1" .. "3.3" (unmodified flicker PM), "4.1"
/// (unmodified white PM, ceil(r) <= d: the direct sum) and "4.2". An empty
/// case and edf 0: no answer (as edf_greenhall_stride).
struct GreenhallEdf {
  double edf = 0.0;         ///< equivalent degrees of freedom
  const char* method = "";  ///< the case that answered
};

/// edf_greenhall_stride with the case that answered.
GreenhallEdf edf_greenhall_case(int alpha, int d, std::size_t m, std::size_t n_phase, std::size_t stride,
                                bool modified);

/// The pieces of Greenhall & Riley's algorithm (PTTI 2003; Greenhall 2004),
/// for callers that evaluate its equations themselves (the Python module's
/// AllanTools-shaped calls). alpha: 2 .. -4, d: 1 .. 3; outside, 0.
namespace greenhall {

/// Eq. (7): the generalized autocovariance kernel of phase noise alpha at lag t.
double sw(double t, int alpha);
/// Eq. (8): sw under the averaging filter of length 1/F (F infinite: a point sample).
double sx(double t, double F, int alpha);
/// Eq. (9): sx under the d-th difference.
double sz(double t, double F, int alpha, int d);
/// Eq. (10): the basic sum over J lags of M terms at stride factor S.
double basic_sum(double J, double M, double S, double F, int alpha, int d);
/// Eq. (13) with J and M given: sz(0)^2 M / basic_sum (0 when the sum is not positive).
double edf_direct(double J, double M, double S, double F, int alpha, int d);
/// Eq. (13) on N phase points at factor m, stride factor S and filter factor
/// F: L = m/F + m d, M = 1 + floor(S (N - L) / m), J = min(M, (d+1) S).
double edf_eq13(int alpha, int d, double m, double S, double F, double N);

/// A pair of coefficients of Greenhall & Riley's tables.
struct Coeffs {
  double a0 = 0.0;  ///< first coefficient
  double a1 = 0.0;  ///< second coefficient
};
/// Table 1 (modified variances, large r): {0, 0} where the variance does not converge.
Coeffs table1(int alpha, int d);
/// Table 2 (unmodified variances, large r): {0, 0} where the variance does not converge.
Coeffs table2(int alpha, int d);
/// Table 3 (unmodified flicker PM): the log factor b0 + b1 ln m, as {b0, b1}.
Coeffs table3(int d);

}  // namespace greenhall

/// NIST SP 1065 Table 8 for MTOT on its own, b (N/m) - c at every m (alpha
/// 2 .. -2; 0 otherwise), not bounded below: edf_mtotvar takes it from m = 10 on.
double edf_mtotvar_table(int alpha, double m, double n_phase);

/// NIST SP 1065 Table 5 simple approximations (overlapping AVAR).
double edf_simple(int alpha, std::size_t m, std::size_t n_phase);

/// NIST SP 1065 Table 11 for TOTVAR (b*T/tau - c) for white, flicker and
/// random-walk FM; for flicker PM Stable32's rule (SP 1065 Table 5 plus 2),
/// for white PM Table 5.
double edf_totvar(int alpha, std::size_t m, std::size_t n_phase);

/// MTOT and TTOT: MDEV's Greenhall-Riley EDF below m = 10, NIST SP 1065
/// Table 8 from m = 10 on (b (N/m) - c), alpha 2 .. -2 (0 otherwise).
/// Stable32 takes MDEV's EDF at the same factors; from m = 10 on its
/// intervals follow other coefficients (docs/formulas/stability.md, 5.6).
double edf_mtotvar(int alpha, std::size_t m, std::size_t n_phase);

/// HTOT: from m = 16 on, for white FM to random-run FM (alpha 0 .. -4),
/// Howe et al.'s (T/tau) / (b0 + b1 tau/T) (PTTI 2000, Table 1), and for
/// flicker PM Stable32's rule (SP 1065 Table 5 plus 2, as edf_totvar); below
/// m = 16, and for white PM, the SP 1065 Table 5 approximation (Stable32's
/// choice); the overlapping Hadamard EDF for alpha -3 and -4 below m = 16.
double edf_htotvar(int alpha, std::size_t m, std::size_t n_phase);

/// Theo1 (and TheoBR) at even factor m on N phase points, r = 0.75 m: the
/// five forms of NIST SP 1065 sec. 5.2.15 (Howe & Peppler 2003, Howe &
/// Tasset 2004) for alpha 2 .. -2; 0 (no interval) for other alpha.
double edf_theo1(int alpha, std::size_t m, std::size_t n_phase);

/// How the EDF of a deviation is computed: Greenhall's algorithm, or Stable32's simple approximations.
enum class EdfMethod { greenhall, simple };

/// EDF of a statistic as Stable32 computes it (MTOT, TTOT, HTOT and the
/// Theo family by the functions above whatever the method, TheoH by its
/// part at m; TIE rms and MTIE: 0, no interval).
double edf_for(Stat stat, int alpha, std::size_t m, std::size_t n_phase, EdfMethod method = EdfMethod::greenhall);

/// edf_for with the overlapping statistics' terms taken every `stride`
/// points (adev and hdev are non-overlapping whatever the stride; the simple
/// formulas know no stride and give edf_for's value).
double edf_for_stride(Stat stat, int alpha, std::size_t m, std::size_t n_phase, std::size_t stride,
                      EdfMethod method = EdfMethod::greenhall);

}  // namespace cubecal
