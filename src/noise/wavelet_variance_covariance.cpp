// The covariance of the empirical Haar wavelet variance of a composite model
// (noise/wavelet_variance_covariance.hpp; docs/formulas/noise-terms.md §8d).
//
// The coefficient at scale tau = 2m is a second difference of the phase
// S(t) = sum_{i<t} x_i: W_a = (S(a+2m) - 2 S(a+m) + S(a)) / (2m). Every
// process has a generalized covariance K of its phase (defined up to an
// even polynomial of degree <= 2, which second differences annihilate):
//   WN  -sigma2 |u| / 2           QN  Q2 [u = 0]
//   RW  gamma2 (|u|^3 - |u|) / 12  GM  -D(u) / 2, D(u) = var(x_1 + .. + x_u)
//   MA1 that of WN sigma2 (1 + theta)^2 plus QN -theta sigma2 (the same
//       autocovariance; the coefficients are Gaussian, so the same covariance)
// so c_jk(h) = sum_{p,q} w_p w_q K(h + q m_k - p m_j) / (4 m_j m_k) with
// w = (1, -2, 1). The inner difference (step m_j) is taken in closed form,
// K1_j(v) = sum_p w_p K(v - p m_j), so that the outer one (step m_k >> m_j)
// loses no digits; c_jk is then smooth between the nine lags
// h = p m_j - q m_k where some argument crosses a kink of K.
#include "detail/wavelet_variance_covariance.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <map>
#include <string>
#include <utility>

#include "cubecal/error.hpp"

namespace cubecal {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// e^-x - 1 + x (x >= 0), without the cancellation near 0.
double g2(double x) {
  if (x < 0.1) {
    double term = 0.5 * x * x, sum = 0.0;
    for (int k = 2; k < 14; ++k) {
      sum += term;
      term *= -x / (k + 1);
    }
    return sum;
  }
  return std::expm1(-x) + x;
}

// e^-x - 1 + x - x^2 / 2 given e = e^-x (0 <= x <= 2 where it is used):
// a series below 0.1, else to an absolute error of ~1e-16 (relative 1e-12).
double g3(double x, double e) {
  if (x < 0.1) {
    double term = -x * x * x / 6.0, sum = 0.0;
    for (int k = 3; k < 12; ++k) {
      sum += term;
      term *= -x / (k + 1);
    }
    return sum;
  }
  return (e - 1.0 + x) - 0.5 * x * x;
}

// sinh a - a.
double sinh_minus(double a) {
  if (a < 0.5) {
    double term = a * a * a / 6.0, sum = 0.0;
    for (int k = 3; k < 30; k += 2) {
      sum += term;
      term *= a * a / ((k + 1) * (k + 2));
    }
    return sum;
  }
  return std::sinh(a) - a;
}

// 1 - (1 + y) e^-y.
double h1(double y) {
  if (y < 0.5) {
    double pw = y * y / 2.0, sum = 0.0;  // y^k / k!
    for (int k = 2; k < 24; ++k) {
      sum += ((k % 2 == 0) ? 1.0 : -1.0) * (k - 1) * pw;
      pw *= y / (k + 1);
    }
    return sum;
  }
  return 1.0 - (1.0 + y) * std::exp(-y);
}

// sum_{d=1}^{D} e^{-b d} and sum_{d=1}^{D} d e^{-b d} (b > 0, D >= 1),
// stable for b D small as well as large.
double geometric0(double b, double D) { return std::exp(-b) * std::expm1(-b * D) / std::expm1(-b); }
double geometric1(double b, double D) {
  const double q = -std::expm1(-b);
  const double y = b * D;
  return std::exp(-b) * (h1(y) + y * std::exp(-y) * g2(b) / b) / (q * q);
}

struct GmTerm {
  double a = 0.0;    // -ln phi
  double cg = 0.0;   // gamma0 / (4 sinh^2(a / 2)), gamma0 = sigma2 / (1 - phi^2)
  double sam = 0.0;  // sinh a - a
};

// The model's random part, per kind (a model may repeat a kind; its values add).
struct Terms {
  double wn = 0.0, qn = 0.0, rw = 0.0, omega = 0.0;
  std::vector<GmTerm> gm;
};

[[noreturn]] void bad_parameter(const CompositeModel& model) {
  throw UsageError(Field::model, "model " + model_name(model) +
                                     ": every variance must be finite and >= 0, every drift finite, every "
                                     "Gauss-Markov phi in (0, 1) and every MA1 theta in (-1, 1)");
}

Terms terms_of(const CompositeModel& model) {
  Terms t;
  for (const Process& p : model.processes) {
    if (!std::isfinite(p.value) || (p.kind != ProcessKind::dr && p.value < 0.0)) bad_parameter(model);
    switch (p.kind) {
      case ProcessKind::wn: t.wn += p.value; break;
      case ProcessKind::qn: t.qn += p.value; break;
      case ProcessKind::rw: t.rw += p.value; break;
      case ProcessKind::dr: t.omega += p.value; break;
      case ProcessKind::gm: {
        if (!(p.phi > 0.0 && p.phi < 1.0)) bad_parameter(model);
        const double a = -std::log(p.phi);
        // Below this the term is a random walk to every digit (a tau ~ 1e-14
        // at a million samples), and its constants would overflow.
        if (a < 1e-20) {
          t.rw += p.value;
          break;
        }
        if (p.value == 0.0) break;
        const double gamma0 = p.value / -std::expm1(-2.0 * a);
        const double sh = std::sinh(0.5 * a);
        t.gm.push_back({a, gamma0 / (4.0 * sh * sh), sinh_minus(a)});
        break;
      }
      case ProcessKind::ma1:
        if (!(std::abs(p.theta) < 1.0)) bad_parameter(model);
        t.wn += p.value * (1.0 + p.theta) * (1.0 + p.theta);
        t.qn -= p.value * p.theta;
        break;
      case ProcessKind::sin:
        // A line is deterministic but for its phase: over a record of many
        // periods its own wavelet variance is estimated to within the
        // record's edge effects, and its cross term with the noise is left
        // out. The covariance is the noise's (an approximation for the
        // WIC's optimism and the sandwich; docs/formulas/noise-terms.md §8f).
        if (!(p.omega > 0.0 && p.omega < std::numbers::pi)) bad_parameter(model);
        break;
    }
  }
  return t;
}

// c_jk(h) for m_j <= m_k.
class PairKernel {
 public:
  PairKernel(const Terms& t, double mj, double mk) : t_(t), mj_(mj), mk_(mk) {
    for (const GmTerm& g : t.gm) {
      const double am = g.a * mj;
      const double e1 = std::expm1(-am);
      Gm s;
      s.e2 = e1 * e1;
      s.small = am <= 1.0;
      s.f = std::exp(-am);
      s.d2 = g2(am) * (am - e1);  // a^2 m^2 - E2
      gm_.push_back(s);
    }
  }

  // sum_p w_p K(v - p m_j), the Gauss-Markov terms less the constant
  // -cg E2 (annihilated by the outer difference).
  double k1(double v) const {
    const double m = mj_;
    const double t = std::abs(v - m);
    const double r = std::max(m - t, 0.0);
    double sum = -t_.wn * r + t_.rw / 12.0 * (6.0 * m * m * t + 2.0 * r * r * r - 2.0 * r);
    if (t_.qn != 0.0) sum += t_.qn * (v == 0.0 || v == 2.0 * m ? 1.0 : v == m ? -2.0 : 0.0);
    for (std::size_t i = 0; i < gm_.size(); ++i) {
      const GmTerm& g = t_.gm[i];
      const Gm& s = gm_[i];
      if (t >= m) {
        const double d = g.a * (t - m);
        sum -= g.cg * s.e2 * (d > 40.0 ? -1.0 : std::expm1(-d));
        continue;
      }
      // The three distances m - t, t, m + t from the kinks.
      const double lo = g.a * (m - t), mid = g.a * t, hi = g.a * (m + t);
      double bracket = 0.0;
      if (s.small) {
        // The even part a^2 u^2 / 2 of g2 sums to a^2 m^2 over the three
        // distances; while a m <= 1 it is taken out against E2 exactly.
        // e^{-a(m -+ t)} = e^{-a m} e^{+-a t}: one exponential.
        const double e = hi < 0.1 ? 1.0 : std::exp(-mid);
        bracket = g3(lo, s.f / e) - 2.0 * g3(mid, e) + g3(hi, s.f * e) + s.d2;
      } else {
        // Terms of order a m >= 1: absolute rounding suffices.
        const auto ex = [](double x) { return x > 40.0 ? 0.0 : std::exp(-x); };
        const double e = ex(mid);
        bracket = (ex(lo) - 1.0 + lo) - 2.0 * (e - 1.0 + mid) + (s.f * e - 1.0 + hi) - s.e2;
      }
      sum -= g.cg * (2.0 * r * g.sam + bracket);
    }
    return sum;
  }

  double c(double h) const { return (k1(h) - 2.0 * k1(h + mk_) + k1(h + 2.0 * mk_)) / (4.0 * mj_ * mk_); }

 private:
  struct Gm {
    double e2 = 0.0, d2 = 0.0, f = 0.0;  // expm1(-a m)^2, a^2 m^2 - e2, e^{-a m}
    bool small = true;
  };
  const Terms& t_;
  double mj_, mk_;
  std::vector<Gm> gm_;
};

// Gauss rules for the uniform measure on the integers 0 .. P-1 (discrete
// Chebyshev polynomials, Golub-Welsch): n nodes sum every polynomial of
// degree <= 2n - 1 over the P integers exactly.
struct Rule {
  std::vector<double> x, w;
};

class RuleCache {
 public:
  const Rule& get(long long points, int n) {
    auto [it, fresh] = rules_.try_emplace({points, n});
    if (fresh) {
      const double P = static_cast<double>(points);
      Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(n, n);
      for (int k = 1; k < n; ++k) {
        const double kk = static_cast<double>(k);
        const double beta = kk * kk * (P * P - kk * kk) / (4.0 * (4.0 * kk * kk - 1.0));
        jac(k, k - 1) = jac(k - 1, k) = std::sqrt(beta);
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jac);
      Rule& r = it->second;
      for (int i = 0; i < n; ++i) {
        r.x.push_back(0.5 * (P - 1.0) + eig.eigenvalues()(i));
        const double v = eig.eigenvectors()(0, i);
        r.w.push_back(P * v * v);
      }
    }
    return it->second;
  }

 private:
  std::map<std::pair<long long, int>, Rule> rules_;
};

struct Sums {
  double s2 = 0.0;  // sum n(h) c(h)^2
  double s1 = 0.0;  // sum n(h) c(h)
};

// The double sums over the pairs of coefficients at scales m_j <= m_k, with
// M_j >= M_k coefficients: a lag h occurs n(h) times.
class LagSums {
 public:
  LagSums(const Terms& t, double mj, double mk, double Mj, double Mk, RuleCache& cache)
      : t_(t), kernel_(t, mj, mk), mj_(mj), mk_(mk), Mj_(Mj), Mk_(Mk), cache_(cache) {
    for (const GmTerm& g : t.gm) rates_.push_back(g.a);
  }

  Sums run() {
    const double hmin = -(Mj_ - 1.0), hmax = Mk_ - 1.0;
    const double lo = std::max(hmin, -2.0 * mk_), hi = std::min(hmax, 2.0 * mj_);
    // The lags where c or n has a kink, each summed alone.
    std::vector<double> at{lo, hi, 0.0, Mk_ - Mj_};
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) at.push_back(p * mj_ - q * mk_);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    at.erase(std::remove_if(at.begin(), at.end(), [&](double h) { return h < lo || h > hi; }), at.end());
    Sums s;
    for (std::size_t i = 0; i < at.size(); ++i) {
      add(s, at[i], 1.0);
      if (i + 1 < at.size() && at[i + 1] > at[i] + 1.0) piece(s, at[i] + 1.0, at[i + 1] - 1.0);
    }
    // Beyond the windows' overlap only the Gauss-Markov terms remain:
    // c = sum_g T_g e^{-a_g d}, d the distance from the last overlap.
    if (!t_.gm.empty()) {
      if (hmax > 2.0 * mj_) tail(s, Mk_ - 2.0 * mj_, hmax - 2.0 * mj_);
      if (hmin < -2.0 * mk_) tail(s, Mj_ - 2.0 * mk_, -2.0 * mk_ - hmin);
    }
    return s;
  }

 private:
  double count(double h) const { return std::min(Mk_ - 1.0, Mj_ - 1.0 + h) - std::max(0.0, h) + 1.0; }

  void add(Sums& s, double h, double weight) const {
    const double c = kernel_.c(h);
    const double nw = count(h) * weight;
    s.s2 += nw * c * c;
    s.s1 += nw * c;
  }

  // The widest panel at distance `from` (>= 1) from a kink: an exponential
  // of rate a may change by e^2 across it while a * from < 1, by its own
  // decay e^{a from} once that exceeds 1, and is ignored past e^-36.
  double width(double from) const {
    double cap = kInf;
    for (double a : rates_) {
      const double x = a * from;
      if (x > 36.0) continue;
      cap = std::min(cap, x >= 1.0 ? from : 2.0 / a);
    }
    return cap == kInf ? kInf : std::max(1.0, std::floor(cap));
  }

  // The lags lo .. hi (c smooth there): panels graded from both ends.
  void piece(Sums& s, double lo, double hi) {
    const double P = hi - lo + 1.0;
    std::vector<double> left;
    double d = 0.0;
    for (;;) {
      const double w = width(d + 1.0);
      if (w == kInf || 2.0 * (d + w) > P) break;
      left.push_back(w);
      d += w;
    }
    const double mid = P - 2.0 * d;
    const double wm = width(d + 1.0);
    double start = lo;
    for (double w : left) {
      panel(s, start, w);
      start += w;
    }
    if (mid > 0.0) {
      const double k = wm == kInf ? 1.0 : std::ceil(mid / wm);
      double done = 0.0;
      for (double i = 1.0; i <= k; i += 1.0) {
        const double upto = std::round(mid * i / k);
        panel(s, start + done, upto - done);
        done = upto;
      }
      start += mid;
    }
    for (auto it = left.rbegin(); it != left.rend(); ++it) {
      panel(s, start, *it);
      start += *it;
    }
  }

  void panel(Sums& s, double start, double points) {
    if (points <= 0.0) return;
    const int n = t_.gm.empty() ? 4 : 8;  // n c^2 is a polynomial of degree <= 7 without them
    if (points <= n) {
      for (double i = 0.0; i < points; i += 1.0) add(s, start + i, 1.0);
      return;
    }
    const Rule& r = cache_.get(static_cast<long long>(points), n);
    for (std::size_t i = 0; i < r.x.size(); ++i) add(s, start + r.x[i], r.w[i]);
  }

  // d = 1 .. D with n = n0 - d.
  void tail(Sums& s, double n0, double D) const {
    if (D < 1.0) return;
    std::vector<double> amp;
    for (const GmTerm& g : t_.gm)
      amp.push_back(-g.cg * std::pow(std::expm1(-g.a * mj_) * std::expm1(-g.a * mk_), 2) / (4.0 * mj_ * mk_));
    for (std::size_t i = 0; i < amp.size(); ++i) {
      const double a = t_.gm[i].a;
      s.s1 += amp[i] * (n0 * geometric0(a, D) - geometric1(a, D));
      for (std::size_t k = 0; k < amp.size(); ++k) {
        const double b = a + t_.gm[k].a;
        s.s2 += amp[i] * amp[k] * (n0 * geometric0(b, D) - geometric1(b, D));
      }
    }
  }

  const Terms& t_;
  PairKernel kernel_;
  double mj_, mk_, Mj_, Mk_;
  RuleCache& cache_;
  std::vector<double> rates_;
};

double half_scale(double tau) {
  if (!(tau >= 2.0) || !std::isfinite(tau) || std::fmod(tau, 2.0) != 0.0 || tau > 9.0e15)
    throw UsageError(Field::scales,
                     "a wavelet-variance scale must be an even number of samples >= 2, not " + std::to_string(tau));
  return tau / 2.0;
}

}  // namespace

double haar_coefficient_covariance(const CompositeModel& model, double tau_j, double tau_k, long long h) {
  const Terms t = terms_of(model);
  const double mj = half_scale(tau_j), mk = half_scale(tau_k);
  const auto lag = static_cast<double>(h);
  return mj <= mk ? PairKernel(t, mj, mk).c(lag) : PairKernel(t, mk, mj).c(-lag);
}

Matrix wavelet_variance_covariance(const CompositeModel& model, std::span<const double> tau, std::size_t samples) {
  const Terms t = terms_of(model);
  const std::size_t J = tau.size();
  std::vector<double> m(J);
  const auto N = static_cast<double>(samples);
  for (std::size_t j = 0; j < J; ++j) {
    m[j] = half_scale(tau[j]);
    if (tau[j] > N)
      throw UsageError(Field::scales, "the scale " + std::to_string(tau[j]) + " is longer than the record (" +
                                          std::to_string(samples) + " samples)");
  }
  Matrix cov(J, J);
  RuleCache cache;
  for (std::size_t j = 0; j < J; ++j)
    for (std::size_t k = j; k < J; ++k) {
      const double ma = std::min(m[j], m[k]), mb = std::max(m[j], m[k]);
      const double Ma = N - 2.0 * ma + 1.0, Mb = N - 2.0 * mb + 1.0;
      const Sums s = LagSums(t, ma, mb, Ma, Mb, cache).run();
      // Coefficient means under a drift: mu = omega tau / 4.
      const double mu2 = t.omega * t.omega * m[j] * m[k] / 4.0;
      cov(j, k) = cov(k, j) = (2.0 * s.s2 + 4.0 * mu2 * s.s1) / (Ma * Mb);
    }
  return cov;
}

}  // namespace cubecal
