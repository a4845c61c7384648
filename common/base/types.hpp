// Vocabulary types shared by every stage. 2D plane strain throughout (docs/method.md §2):
// x horizontal (runout towards +x), y up, SI units.
#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/LU>  // determinant() and inverse() of the small fixed-size matrices

namespace slide {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

/// Stress [σxx, σyy, σzz, σxy] in Pa, tension positive, or strain
/// [εxx, εyy, εzz, γxy] with γxy = 2 εxy (engineering shear). σzz is the
/// out-of-plane plane-strain stress; εzz = 0 in plane strain.
using Vec4 = Eigen::Vector4d;

using Index = std::int64_t;

/// Standard gravity used by every case (docs/method.md §2).
inline constexpr double gravity_acceleration = 9.81;
inline Vec2 gravity_vector() {
  return {0.0, -gravity_acceleration};
}

}  // namespace slide
