// Magnetometer calibration: checks shared by every method, and the mapping of
// TWOSTEP and of the ellipsoid fit to one result h_cal = A^-1 (h - b).
#include "cubecal/calib/mag_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "cubecal/calib/ellipsoid_fit.hpp"
#include "cubecal/calib/twostep.hpp"
#include "cubecal/error.hpp"
#include "../detail/eigen_matrix.hpp"
#include "detail/eigen_vec3.hpp"

namespace cubecal::mag {

namespace {

using M3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;
using calib::detail::to_array;
using calib::detail::to_eigen;

std::string fmt_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

constexpr int kSymI[6] = {0, 1, 2, 0, 0, 1};
constexpr int kSymJ[6] = {0, 1, 2, 1, 2, 2};
const char* const kSoftNames[6] = {"W11", "W22", "W33", "W12", "W13", "W23"};

// |v| without overflow or underflow: a value of 1e200 is a finite |h| too.
double norm3(const Vec3& v) {
  const double ss = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (std::isfinite(ss) && ss >= std::numeric_limits<double>::min()) return std::sqrt(ss);
  const double m = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(m > 0.0) || !std::isfinite(m)) return m;
  const double x = v[0] / m, y = v[1] / m, z = v[2] / m;
  return m * std::sqrt(x * x + y * y + z * z);
}

double field_at(std::span<const double> F, std::size_t k) { return F.size() == 1 ? F[0] : F[k]; }

std::string points_text(std::size_t n) { return std::to_string(n) + (n == 1 ? " point" : " points"); }

[[noreturn]] void no_coverage(const std::string& why) {
  throw CalibrationError(CalibrationReason::poor_coverage,
                         "points do not cover the sphere: rotate the sensor through all orientations (" + why + ")");
}

}  // namespace

std::string_view to_string(Method m) noexcept {
  switch (m) {
    case Method::twostep: return "twostep";
    case Method::twostep_full: return "twostep-full";
    case Method::ellipsoid: return "ellipsoid";
  }
  return "ellipsoid";
}

std::optional<Method> parse_method(std::string_view s) noexcept {
  if (s == "twostep") return Method::twostep;
  if (s == "twostep-full") return Method::twostep_full;
  if (s == "ellipsoid") return Method::ellipsoid;
  return std::nullopt;
}

Vec3 apply(const Vec3& h, const Vec3& bias, const Mat3& correction) {
  Vec3 r{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) r[i] += correction[i][j] * (h[j] - bias[j]);
  return r;
}

namespace {
template <class Residual>
NormError norm_stats(std::size_t n, Residual res) {
  NormError e;
  if (n == 0) return e;
  double s = 0.0, ss = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double r = res(k);
    s += r;
    ss += r * r;
    e.max = std::max(e.max, std::abs(r));
  }
  e.mean = s / static_cast<double>(n);
  e.rms = std::sqrt(ss / static_cast<double>(n));
  return e;
}
}  // namespace

NormError norm_error(std::span<const Vec3> h, const Vec3& bias, const Mat3& correction, std::span<const double> F) {
  return norm_stats(h.size(), [&](std::size_t k) { return norm3(apply(h[k], bias, correction)) - field_at(F, k); });
}

NormError raw_norm_error(std::span<const Vec3> h, std::span<const double> F) {
  return norm_stats(h.size(), [&](std::size_t k) { return norm3(h[k]) - field_at(F, k); });
}

namespace {

// The median of v (v is reordered).
double median_of(std::vector<double>& v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  const double hi = v[mid];
  if (v.size() % 2 == 1) return hi;
  const double lo = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
  return lo + 0.5 * (hi - lo);
}

// The robust first pass: the median |h| and the robust sigma, 1.4826 MAD
// floored at kGrossSigmaFloor x median (exact or quantized norms leave MAD 0);
// the points further than kGrossSigmas robust sigmas from the median go to
// r.gross, the others to `kept`.
void gross_pass(const std::vector<double>& norms, OutlierRejection& r, std::vector<std::size_t>& kept) {
  std::vector<double> v = norms;
  r.median_norm = median_of(v);
  for (double& x : v) x = std::abs(x - r.median_norm);
  r.robust_sigma = std::max(1.4826 * median_of(v), kGrossSigmaFloor * r.median_norm);
  for (std::size_t k = 0; k < norms.size(); ++k) {
    const bool gross = std::abs(norms[k] - r.median_norm) > kGrossSigmas * r.robust_sigma;
    (gross ? r.gross : kept).push_back(k);
  }
}

}  // namespace

OutlierRejection reject_outliers(std::span<const Vec3> h, double sigma_level) {
  if (!(sigma_level > 0.0) || !std::isfinite(sigma_level))
    throw CalibrationError(CalibrationReason::bad_option,
                           "the outlier rejection level must be a positive number of standard deviations");
  OutlierRejection r;
  const std::size_t n = h.size();
  if (n < 2) {
    for (std::size_t k = 0; k < n; ++k) r.kept.push_back(k);
    return r;
  }
  std::vector<double> norms(n);
  for (std::size_t k = 0; k < n; ++k) norms[k] = norm3(h[k]);
  std::vector<std::size_t> pass;
  gross_pass(norms, r, pass);
  // Magneto's rule on the points the first pass kept.
  double s = 0.0;
  for (std::size_t k : pass) s += norms[k];
  r.mean_norm = s / static_cast<double>(pass.size());
  double ss = 0.0;
  for (std::size_t k : pass) ss += (norms[k] - r.mean_norm) * (norms[k] - r.mean_norm);
  r.std_norm = std::sqrt(ss / static_cast<double>(pass.size()));  // Magneto prints the population value
  for (std::size_t k : pass) {
    const bool out = r.std_norm > 0.0 && std::abs(norms[k] - r.mean_norm) / r.std_norm > sigma_level;
    (out ? r.rejected : r.kept).push_back(k);
  }
  if (!r.gross.empty()) {
    r.rejected.insert(r.rejected.end(), r.gross.begin(), r.gross.end());
    std::sort(r.rejected.begin(), r.rejected.end());
  }
  return r;
}

Coverage sphere_coverage(std::span<const Vec3> h) {
  Coverage c;
  const std::size_t n = h.size();
  if (n == 0) return c;
  V3 m = V3::Zero();
  for (const Vec3& p : h) m += to_eigen(p);
  m /= static_cast<double>(n);
  M3 cov = M3::Zero();
  for (const Vec3& p : h) cov += (to_eigen(p) - m) * (to_eigen(p) - m).transpose();
  cov /= static_cast<double>(n);
  const Eigen::SelfAdjointEigenSolver<M3> ec(cov);
  for (int i = 0; i < 3; ++i) c.spread[static_cast<std::size_t>(i)] = std::sqrt(std::max(ec.eigenvalues()(2 - i), 0.0));
  const double sc = std::sqrt(cov.trace());

  // Algebraic sphere fit |x|^2 = 2 c.x + k in normalised coordinates.
  V3 centre = m;
  if (sc > 0.0) {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    Eigen::Vector4d y = Eigen::Vector4d::Zero();
    for (const Vec3& p : h) {
      const V3 x = (to_eigen(p) - m) / sc;
      const Eigen::Vector4d row(2.0 * x(0), 2.0 * x(1), 2.0 * x(2), 1.0);
      A.noalias() += row * row.transpose();
      y += row * x.squaredNorm();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> ea(A, Eigen::EigenvaluesOnly);
    const Eigen::LDLT<Eigen::Matrix4d> l(A);
    if (ea.eigenvalues()(0) > 1e-10 * ea.eigenvalues()(3)) {
      const Eigen::Vector4d sol = l.solve(y);
      if (sol.allFinite()) {
        centre = m + sc * sol.head<3>();
        c.centre_from_sphere_fit = true;
      }
    }
  }
  c.centre = {centre(0), centre(1), centre(2)};

  V3 mean_u = V3::Zero();
  M3 S = M3::Zero();
  std::size_t used = 0;
  bool oct[8] = {};
  for (const Vec3& p : h) {
    const V3 d = to_eigen(p) - centre;
    const double len = d.norm();
    if (!(len > 0.0)) continue;
    const V3 u = d / len;
    mean_u += u;
    S += u * u.transpose();
    ++used;
    oct[(u(0) >= 0 ? 1 : 0) + (u(1) >= 0 ? 2 : 0) + (u(2) >= 0 ? 4 : 0)] = true;
  }
  if (used == 0) return c;
  mean_u /= static_cast<double>(used);
  S /= static_cast<double>(used);
  c.resultant = mean_u.norm();
  c.lambda_min = std::max(Eigen::SelfAdjointEigenSolver<M3>(S).eigenvalues()(0), 0.0);
  c.octants = static_cast<std::size_t>(std::count(std::begin(oct), std::end(oct), true));
  return c;
}

void check_coverage(const Coverage& c, Method m, double F) {
  if (m == Method::twostep) {
    if (!(c.spread[2] >= kMinSpreadBiasOnly * F))
      no_coverage("the points hardly leave one plane: smallest spread " + fmt_g(c.spread[2]) + " < " +
                  fmt_g(kMinSpreadBiasOnly) + " x field norm " + fmt_g(F));
    return;
  }
  if (!c.centre_from_sphere_fit) no_coverage("the points are coplanar");
  if (!(c.spread[2] >= kMinSpreadFull * F))
    no_coverage("the points cover too small a part of the field sphere: smallest spread " + fmt_g(c.spread[2]) + " < " +
                fmt_g(kMinSpreadFull) + " x field norm " + fmt_g(F));
  if (!(c.lambda_min >= kMinLambdaFull))
    no_coverage("the directions stay near one great circle: smallest eigenvalue of their scatter " +
                fmt_g(c.lambda_min) + " < " + fmt_g(kMinLambdaFull) + ", 1/3 for the whole sphere");
  if (!(c.resultant <= kMaxResultantFull))
    no_coverage("the directions cover less than a hemisphere: mean resultant " + fmt_g(c.resultant) + " > " +
                fmt_g(kMaxResultantFull) + ", 0 for the whole sphere");
}

namespace {

// The points, the norms and the options, as the header's CalibrationErrors
// say; true when the field norm is given per point.
bool check_input(std::span<const Vec3> h_in, const Options& opt) {
  const std::size_t n_in = h_in.size();
  if (n_in < kMinPoints)
    throw CalibrationError(CalibrationReason::too_few_points, "magnetometer calibration needs at least " +
                                                                  std::to_string(kMinPoints) + " points, got " +
                                                                  std::to_string(n_in));
  for (const Vec3& p : h_in)
    for (double v : p)
      if (!std::isfinite(v)) throw CalibrationError(CalibrationReason::bad_data, "non-finite magnetometer value");
  if (opt.field_norm < 0.0 || !std::isfinite(opt.field_norm))
    throw CalibrationError(CalibrationReason::field_norm, "the field norm must be positive");
  if (opt.noise < 0.0 || !std::isfinite(opt.noise))
    throw CalibrationError(CalibrationReason::bad_option, "the noise must be a positive standard deviation");
  if (opt.reject_sigma < 0.0 || !std::isfinite(opt.reject_sigma))
    throw CalibrationError(CalibrationReason::bad_option,
                           "the outlier rejection level must be a positive number of standard deviations");
  const bool per_point = !opt.field_norms.empty();
  if (per_point) {
    if (opt.method == Method::ellipsoid)
      throw CalibrationError(CalibrationReason::bad_option,
                             "per-point field norms apply to TWOSTEP only (the ellipsoid fit takes one norm)");
    if (opt.field_norms.size() != n_in)
      throw CalibrationError(CalibrationReason::field_norm, "one field norm per point: expected " +
                                                                std::to_string(n_in) + ", got " +
                                                                std::to_string(opt.field_norms.size()));
    for (double f : opt.field_norms)
      if (!(f > 0.0) || !std::isfinite(f))
        throw CalibrationError(CalibrationReason::field_norm, "the field norm must be positive");
  }
  return per_point;
}

// Magneto's outlier rule (one pass) on the points, and on their per-point
// norms alongside; what was rejected goes into r.
void select_points(std::span<const Vec3> h_in, const Options& opt, bool per_point, Result& r, std::vector<Vec3>& h,
                   std::vector<double>& Hk) {
  if (opt.reject_sigma > 0.0) {
    const OutlierRejection rej = reject_outliers(h_in, opt.reject_sigma);
    r.rejected = rej.rejected;
    for (std::size_t k : rej.kept) {
      h.push_back(h_in[k]);
      if (per_point) Hk.push_back(opt.field_norms[k]);
    }
    r.rejected_gross = rej.gross;
    if (!rej.gross.empty()) {
      double largest = 0.0;
      for (std::size_t k : rej.gross) largest = std::max(largest, norm3(h_in[k]));
      r.notes.push_back(points_text(rej.gross.size()) +
                        (rej.gross.size() == 1 ? " rejected as a gross outlier" : " rejected as gross outliers") +
                        ": ||h| - " + fmt_g(rej.median_norm) + "| > " + fmt_g(kGrossSigmas) + " x " +
                        fmt_g(rej.robust_sigma) + " (median |h| and robust sigma 1.4826 MAD), largest |h| " +
                        fmt_g(largest) + "; Magneto's rule then applies to the others");
    }
    const std::size_t magneto = rej.rejected.size() - rej.gross.size();
    if (magneto > 0)
      r.notes.push_back(points_text(magneto) + " rejected: ||h| - " + fmt_g(rej.mean_norm) + "| > " +
                        fmt_g(opt.reject_sigma) + " x " + fmt_g(rej.std_norm) + " (Magneto's rule)");
  } else {
    h.assign(h_in.begin(), h_in.end());
    if (per_point) Hk = opt.field_norms;
  }
  r.points_used = h.size();
  r.points_rejected = r.rejected.size();
  if (h.size() < kMinPoints)
    throw CalibrationError(CalibrationReason::too_few_points,
                           "only " + std::to_string(h.size()) + " points left after outlier rejection, " +
                               std::to_string(kMinPoints) + " needed (raise the rejection level)");
}

// F: the mean of the per-point norms, the norm given, or Magneto's default
// (the mean raw |h|, over the points kept by the outlier rule); Hk then
// holds the one norm.
void set_field_norm(const std::vector<Vec3>& h, const Options& opt, bool per_point, bool rejecting, Result& r,
                    std::vector<double>& Hk) {
  if (per_point) {
    double s = 0.0;
    for (double f : Hk) s += f;
    r.field_norm = s / static_cast<double>(Hk.size());
    r.field_norm_per_point = true;
  } else if (opt.field_norm > 0.0) {
    r.field_norm = opt.field_norm;
  } else {
    double s = 0.0;
    for (const Vec3& p : h) s += norm3(p);
    r.field_norm = s / static_cast<double>(h.size());
    r.field_norm_default = true;
    r.notes.push_back("field norm F = " + fmt_g(r.field_norm) + ", the mean raw |h| of " +
                      (rejecting ? "the points kept" : "all points") +
                      " (Magneto's default); give the local field norm for an absolute scale" +
                      (opt.method == Method::twostep ? std::string(" (bias-only TWOSTEP takes |h - b| = F: the bias "
                                                                   "depends on it)")
                                                     : std::string()));
    if (!(r.field_norm > 0.0))
      throw CalibrationError(CalibrationReason::field_norm, "the field norm must be positive (all points are zero)");
  }
  if (!per_point) Hk.assign(1, r.field_norm);
}

// The ellipsoid fit's b and W = A^-1, with their covariance from the
// geometric residuals.
void fit_with_ellipsoid(const std::vector<Vec3>& h, const Options& opt, Result& r) {
  const std::size_t n = h.size();
  const EllipsoidFit f = fit_ellipsoid(h, r.field_norm);
  r.bias = f.centre;
  r.soft_iron = f.correction;
  // Covariance of (b, W = A^-1) from the geometric residuals
  // r_k = |W (h_k - b)| - F linearised at the fit, sigma_k = s |W u_k|.
  const M3 W = to_eigen(r.soft_iron);
  const V3 b = to_eigen(r.bias);
  Eigen::Matrix<double, 9, 9> JtJ = Eigen::Matrix<double, 9, 9>::Zero();
  std::vector<double> res(n), g2(n);
  std::vector<Eigen::Matrix<double, 9, 1>> rows(n);
  for (std::size_t k = 0; k < n; ++k) {
    const V3 x = to_eigen(h[k]) - b;
    const V3 y = W * x;
    const double len = y.norm();
    const V3 u = len > 0.0 ? V3(y / len) : V3::UnitX();
    res[k] = len - r.field_norm;
    g2[k] = (W * u).squaredNorm();
    Eigen::Matrix<double, 9, 1> row;
    row.head<3>() = -(W * u);
    for (int e = 0; e < 6; ++e) {
      const int i = kSymI[e], j = kSymJ[e];
      row(3 + e) = i == j ? u(i) * x(i) : u(i) * x(j) + u(j) * x(i);
    }
    rows[k] = row;
  }
  r.dof = n - 9;
  double s2 = opt.noise * opt.noise;
  if (opt.noise == 0.0) {
    double acc = 0.0;
    for (std::size_t k = 0; k < n; ++k) acc += res[k] * res[k] / g2[k];
    s2 = std::max(acc / static_cast<double>(r.dof), 1e-300);
  }
  r.chi2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double v = s2 * g2[k];
    r.chi2 += res[k] * res[k] / v;
    JtJ.noalias() += rows[k] * rows[k].transpose() / v;
  }
  r.noise = std::sqrt(s2);
  const Eigen::LDLT<Eigen::Matrix<double, 9, 9>> l(JtJ);
  Eigen::Matrix<double, 9, 9> C = l.solve(Eigen::Matrix<double, 9, 9>::Identity());
  C = 0.5 * (C + C.transpose());
  r.covariance = cubecal::detail::to_matrix(C);
  if (f.axis_ratio > 2.0)
    r.notes.push_back("axis ratio " + fmt_g(f.axis_ratio) +
                      " > 2: beyond the range the k = 4 constraint is meant for; check the data");
}

// TWOSTEP (bias only, or the full form) mapped to the result.
void fit_with_twostep(const std::vector<Vec3>& h, const std::vector<double>& Hk, const Options& opt, Result& r) {
  TwostepOptions to;
  to.full = opt.method == Method::twostep_full;
  to.noise = opt.noise;
  to.mean_correction = opt.mean_correction;
  to.eta_tol = opt.eta_tol;
  to.max_iterations = opt.max_iterations;
  const TwostepResult t = twostep(h, Hk, to);
  r.bias = t.offset;
  if (to.full) {
    for (std::size_t i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < 3; ++j) r.soft_iron[i][j] = (i == j ? 1.0 : 0.0) + t.D[i][j];
  }
  r.covariance = t.offset_cov;
  r.chi2 = t.chi2;
  r.dof = t.dof;
  r.noise = t.noise;
  r.iterations = t.iterations;
  r.converged = t.converged;
  r.eta = t.eta;
  if (to.full && t.centred_degenerate)
    r.notes.push_back(
        "TWOSTEP step 1 is degenerate (one field norm for all points): the common gain comes from "
        "step 2 alone");
  if (!t.converged)
    r.notes.push_back("TWOSTEP stopped after " + std::to_string(t.iterations) +
                      " iterations with eta = " + fmt_g(t.eta) + " (not below " + fmt_g(opt.eta_tol) + ")");
}

// The noise used (estimated or given) and, for a given noise, the chi2 test.
void judge_noise(const Options& opt, Result& r) {
  r.noise_estimated = opt.noise == 0.0;
  if (r.noise_estimated)
    r.notes.push_back("noise s = " + fmt_g(r.noise) +
                      " per axis estimated from the residuals (chi2 = dof by construction); give it for a "
                      "consistency test");
  else if (r.dof > 0) {
    const boost::math::chi_squared_distribution<double> chi(static_cast<double>(r.dof));
    r.p_value = boost::math::cdf(boost::math::complement(chi, std::max(r.chi2, 0.0)));
  }
}

// Covariance names, the sigmas of b and W, the semi-axes and axis ratio.
void describe_parameters(Result& r) {
  r.covariance_names = {"b1", "b2", "b3"};
  if (r.covariance.rows() == 9)
    for (const char* nm : kSoftNames) r.covariance_names.emplace_back(nm);
  for (std::size_t i = 0; i < 3; ++i) r.bias_sigma[i] = std::sqrt(std::max(r.covariance(i, i), 0.0));
  if (r.covariance.rows() == 9)
    for (int e = 0; e < 6; ++e) {
      const double sd =
          std::sqrt(std::max(r.covariance(static_cast<std::size_t>(3 + e), static_cast<std::size_t>(3 + e)), 0.0));
      r.soft_iron_sigma[static_cast<std::size_t>(kSymI[e])][static_cast<std::size_t>(kSymJ[e])] = sd;
      r.soft_iron_sigma[static_cast<std::size_t>(kSymJ[e])][static_cast<std::size_t>(kSymI[e])] = sd;
    }
  const Eigen::SelfAdjointEigenSolver<M3> ew(to_eigen(r.soft_iron));
  const V3 wl = ew.eigenvalues();  // ascending: semi-axes F / w descending
  for (int i = 0; i < 3; ++i) r.semi_axes[static_cast<std::size_t>(i)] = r.field_norm / wl(i);
  r.axis_ratio = wl(2) / wl(0);
}

}  // namespace

Result calibrate(std::span<const Vec3> h_in, const Options& opt) {
  const bool per_point = check_input(h_in, opt);

  Result r;
  r.method = opt.method;
  r.reject_sigma = opt.reject_sigma;

  std::vector<Vec3> h;
  std::vector<double> Hk;
  select_points(h_in, opt, per_point, r, h, Hk);
  set_field_norm(h, opt, per_point, opt.reject_sigma > 0.0, r, Hk);

  r.coverage = sphere_coverage(h);
  if (opt.check_coverage) check_coverage(r.coverage, opt.method, r.field_norm);
  if (opt.method == Method::twostep &&
      (r.coverage.lambda_min < kMinLambdaFull || r.coverage.resultant > kMaxResultantFull))
    r.notes.push_back(
        "partial sphere coverage: the bias is less certain along the poorly covered direction (see "
        "bias_sigma)");

  if (opt.method == Method::ellipsoid)
    fit_with_ellipsoid(h, opt, r);
  else
    fit_with_twostep(h, Hk, opt, r);
  judge_noise(opt, r);
  describe_parameters(r);

  r.before = raw_norm_error(h, Hk);
  r.after = norm_error(h, r.bias, r.soft_iron, Hk);
  if (r.after.rms > 0.05 * r.field_norm)
    r.notes.push_back("the points fit the model poorly: rms | |h_cal| - F | is " +
                      fmt_g(100.0 * r.after.rms / r.field_norm) +
                      " % of F (outliers: try the rejection level; a field that changed during the run?)");
  return r;
}

}  // namespace cubecal::mag
