/// @file
/// Li & Griffiths (2004) ellipsoid-specific least-squares fit with k = 4, as
/// in Magneto (docs/formulas/magnetometer.md §2), and its conversion to a hard-iron
/// offset b = -M^-1 n and a symmetric soft-iron correction
/// A^-1 = F / sqrt(n^T M^-1 n - d) * sqrtm(M), so that h_cal = A^-1 (h - b)
/// has |h_cal| = F on the fitted ellipsoid.
///
/// Quadric: a x^2 + b y^2 + c z^2 + 2f yz + 2g xz + 2h xy + 2p x + 2q y + 2r z
/// + d = 0, constraint 4J - I^2 = 1 (I = a+b+c, J = ab+bc+ca-f^2-g^2-h^2).
/// The fit is similarity invariant; it runs on points centred on their mean
/// and scaled to unit RMS radius for conditioning.
#pragma once
#include <array>
#include <span>

#include "cubecal/calib/mag_calibration.hpp"

namespace cubecal::mag {

/// An algebraic ellipsoid fit of magnetometer points (Li & Griffiths' constraint) and the calibration it gives.
struct EllipsoidFit {
  /// a b c f g h p q r d in the units of the input, scaled so that
  /// 4J - I^2 = 1 and a > 0.
  std::array<double, 10> coeff{};
  Mat3 M{};  ///< [[a,h,g],[h,b,f],[g,f,c]]
  Vec3 n{};  ///< (p, q, r)
  /// The constant d of the quadric, input units squared.
  double d = 0.0;
  Vec3 centre{};      ///< hard-iron offset b = -M^-1 n
  Mat3 correction{};  ///< A^-1 for the field norm given
  /// The field norm F the correction maps the ellipsoid to (input units).
  double field_norm = 0.0;
  Vec3 semi_axes{};         ///< descending, input units
  double axis_ratio = 1.0;  ///< longest / shortest
  /// Eigenvalues of M (ascending), after the normalisation above.
  Vec3 m_eigenvalues{};
  double eigenvalue = 0.0;  ///< the generalised eigenvalue chosen (algebraic residual)
};

/// At least 10 points that are not coplanar. Throws CalibrationError
/// (cubecal/error.hpp): too_few_points (fewer than 10 points); field_norm
/// (field_norm not positive); degenerate ("degenerate ellipsoid fit: ...":
/// all points equal, coplanar points, no eigenvector satisfying the
/// constraint, M not positive definite, or a quadric without real points,
/// n^T M^-1 n - d <= 0).
EllipsoidFit fit_ellipsoid(std::span<const Vec3> h, double field_norm);

/// The conversion alone, from quadric coefficients a b c f g h p q r d (any
/// scale and sign). Throws CalibrationError: field_norm, degenerate.
EllipsoidFit ellipsoid_from_quadric(const std::array<double, 10>& coeff, double field_norm);

}  // namespace cubecal::mag
