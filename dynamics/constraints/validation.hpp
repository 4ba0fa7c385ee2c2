/// \file
/// Checks of joint input for the constraint library (the bad-input rules of
/// the joints issue). Each throws lieflow::InvalidInput whose field() is the
/// name given by the caller (e.g. "joints[2].axis_main") and whose reason()
/// says what is wrong; on success it returns the cleaned-up value.
///
/// Rules:
///  * a vector (anchor, axis) must be finite;
///  * an axis must be non-zero and unit to within kAxisUnitTolerance
///    (|‖a‖ − 1| ≤ 1e-6): it is then normalized; farther from unit it is
///    rejected, not silently rescaled;
///  * the two axes of a universal joint (and the r, s axes of a gear node)
///    must be orthogonal to within kAxisOrthogonalityTolerance (|a₁·a₂| ≤ 1e-6
///    for unit axes); the second is then made exactly orthogonal
///    (Gram–Schmidt) so that the constraints hold exactly at assembly;
///  * a gear ratio must be finite and non-zero.
#pragma once

#include <cmath>
#include <sstream>
#include <string>

#include "liegroup/invalid_input.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace constraints {

/// |‖a‖ − 1| up to which an axis is normalized instead of rejected (the same
/// tolerance as the checked factories of liegroup/, SO3::kCheckedTolerance).
constexpr double kAxisUnitTolerance = 1e-6;

/// |a₁·a₂| up to which two unit axes count as orthogonal.
constexpr double kAxisOrthogonalityTolerance = 1e-6;

/// ‖R_ref a_b − a_a‖ up to which the two axes of a revolute joint count as
/// aligned in the reference configuration.
constexpr double kAxisAlignmentTolerance = 1e-6;

/// "prefix.name", or "name" when the prefix is empty.
inline std::string fieldName(const std::string& prefix, const std::string& name) {
  return prefix.empty() ? name : prefix + "." + name;
}

/// Throws unless every component of x is finite.
template <typename T>
void checkFinite(const Vector3<T>& x, const std::string& field) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(scalarValue(x[i])))
      throw InvalidInput(field, "vector has a non-finite component");
}

/// The unit axis a/‖a‖. Throws if a is non-finite, zero, or not within
/// kAxisUnitTolerance of unit length.
template <typename T>
Vector3<T> checkedUnitAxis(const Vector3<T>& axis, const std::string& field) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(scalarValue(axis[i])))
      throw InvalidInput(field, "axis has a non-finite component");
  const double norm = std::sqrt(scalarValue(axis.squaredNorm()));
  if (norm == 0.0) throw InvalidInput(field, "axis is zero (a unit vector is required)");
  if (!(std::abs(norm - 1.0) <= kAxisUnitTolerance)) {
    std::ostringstream reason;
    reason << "axis norm " << norm << " is not within " << kAxisUnitTolerance
           << " of 1 (a unit vector is required)";
    throw InvalidInput(field, reason.str());
  }
  return axis / Eigen::numext::sqrt(axis.squaredNorm());
}

/// `second` made exactly orthogonal to `first` (both unit): second − (first·second) first,
/// renormalized. Throws (naming `field`, the second axis) if |first·second| >
/// kAxisOrthogonalityTolerance.
template <typename T>
Vector3<T> checkedOrthogonalAxis(const Vector3<T>& first, const Vector3<T>& second,
                                 const std::string& field, const std::string& first_name) {
  const T c = first.dot(second);
  if (!(std::abs(scalarValue(c)) <= kAxisOrthogonalityTolerance)) {
    std::ostringstream reason;
    reason << "axis is not orthogonal to " << first_name << " (cosine of the angle between them "
           << scalarValue(c) << ", tolerance " << kAxisOrthogonalityTolerance << ")";
    throw InvalidInput(field, reason.str());
  }
  const Vector3<T> w = second - c * first;
  return w / Eigen::numext::sqrt(w.squaredNorm());
}

/// The gear ratio α, which must be finite and non-zero (α = 0 would decouple
/// the gears and leave a row that is not a gear relation).
template <typename T>
T checkedGearRatio(const T& ratio, const std::string& field) {
  const double r = scalarValue(ratio);
  if (!std::isfinite(r)) throw InvalidInput(field, "gear ratio is not finite");
  if (r == 0.0) throw InvalidInput(field, "gear ratio is 0 (a non-zero ratio α is required)");
  return ratio;
}

}  // namespace constraints
}  // namespace lieflow
