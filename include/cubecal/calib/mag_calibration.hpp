/// @file
/// Magnetometer calibration from points measured over many orientations:
/// the common result of TWOSTEP (bias only, or bias + symmetric D) and of the
/// Li-Griffiths ellipsoid fit, and the checks every method shares (point
/// count, field norm, Magneto's outlier rule, sphere coverage).
/// docs/formulas/magnetometer.md §1-2, the shared checks §3.
///
/// Every method gives the calibration in one form,
///     h_cal = A^-1 (h - b),
/// b the hard-iron offset in the units of the input, A^-1 the symmetric
/// soft-iron correction (identity for bias-only TWOSTEP), so that |h_cal| is
/// the field norm F.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/math/matrix.hpp"
#include "cubecal/math/vec3.hpp"

namespace cubecal::mag {

/// Fewer points than this (after outlier rejection) is an error for every
/// method: the full models have 9 parameters and need redundancy to give a
/// covariance and a chi-squared.
inline constexpr std::size_t kMinPoints = 10;

/// The magnetometer calibration methods: TWOSTEP bias only, TWOSTEP with the symmetric D (9 parameters), and the
/// ellipsoid fit.
enum class Method { twostep, twostep_full, ellipsoid };

std::string_view to_string(Method m) noexcept;  ///< "twostep", "twostep-full", "ellipsoid"
/// The method named `s` ("twostep", "twostep-full", "ellipsoid"); nullopt for any other name. Throws nothing.
std::optional<Method> parse_method(std::string_view s) noexcept;

/// Statistics of r_k = |h_k| - F (before) or |A^-1 (h_k - b)| - F (after).
struct NormError {
  /// Mean of r_k (input units).
  double mean = 0.0;
  /// Root mean square of r_k (input units).
  double rms = 0.0;
  double max = 0.0;  ///< max |r_k|
};

/// How well the points cover the sphere, about `centre` (the centre of an
/// algebraic sphere fit |h|^2 = 2 c.h + k; the centroid of the points when
/// that fit is singular, e.g. for coplanar points).
struct Coverage {
  /// The centre the directions are taken about (input units).
  Vec3 centre{};
  /// True when `centre` is the sphere fit's centre, false when it is the centroid of the points.
  bool centre_from_sphere_fit = false;
  /// |mean of the unit directions u_k = (h_k - centre)/|h_k - centre||:
  /// 0 for the whole sphere, 0.5 for a hemisphere, 1 for one direction.
  double resultant = 1.0;
  /// Smallest eigenvalue of mean(u_k u_k^T): 1/3 for the whole sphere, 0 when
  /// the directions lie on one great circle (rotation about one axis only).
  double lambda_min = 0.0;
  /// sqrt of the eigenvalues of the covariance of the points (descending), in
  /// input units: how far the cloud extends in each principal direction.
  Vec3 spread{};
  std::size_t octants = 0;  ///< octants about the centre holding a direction (of 8)
};

// Coverage thresholds (see check_coverage).
inline constexpr double kMinLambdaFull = 0.05;      ///< directions at most a +-22 deg band
inline constexpr double kMaxResultantFull = 0.55;   ///< about a hemisphere (0.5) at least
inline constexpr double kMinSpreadFull = 0.1;       ///< smallest spread / F
inline constexpr double kMinSpreadBiasOnly = 0.05;  ///< smallest spread / F

/// How well the points `h` (input units) cover the sphere. Throws nothing for finite points.
Coverage sphere_coverage(std::span<const Vec3> h);

/// Throws CalibrationError (poor_coverage) "points do not cover the sphere:
/// rotate the sensor through all orientations (...)" when the points cannot determine the
/// method's parameters:
/// - ellipsoid and twostep-full (9 parameters): the points are not coplanar
///   (the sphere fit exists), smallest spread >= 0.1 F (not a small cluster:
///   a hemisphere gives 0.29 F, the whole sphere 0.58 F), lambda_min >= 0.05
///   (not one great circle or a band narrower than about +-22 deg) and
///   resultant <= 0.55 (a hemisphere, 0.5, passes; a cap of half-angle
///   below 84 deg fails);
/// - twostep (bias only, the field norm known): the points leave one plane,
///   smallest spread >= 0.05 F (a cap of half-angle 60 deg gives 0.14 F).
///   Coplanar points are refused: on one circle the bias has two solutions
///   (one, without first-order information, on a great circle). A partial
///   sphere is accepted and shows in bias_sigma and in a note.
void check_coverage(const Coverage& c, Method m, double field_norm);

/// The outlier rule (`--reject D`), two passes.
/// 1. Gross outliers, robustly: with med the median of |h_k| and the robust
///    sigma rs = max(1.4826 MAD, kGrossSigmaFloor med), MAD the median of
///    ||h_k| - med|, reject k when ||h_k| - med| > kGrossSigmas rs. A corrupt
///    value (1e50) cannot move the median or the MAD, so it cannot hide itself
///    or the other outliers.
/// 2. Magneto's rule, one pass, on the points pass 1 kept: with m and sd the
///    mean and (population) standard deviation of their |h_k|, reject k when
///    ||h_k| - m| / sd > sigma_level. Without gross outliers this is Magneto's
///    rule alone and reproduces Magneto 1.4's choice on jremington's ICM-20948
///    run (docs/formulas/magnetometer.md §3.3).
struct OutlierRejection {
  /// Median of |h_k| over all points (input units).
  double median_norm = 0.0;
  /// The robust sigma of pass 1: max(1.4826 MAD, kGrossSigmaFloor x median_norm) (input units).
  double robust_sigma = 0.0;
  /// Mean of |h_k| over the points pass 1 kept (input units).
  double mean_norm = 0.0;
  /// Population standard deviation of |h_k| over the points pass 1 kept (input units).
  double std_norm = 0.0;
  std::vector<std::size_t> kept;      ///< indices into the input, ascending
  std::vector<std::size_t> rejected;  ///< indices into the input, ascending (both passes)
  std::vector<std::size_t> gross;     ///< the indices pass 1 rejected, ascending (a subset of rejected)
};
/// Pass 1 of the outlier rule rejects |h_k| further than this many robust sigmas from the median |h|.
inline constexpr double kGrossSigmas = 10.0;
/// The robust sigma of pass 1 is at least this fraction of the median |h|
/// (when more than half of the norms are equal, MAD is 0).
inline constexpr double kGrossSigmaFloor = 0.01;
/// Throws CalibrationError (bad_option) when sigma_level is not positive.
OutlierRejection reject_outliers(std::span<const Vec3> h, double sigma_level);

Vec3 apply(const Vec3& h, const Vec3& bias, const Mat3& correction);  ///< A^-1 (h - b)
NormError norm_error(std::span<const Vec3> h, const Vec3& bias, const Mat3& correction,
                     std::span<const double> field_norm);  ///< one F, or one per point
/// Statistics of |h_k| - F for the raw points (no correction), F per point or one for all (input units).
NormError raw_norm_error(std::span<const Vec3> h, std::span<const double> field_norm);

/// What a magnetometer calibration is asked to do (calibrate).
struct Options {
  /// The method run.
  Method method = Method::ellipsoid;
  /// Field norm F: |h_cal| after calibration. 0: the mean |h| of the points
  /// the outlier rule kept (of all points when reject_sigma is 0; Magneto
  /// takes the mean over all points, outliers included). Must be positive
  /// when given.
  double field_norm = 0.0;
  /// TWOSTEP only: the reference field norm |H_k| of each point (e.g. IGRF
  /// along an orbit), one per input point; overrides field_norm.
  std::vector<double> field_norms;
  /// Per-axis measurement noise s (input units, 1 sigma). 0: estimated from
  /// the residuals (chi2 then equals dof by construction; no p-value).
  double noise = 0.0;
  double reject_sigma = 0.0;  ///< Magneto's outlier rule at this level; 0: off
  /// Refuse points that do not cover the sphere well enough for the method (check_coverage).
  bool check_coverage = true;
  /// TWOSTEP second step.
  double eta_tol = 1e-12;
  /// TWOSTEP second step: the most Gauss-Newton iterations.
  std::size_t max_iterations = 100;
  bool mean_correction = true;  ///< mu_k = -3 s^2 (false: mu_k = 0)
};

/// A magnetometer calibration: h_cal = A^-1 (h - b), with its uncertainty and residuals.
struct Result {
  /// The method that ran.
  Method method = Method::ellipsoid;
  Vec3 bias{};                  ///< hard-iron offset b (input units)
  Vec3 bias_sigma{};            ///< 1 sigma
  Mat3 soft_iron = kIdentity3;  ///< correction A^-1 (symmetric)
  Mat3 soft_iron_sigma{};       ///< 1 sigma of each entry (0 for bias-only)
  /// Covariance of (b1, b2, b3) for bias-only, of (b1, b2, b3, W11, W22, W33,
  /// W12, W13, W23) with W = A^-1 otherwise; names in covariance_names.
  Matrix covariance;
  /// The names of covariance's rows and columns: "b1", "b2", "b3" and, unless
  /// bias-only, the W entries.
  std::vector<std::string> covariance_names;
  double field_norm = 0.0;          ///< F (the mean of |H_k| when given per point)
  bool field_norm_default = false;  ///< F was the mean raw |h| of the points used
  /// True when a field norm was given per point (Options::field_norms).
  bool field_norm_per_point = false;
  Vec3 semi_axes{};         ///< of the raw-data ellipsoid, descending (F for bias-only)
  double axis_ratio = 1.0;  ///< longest / shortest semi-axis
  /// Norm errors |h| - F before calibration (raw points) and after it (calibrated points), input units.
  ///@{
  NormError before, after;
  ///@}
  /// Chi-squared of the residuals with the noise s (dimensionless).
  double chi2 = 0.0;
  /// Degrees of freedom of chi2: points used minus parameters.
  std::size_t dof = 0;
  std::optional<double> p_value;  ///< P(chi2_dof >= chi2); only when noise was given
  double noise = 0.0;             ///< s used (input units)
  /// True when s was estimated from the residuals (Options::noise 0).
  bool noise_estimated = false;
  std::size_t iterations = 0;  ///< TWOSTEP second-step iterations
  /// False when TWOSTEP's second step stopped at max_iterations.
  bool converged = true;
  double eta = 0.0;  ///< last TWOSTEP step size (Fisher-weighted)
  /// Points the fit used (after outlier rejection).
  std::size_t points_used = 0;
  /// Points the outlier rule rejected.
  std::size_t points_rejected = 0;
  std::vector<std::size_t> rejected;  ///< input indices
  /// Input indices of the points rejected as gross outliers (pass 1 of reject_outliers; a subset of rejected).
  std::vector<std::size_t> rejected_gross;
  /// The outlier rule's level (sigma; 0: off).
  double reject_sigma = 0.0;
  /// How well the points used cover the sphere.
  Coverage coverage;
  std::vector<std::string> notes;  ///< what the reader must know (defaults taken, degeneracies)
};

/// Runs the chosen method. Throws CalibrationError (cubecal/error.hpp), with a
/// message fit for the user:
///   too_few_points  fewer than kMinPoints points (before or after rejection);
///   bad_data        non-finite values;
///   field_norm      a negative or non-finite field norm, per-point norms of
///                   the wrong count or not positive, all points zero (no
///                   default norm);
///   bad_option      a negative noise or rejection level, per-point norms
///                   with the ellipsoid method;
///   poor_coverage   insufficient sphere coverage (check_coverage);
///   degenerate      a degenerate fit (ellipsoid_fit.hpp, twostep.hpp).
Result calibrate(std::span<const Vec3> h, const Options& opt);

}  // namespace cubecal::mag
