// Equivalent degrees of freedom.
//
// Greenhall & Riley, "Uncertainty of stability variances based on finite
// differences", PTTI 2003: the EDF of a variance built on d-th differences
// of phase follows from the generalized autocovariance of the power-law
// phase noise, sw(t) ~ |t|^(-alpha-1) (with a log factor for odd alpha).
// Eq. (13) sums it directly when at most J_max = 100 lags contribute;
// Tables 1-3 give the large-r asymptotes otherwise.
#include "cubecal/stats/edf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cubecal {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kJmax = 100;
// Where the total variances' own EDF formulas take over (see edf_mtotvar,
// edf_htotvar).
constexpr std::size_t kMtotTableFrom = 10;
constexpr std::size_t kHtotTableFrom = 16;

double binomial(int n, int k) {
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

}  // namespace

namespace greenhall {
// Eq. (7): generalized autocovariance kernel of phase noise with exponent alpha.
double sw(double t, int alpha) {
  const double a = std::abs(t);
  switch (alpha) {
    case 2: return -a;
    case 1: return a == 0.0 ? 0.0 : t * t * std::log(a);
    case 0: return a * a * a;
    case -1: return a == 0.0 ? 0.0 : t * t * t * t * std::log(a);
    case -2: return a * a * a * a * a;
    case -3: return a == 0.0 ? 0.0 : std::pow(t, 6) * std::log(a);
    case -4: return std::pow(a, 7);
    default: return 0.0;
  }
}

// Eq. (8): the averaging filter of length 1/F applied to the kernel;
// F = infinity is the limit of an unfiltered (point) sample.
double sx(double t, double F, int alpha) {
  if (std::isinf(F)) return sw(t, alpha + 2);
  return F * F * (2.0 * sw(t, alpha) - sw(t - 1.0 / F, alpha) - sw(t + 1.0 / F, alpha));
}

// Eq. (9): the d-th difference, coefficients (-1)^j C(2d, d+j).
double sz(double t, double F, int alpha, int d) {
  switch (d) {
    case 1: return 2.0 * sx(t, F, alpha) - sx(t - 1.0, F, alpha) - sx(t + 1.0, F, alpha);
    case 2:
      return 6.0 * sx(t, F, alpha) - 4.0 * (sx(t - 1.0, F, alpha) + sx(t + 1.0, F, alpha)) + sx(t - 2.0, F, alpha) +
             sx(t + 2.0, F, alpha);
    case 3:
      return 20.0 * sx(t, F, alpha) - 15.0 * (sx(t - 1.0, F, alpha) + sx(t + 1.0, F, alpha)) +
             6.0 * (sx(t - 2.0, F, alpha) + sx(t + 2.0, F, alpha)) - (sx(t - 3.0, F, alpha) + sx(t + 3.0, F, alpha));
    default: return 0.0;
  }
}

// Eq. (10).
double basic_sum(double J, double M, double S, double F, int alpha, int d) {
  const double z0 = sz(0.0, F, alpha, d);
  const double zJ = sz(J / S, F, alpha, d);
  double sum = z0 * z0 + (1.0 - J / M) * zJ * zJ;
  const int jn = static_cast<int>(J);
  for (int j = 1; j < jn; ++j) {
    const double z = sz(j / S, F, alpha, d);
    sum += 2.0 * (1.0 - j / M) * z * z;
  }
  return sum;
}

// Eq. (13) evaluated: EDF = sz(0)^2 M / BasicSum.
double edf_direct(double J, double M, double S, double F, int alpha, int d) {
  const double z0 = sz(0.0, F, alpha, d);
  const double bs = basic_sum(J, M, S, F, alpha, d);
  return bs > 0.0 ? z0 * z0 * M / bs : 0.0;
}

// Table 1 (modified variances), rows alpha = 2..-4, columns d = 1..3.
// {0,0} marks combinations where the variance does not converge.
constexpr Coeffs kTable1[7][3] = {
    {{2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}, {22.0 / 25.0, 2.0 / 3.0}},
    {{0.840, 0.345}, {0.997, 0.616}, {1.141, 0.843}},
    {{1.079, 0.368}, {1.033, 0.607}, {1.184, 0.848}},
    {{0, 0}, {1.048, 0.534}, {1.180, 0.816}},
    {{0, 0}, {1.302, 0.535}, {1.175, 0.777}},
    {{0, 0}, {0, 0}, {1.194, 0.703}},
    {{0, 0}, {0, 0}, {1.489, 0.702}},
};

// Table 2 (unmodified variances).
constexpr Coeffs kTable2[7][3] = {
    {{3.0 / 2.0, 1.0 / 2.0}, {35.0 / 18.0, 1.0}, {231.0 / 100.0, 3.0 / 2.0}},
    {{78.6, 25.2}, {790.0, 410.0}, {9950.0, 6520.0}},
    {{2.0 / 3.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}},
    {{0, 0}, {0.852, 0.375}, {0.997, 0.617}},
    {{0, 0}, {1.079, 0.368}, {1.033, 0.607}},
    {{0, 0}, {0, 0}, {1.053, 0.553}},
    {{0, 0}, {0, 0}, {1.302, 0.535}},
};

// Table 3 (unmodified, alpha = 1): log factor b0 + b1 ln m.
constexpr Coeffs kTable3[3] = {{6.0, 4.0}, {15.23, 12.0}, {47.8, 40.0}};

double edf_eq13(int alpha, int d, double m, double S, double F, double N) {
  const double L = m / F + m * d;
  const double M = 1.0 + std::floor(S * (N - L) / m);
  const double J = std::min(M, (d + 1) * S);
  return edf_direct(J, M, S, F, alpha, d);
}

Coeffs table1(int alpha, int d) {
  if (alpha > 2 || alpha < -4 || d < 1 || d > 3) return {};
  return kTable1[2 - alpha][d - 1];
}

Coeffs table2(int alpha, int d) {
  if (alpha > 2 || alpha < -4 || d < 1 || d > 3) return {};
  return kTable2[2 - alpha][d - 1];
}

Coeffs table3(int d) {
  if (d < 1 || d > 3) return {};
  return kTable3[d - 1];
}

}  // namespace greenhall

double edf_greenhall(int alpha, int d, std::size_t m, std::size_t n_phase, bool overlapping, bool modified) {
  return edf_greenhall_stride(alpha, d, m, n_phase, overlapping ? 1 : m, modified);
}

double edf_greenhall_stride(int alpha, int d, std::size_t m, std::size_t n_phase, std::size_t stride, bool modified) {
  return edf_greenhall_case(alpha, d, m, n_phase, stride, modified).edf;
}

namespace {

// Greenhall & Riley's cases 1 (modified) to 3 (unmodified flicker PM) with
// the J <= J_max sum, the large-r table and the J_max sum at r <= d + 1.
GreenhallEdf greenhall_filtered(int alpha, int d, double m, double M, double S, double J, bool modified) {
  using namespace greenhall;
  const double r = M / S;
  if (modified) {  // case 1: all alpha
    if (J <= kJmax) return {edf_direct(J, M, S, 1.0, alpha, d), "1.1"};
    if (r > d + 1) {
      const Coeffs c = table1(alpha, d);
      return {1.0 / ((c.a0 - c.a1 / r) / r), "1.2"};
    }
    return {edf_direct(kJmax, kJmax, kJmax / r, 1.0, alpha, d), "1.3"};
  }
  if (alpha <= 0) {  // case 2: unmodified, alpha <= 0
    if (J <= kJmax) {
      const bool a = m * (d + 1) <= kJmax;
      return {edf_direct(J, M, S, a ? m : kInf, alpha, d), a ? "2.1a" : "2.1b"};
    }
    if (r > d + 1) {
      const Coeffs c = table2(alpha, d);
      return {1.0 / ((c.a0 - c.a1 / r) / r), "2.2"};
    }
    return {edf_direct(kJmax, kJmax, kJmax / r, kInf, alpha, d), "2.3"};
  }
  // case 3: unmodified flicker PM
  if (J <= kJmax) return {edf_direct(J, M, S, m, alpha, d), "3.1"};
  const Coeffs b = table3(d);
  const double lf = b.a0 + b.a1 * std::log(m);
  if (r > d + 1) {
    const Coeffs c = table2(alpha, d);
    return {1.0 / ((c.a0 - c.a1 / r) / (lf * lf * r)), "3.2"};
  }
  const double mp = kJmax / r;
  const double bs = basic_sum(kJmax, kJmax, mp, mp, alpha, d);
  return {bs > 0.0 ? lf * lf * kJmax / bs : 0.0, "3.3"};
}

}  // namespace

GreenhallEdf edf_greenhall_case(int alpha, int d, std::size_t m_, std::size_t n_phase, std::size_t stride,
                                bool modified) {
  if (d < 1 || d > 3 || alpha > 2 || alpha < -4 || alpha + 2 * d <= 1 || m_ == 0) return {};
  if (stride == 0 || stride > m_ || m_ % stride != 0) return {};
  const double m = static_cast<double>(m_);
  const double N = static_cast<double>(n_phase);
  const double F = modified ? 1.0 : m;
  // The stride factor of the paper: S = m / stride (m: fully overlapping,
  // 1: non-overlapping), so that M counts the terms taken every stride.
  const double S = static_cast<double>(m_ / stride);
  const double L = m / F + m * d;  // span of the filter on phase samples
  if (N < L) return {};
  const double M = 1.0 + std::floor(S * (N - L) / m);
  const double J = std::min(M, (d + 1) * S);
  if (modified || alpha <= 1) return greenhall_filtered(alpha, d, m, M, S, J, modified);
  // case 4: unmodified white PM
  const double r = M / S;
  const double K = std::ceil(r);
  if (K <= d) return {greenhall::edf_direct(J, M, S, m, alpha, d), "4.1"};
  const double a0 = binomial(4 * d, 2 * d) / (binomial(2 * d, d) * binomial(2 * d, d));
  const double a1 = d / 2.0;
  return {1.0 / ((a0 - a1 / r) / M), "4.2"};
}

double edf_simple(int alpha, std::size_t m_, std::size_t n_phase) {
  const double N = static_cast<double>(n_phase);
  const double m = static_cast<double>(m_);
  switch (alpha) {
    case 2: return (N + 1.0) * (N - 2.0 * m) / (2.0 * (N - m));
    case 1: return std::exp(std::sqrt(std::log((N - 1.0) / (2.0 * m)) * std::log((2.0 * m + 1.0) * (N - 1.0) / 4.0)));
    case 0: return (3.0 * (N - 1.0) / (2.0 * m) - 2.0 * (N - 2.0) / N) * 4.0 * m * m / (4.0 * m * m + 5.0);
    case -1:
      // SP 1065 Table 5 has (N-2)^2 for m = 1.
      if (m_ == 1) return 2.0 * (N - 2.0) * (N - 2.0) / (2.3 * N - 4.9);
      return 5.0 * N * N / (4.0 * m * (N + 3.0 * m));
    case -2:
      return (N - 2.0) / m * ((N - 1.0) * (N - 1.0) - 3.0 * m * (N - 1.0) + 4.0 * m * m) / ((N - 3.0) * (N - 3.0));
    default: return N - 1.0;
  }
}

// Stable32's EDF of TOTDEV and of HTOT (from m = 16) for flicker PM, which
// neither SP 1065 Table 11 nor Howe et al.'s HTOT table covers: SP 1065
// Table 5's plus 2. Inverted from Stable32's bounds (TOTDEV m = 100 of the
// 1253-point Sr87 record, HTOT m = 100 of it and m = 128, 256 of PHASE.DAT:
// Table 5 + 2.07, 2.03, 2.15, 2.14), the bounds agree to 1.6e-4; no
// published form was found (docs/formulas/stability.md 5.4).
namespace {
double edf_flicker_pm_total(std::size_t m, std::size_t n_phase) { return edf_simple(1, m, n_phase) + 2.0; }
}  // namespace

double edf_totvar(int alpha, std::size_t m, std::size_t n_phase) {
  // SP 1065 Table 11: edf = b (T/tau) - c, T the record length.
  const double ratio = static_cast<double>(n_phase) / static_cast<double>(m);
  switch (alpha) {
    case 0: return 1.50 * ratio;
    case -1: return 1.17 * ratio - 0.22;
    case -2: return 0.93 * ratio - 0.36;
    case 1: return edf_flicker_pm_total(m, n_phase);
    default: return edf_simple(alpha, m, n_phase);
  }
}

double edf_mtotvar(int alpha, std::size_t m, std::size_t n_phase) {
  if (alpha > 2 || alpha < -2 || m == 0) return 0.0;
  // Below m = 10 SP 1065 Table 8 overstates the EDF (at m = 1 it exceeds
  // N): MDEV's Greenhall-Riley EDF, as Stable32 takes there (below the
  // spread of MTOT on seeded white and random-walk FM: a lower bound).
  if (m < kMtotTableFrom) return edf_greenhall(alpha, 2, m, n_phase, true, true);
  return std::max(0.0, edf_mtotvar_table(alpha, static_cast<double>(m), static_cast<double>(n_phase)));
}

double edf_mtotvar_table(int alpha, double m, double n_phase) {
  if (alpha > 2 || alpha < -2 || !(m > 0.0)) return 0.0;
  // SP 1065 Table 8: edf = b (N/m) - c.
  struct Bc {
    double b, c;
  };
  constexpr Bc kTable8[5] = {{1.90, 2.1}, {1.20, 1.40}, {1.10, 1.2}, {0.85, 0.50}, {0.75, 0.31}};
  const Bc bc = kTable8[2 - alpha];
  return bc.b * n_phase / m - bc.c;
}

double edf_htotvar(int alpha, std::size_t m, std::size_t n_phase) {
  if (m == 0 || n_phase <= m) return 0.0;
  const double N = static_cast<double>(n_phase);
  const double md = static_cast<double>(m);
  if (m >= kHtotTableFrom && alpha <= 0 && alpha >= -4) {
    // Howe, Beard, Greenhall, Vernotte & Riley, "A total estimator of the
    // Hadamard function used for GPS operations", Proc. 32nd PTTI 2000,
    // Table 1 (white FM to random-run FM): edf = (T/tau) / (b0 + b1 tau/T),
    // T/tau = N/m. The rows as transcribed in AllanToolkit's tables.yml
    // (alpha 0 .. -2, which it labels 2 .. -2) and SigmaTau's edf.jl
    // (alpha 0 .. -4); Stable32's HTOT intervals of white FM follow the
    // alpha 0 row (tests/test_stable32_more.cpp).
    struct B01 {
      double b0, b1;
    };
    constexpr B01 kTable[5] = {{0.559, 1.004}, {0.868, 1.140}, {0.938, 1.696}, {0.974, 2.554}, {1.276, 3.149}};
    const B01 b = kTable[-alpha];
    return (N / md) / (b.b0 + b.b1 * md / N);
  }
  // Flicker PM from m = 16: Stable32's rule, as TOTDEV's.
  if (m >= kHtotTableFrom && alpha == 1) return edf_flicker_pm_total(m, n_phase);
  // Below m = 16 (and for white PM, which the table does not cover):
  // SP 1065 Table 5, as Stable32; beyond its types the overlapping
  // Hadamard EDF.
  if (alpha <= 2 && alpha >= -2) return edf_simple(alpha, m, n_phase);
  return edf_greenhall(alpha, 3, m, n_phase, true, false);
}

double edf_theo1(int alpha, std::size_t m, std::size_t n_phase) {
  // NIST SP 1065 (Riley 2008) sec. 5.2.15, the fits of Howe & Peppler
  // (Proc. 2003 Joint FCS/EFTF) and Howe & Tasset (EFTF 2004), with
  // r = 0.75 m and N phase points; the same forms as AllanToolkit's
  // calc_edf_theo1 and W. J. Riley's TheoBR.cpp (whose white- and
  // flicker-PM lines divide by the last factor: multiplied, as here, they
  // follow the simulated spread). The random-walk form falls to 0 (no
  // interval) near r = 0.6 N.
  if (m == 0 || n_phase <= m) return 0.0;
  const double N = static_cast<double>(n_phase);
  const double r = 0.75 * static_cast<double>(m);
  double edf = 0.0;
  switch (alpha) {
    case 2:  // white PM
      edf = 0.86 * (N + 1.0) * (N - 4.0 * r / 3.0) / (N - r) * (r / (r + 1.14));
      break;
    case 1:  // flicker PM
      edf = (4.798 * N * N - 6.374 * N * r + 12.387 * r) / (std::sqrt(r + 36.6) * (N - r)) * (r / (r + 0.3));
      break;
    case 0: {  // white FM
      const double r15 = r * std::sqrt(r);
      edf = ((4.1 * N + 0.8) / r - (3.1 * N + 6.5) / N) * (r15 / (r15 + 5.2));
      break;
    }
    case -1: {  // flicker FM
      const double r3 = r * r * r;
      edf = (2.0 * N * N - 1.3 * N * r - 3.5 * r) / (N * r) * (r3 / (r3 + 2.3));
      break;
    }
    case -2: {  // random-walk FM
      const double a = 4.4 * N - 1.0;
      const double b = 4.4 * N - 3.0;
      edf = (4.4 * N - 2.0) / (2.9 * r) * ((a * a - 8.6 * r * a + 11.4 * r * r) / (b * b));
      break;
    }
    default: return 0.0;
  }
  return std::max(0.0, edf);
}

double edf_for(Stat stat, int alpha, std::size_t m, std::size_t n_phase, EdfMethod method) {
  switch (stat) {
    case Stat::tierms:
    case Stat::mtie: return 0.0;
    case Stat::mtotdev:
    case Stat::ttotdev: return edf_mtotvar(alpha, m, n_phase);
    case Stat::htotdev: return edf_htotvar(alpha, m, n_phase);
    case Stat::theo1:
    case Stat::theobr: return edf_theo1(alpha, m, n_phase);
    case Stat::theoh: {  // its part's: OADEV's or TheoBR's
      const auto part = theoh_stat_at(stat, m, n_phase);
      return part ? edf_for(*part, alpha, m, n_phase, method) : 0.0;
    }
    default: break;
  }
  if (method == EdfMethod::simple) {
    if (stat == Stat::totdev) return edf_totvar(alpha, m, n_phase);
    return edf_simple(alpha, m, n_phase);
  }
  switch (stat) {
    case Stat::adev: return edf_greenhall(alpha, 2, m, n_phase, false, false);
    case Stat::oadev: return edf_greenhall(alpha, 2, m, n_phase, true, false);
    case Stat::mdev:
    case Stat::tdev: return edf_greenhall(alpha, 2, m, n_phase, true, true);
    case Stat::hdev: return edf_greenhall(alpha, 3, m, n_phase, false, false);
    case Stat::ohdev: return edf_greenhall(alpha, 3, m, n_phase, true, false);
    case Stat::totdev: return edf_totvar(alpha, m, n_phase);
    default: return 0.0;
  }
}

double edf_for_stride(Stat stat, int alpha, std::size_t m, std::size_t n_phase, std::size_t stride, EdfMethod method) {
  if (method == EdfMethod::simple) return edf_for(stat, alpha, m, n_phase, method);
  switch (stat) {
    case Stat::adev: return edf_greenhall_stride(alpha, 2, m, n_phase, m, false);
    case Stat::oadev: return edf_greenhall_stride(alpha, 2, m, n_phase, stride, false);
    case Stat::hdev: return edf_greenhall_stride(alpha, 3, m, n_phase, m, false);
    case Stat::ohdev: return edf_greenhall_stride(alpha, 3, m, n_phase, stride, false);
    default: return edf_for(stat, alpha, m, n_phase, method);
  }
}

}  // namespace cubecal
