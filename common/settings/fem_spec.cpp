#include "common/settings/fem_spec.hpp"

#include <numbers>

namespace slide {

RayleighCoefficients rayleigh_coefficients(const DampingRatio& ratio) {
  // ξ(ω) = α_M/(2ω) + β_K ω/2 = ξ at ω1 and ω2: two linear equations in α_M, β_K.
  const double omega1 = 2.0 * std::numbers::pi * ratio.frequencies[0];
  const double omega2 = 2.0 * std::numbers::pi * ratio.frequencies[1];
  return {.mass = 2.0 * ratio.ratio * omega1 * omega2 / (omega1 + omega2),
          .stiffness = 2.0 * ratio.ratio / (omega1 + omega2)};
}

}  // namespace slide
